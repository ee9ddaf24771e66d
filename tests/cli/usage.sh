# usage.sh - command-line usage of `authalic`: help, version, and every kind of bad usage.
# sh usage.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
IN=$(stage "$SRC/tests/cli/unreferenced.obj")
OUT=$T/o/out.obj

case $1 in
help)
  run --help
  expect_status 0
  expect_out '^usage: authalic sphere IN OUT'
  expect_out '--version'
  [ ! -s "$T/log/stderr" ] || fail "--help printed on stderr"
  ;;
sphere_help)
  run sphere --help
  expect_status 0
  # Every option is listed, and the numeric ones with their defaults.
  for opt in --report --steps --tol --no-balance --quiet --init-only; do expect_out "$opt"; done
  expect_out 'steps K .*default [0-9]+'
  expect_out 'tol T .*default [0-9.e-]+'
  ;;
version)
  run --version
  expect_status 0
  grep -Eq '^authalic [0-9]+\.[0-9]+\.[0-9]+$' "$T/log/stdout" || fail "--version printed '$(cat "$T/log/stdout")'"
  ;;
no_command)
  run
  expect_rejected 'no command'
  ;;
unknown_command)
  run spher "$IN" "$OUT"
  expect_rejected "unknown command 'spher'"
  ;;
unknown_flag)
  run sphere "$IN" "$OUT" --fast
  expect_rejected "unknown option '--fast'"
  ;;
unknown_flag_help)
  # Every command's usage errors point at its own help (circles and atlas came after the first seven).
  for cmd in sphere disk annulus square torus circles atlas texture sample; do
    run $cmd "$IN" "$OUT" --fast
    expect_rejected "unknown option '--fast' \\(see \`authalic $cmd --help\`\\)"
  done
  ;;
prefix_flag)
  # Flags match exactly: an abbreviation or an extension of a real flag is unknown.
  run sphere "$IN" "$OUT" --rep "$T/o/r.json"
  expect_rejected "unknown option '--rep'"
  run sphere "$IN" "$OUT" --quietly
  expect_rejected "unknown option '--quietly'"
  run sphere "$IN" "$OUT" --steps=5
  expect_rejected "unknown option '--steps=5'"
  ;;
missing_args)
  run sphere
  expect_rejected 'missing input and output'
  run sphere "$IN"
  expect_rejected 'missing output'
  ;;
missing_value)
  run sphere "$IN" "$OUT" --steps
  expect_rejected "'--steps' needs a value"
  run sphere "$IN" "$OUT" --report
  expect_rejected "'--report' needs a value"
  ;;
bad_number)
  for v in abc 5x '' 0 -3 513 99999999999999999999 1.5; do
    run sphere "$IN" "$OUT" --steps "$v"
    expect_rejected "--steps '$v'"
  done
  for v in abc 1e-3x '' -1 nan inf 1e999; do
    run sphere "$IN" "$OUT" --tol "$v"
    expect_rejected "--tol '$v'"
  done
  # A radius whose float32 coordinates would overflow or vanish (1e-50 wrote zeros) is refused, and the
  # message says the range (1e39 was "expected a positive number").
  for v in abc '' 0 -1 1e39 1e-50 nan inf; do
    run sphere "$IN" "$OUT" --radius "$v"
    expect_rejected "--radius '$v': expected a number from 1e-30 to 1e30"
  done
  for v in abc '' -0.1 1.5 nan; do
    run sphere "$IN" "$OUT" --restore-shapes "$v"
    expect_rejected "--restore-shapes '$v'"
  done
  for v in abc '' 1 0.5 16.5 nan inf autox AUTO; do
    run sphere "$IN" "$OUT" --refine-mesh "$T/o/surf.obj" --refine-budget "$v"
    expect_rejected "--refine-budget '$v'"
  done
  for v in abc '' Multilevel 1 conformal2; do
    run sphere "$IN" "$OUT" --start "$v"
    expect_rejected "--start '$v': expected conformal or multilevel"
  done
  ;;
duplicate_flag)
  run sphere "$IN" "$OUT" --steps 5 --steps 6
  expect_rejected "'--steps' given twice"
  ;;
bad_combination)
  run sphere "$IN" "$OUT" --init-only --steps 5
  expect_rejected 'init-only'
  run sphere "$IN" "$OUT" --init-only --refine-mesh "$T/o/surf.obj"
  expect_rejected 'init-only'
  [ ! -e "$T/o/surf.obj" ] || fail "a refused run wrote the refined surface"
  # A refined mesh's new vertices and faces would have no density.
  awk '/^v /{n++} END{for(i=0;i<n;i++) print 1}' "$IN" >"$T/d.txt"
  run sphere "$IN" "$OUT" --density "$T/d.txt" --refine-mesh "$T/o/surf.obj"
  expect_rejected '--refine-mesh does not take --density'
  [ ! -e "$T/o/surf.obj" ] || fail "a refused run wrote the refined surface"
  # A map of spherical areas has no chord floor to refine.
  run sphere "$IN" "$OUT" --spherical-areas --refine-mesh "$T/o/surf.obj"
  expect_rejected '--refine-mesh does not take --spherical-areas'
  [ ! -e "$T/o/surf.obj" ] || fail "a refused run wrote the refined surface"
  run sphere "$IN" "$OUT" --refine-budget 3
  expect_rejected '--refine-budget applies to --refine-mesh'
  ;;
refine_outputs)
  # --refine-mesh SURF is an output like OUT, checked before the run: it overwrote the input (status 0),
  # was lost under OUT, or was refused only after the whole map was made.
  cp "$IN" "$T/in.obj"
  sum=$(cksum <"$T/in.obj")
  run sphere "$T/in.obj" "$OUT" --refine-mesh "$T/in.obj"
  expect_rejected "--refine-mesh '$T/in.obj': it is also another input or output file"
  [ "$(cksum <"$T/in.obj")" = "$sum" ] || fail "--refine-mesh IN changed the input"
  run sphere "$IN" "$OUT" --refine-mesh "$OUT"
  expect_rejected 'is also another input or output file'
  # The same file under another name, before either exists.
  run sphere "$IN" "$OUT" --refine-mesh "$T/o/./out.obj"
  expect_rejected 'is also another input or output file'
  mkdir "$T/p.obj.parents.txt"
  run sphere "$IN" "$OUT" --refine-mesh "$T/p.obj"
  expect_rejected "parents file '$T/p.obj.parents.txt' is a directory"
  run sphere "$IN" "$OUT" --refine-mesh "$T/o/r.json" --report "$T/o/r.json"
  expect_rejected 'is also another input or output file'
  # SURF's format follows its extension, else the input's, as OUT's: only STL cannot be written.
  run sphere "$T/in.obj" "$OUT" --refine-mesh "$T/o/in.stl"
  expect_rejected "cannot write that extension"
  # The parents file beside SURF counts too.
  cp "$IN" "$T/s.obj.parents.txt"
  run sphere "$T/s.obj.parents.txt" "$OUT" --refine-mesh "$T/s.obj"
  expect_rejected "$T/s.obj.parents.txt is also another input or output file"
  run sphere "$IN" "$OUT" --refine-mesh "$T/o/surf.STL"
  expect_rejected "--refine-mesh '$T/o/surf.STL': cannot write that extension"
  run sphere "$IN" "$OUT" --refine-mesh "$T/o/nodir/surf.obj"
  expect_rejected "directory '$T/o/nodir' does not exist"
  ;;
extra_arg)
  run sphere "$IN" "$OUT" "$T/o/third.obj"
  expect_rejected "extra argument '$T/o/third.obj'"
  ;;
special_outputs)
  # Outputs are written whole and renamed into place: a FIFO or a device named as an output is refused
  # (a rename would have put a plain file there: as root, /dev/null itself), before any work.
  mkfifo "$T/fifo" || skip "mkfifo failed"
  run sphere "$IN" "$T/fifo"
  expect_status 2
  expect_one_error_line
  expect_err "output '.*fifo' is not a regular file"
  [ -p "$T/fifo" ] || fail "the FIFO was replaced"
  run sphere "$IN" "$OUT" --report /dev/null
  expect_rejected "report '/dev/null' is not a regular file"
  [ -c /dev/null ] || fail "/dev/null is no longer a device"
  # A symbolic link stays; the file it names gets the output, also one that does not exist yet.
  echo old >"$T/o/target.obj"
  ln -s target.obj "$T/o/link.obj"
  ln -s sub/../report.json "$T/o/rlink.json"
  mkdir "$T/o/sub"
  run sphere "$IN" "$T/o/link.obj" --report "$T/o/rlink.json"
  expect_status 0
  [ -L "$T/o/link.obj" ] && [ -L "$T/o/rlink.json" ] || fail "an output's symbolic link was replaced"
  [ "$(obj_nv "$T/o/target.obj")" -gt 0 ] || fail "the link's file did not get the map"
  grep -q '"metrics"' "$T/o/report.json" || fail "the dangling link's file did not get the report"
  # A loop of links is refused, not replaced (the writer stopped after 40 links and renamed over one).
  ln -s loop2.obj "$T/loop1.obj"
  ln -s loop1.obj "$T/loop2.obj"
  run sphere "$IN" "$T/loop1.obj"
  expect_status 2
  expect_one_error_line
  expect_err "too many levels of symbolic links"
  [ -L "$T/loop1.obj" ] && [ -L "$T/loop2.obj" ] || fail "a link of the loop was replaced"
  # An input named as an output: --density as OUT or as the report.
  rm -rf "$T/o"/*
  awk '/^v /{print 1}' "$IN" >"$T/d.txt"
  cp "$T/d.txt" "$T/d0.txt"
  run sphere "$IN" "$OUT" --density "$T/d.txt" --report "$T/d.txt"
  expect_rejected "--density '.*d.txt' is also an output file"
  run sphere "$IN" "$T/d.txt" --format obj --density "$T/d.txt"
  expect_rejected "--density '.*d.txt' is also an output file"
  cmp -s "$T/d.txt" "$T/d0.txt" || fail "the density file was changed"
  ;;
in_eq_out)
  # The same file, by the same name and by another name of it; the input is not touched.
  cp "$IN" "$T/in.obj"
  run sphere "$T/in.obj" "$T/in.obj"
  expect_status 2
  expect_one_error_line
  expect_err 'is the input'
  run sphere "$T/in.obj" "$T/./in.obj"
  expect_status 2
  expect_err 'is the input'
  cmp -s "$SRC/tests/cli/unreferenced.obj" "$T/in.obj" || fail "the input was modified"
  run sphere "$IN" "$OUT" --report "$IN"
  expect_rejected 'report .* is the input'
  run sphere "$IN" "$OUT" --report "$OUT"
  expect_rejected 'report .* is the output'
  ;;
bad_extension)
  # An OUT without a known extension takes the input's format (issue 19): refused only where that
  # format cannot be written (STL), or where the extension names one (.stl) or --format is not one.
  run sphere "$IN" "$T/o/out.stl"
  expect_rejected "cannot write '\.stl'"
  run sphere "$IN" "$T/o/out" --format stl
  expect_rejected "--format 'stl': expected obj, off, ply, freesurfer or gifti"
  cat >"$T/in/tet.stl" <<'EOF2'
solid tet
facet normal 0 0 -1
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 -1 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal -1 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
facet normal 1 1 1
outer loop
vertex 1 0 0
vertex 0 1 0
vertex 0 0 1
endloop
endfacet
endsolid tet
EOF2
  for o in out out.xyz; do
    run sphere "$T/in/tet.stl" "$T/o/$o"
    expect_rejected "output '.*$o' has no extension of a format that can be written and the input is stl"
  done
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

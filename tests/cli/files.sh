# files.sh - file-system failures: missing input, a directory as input, an output in a missing
# directory, an output that is a directory, and an existing output left untouched by a failed run.
# sh files.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
GOOD=$(stage "$SRC/tests/cli/unreferenced.obj")

case $1 in
missing_input)
  run sphere "$T/no-such-file.obj" "$T/o/out.obj"
  expect_rejected 'no-such-file\.obj.*(no such file|cannot open)'
  ;;
dir_input)
  mkdir "$T/dir.obj"
  run sphere "$T/dir.obj" "$T/o/out.obj"
  expect_rejected 'directory'
  ;;
missing_outdir)
  run sphere "$GOOD" "$T/o/missing/out.obj"
  expect_rejected "directory '$T/o/missing' does not exist"
  [ ! -e "$T/o/missing" ] || fail "the missing directory was created"
  run sphere "$GOOD" "$T/o/out.obj" --report "$T/o/missing/r.json"
  expect_rejected "directory '$T/o/missing' does not exist"
  ;;
out_is_dir)
  mkdir "$T/o/d.obj"
  run sphere "$GOOD" "$T/o/d.obj"
  expect_status 2
  expect_one_error_line
  expect_err 'is a directory'
  [ -d "$T/o/d.obj" ] && [ -z "$(ls -A "$T/o/d.obj")" ] || fail "the directory was changed"
  ;;
keep_existing)
  # The run fails late (in validation, after the output name was accepted).
  printf 'the previous result\n' >"$T/o/out.obj"
  cp "$T/o/out.obj" "$T/keep"
  run sphere "$(stage "$SRC/tests/cli/bad/torus.obj")" "$T/o/out.obj" --report "$T/o/r.json"
  expect_status 2
  expect_one_error_line
  cmp -s "$T/o/out.obj" "$T/keep" || fail "the existing output was changed by a failed run"
  [ "$(ls -A "$T/o")" = "out.obj" ] || fail "files left beside the output: $(ls -A "$T/o")"
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

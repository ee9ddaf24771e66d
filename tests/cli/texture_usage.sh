# texture_usage.sh - command-line usage of `authalic texture` and `authalic sample`: help, and
# every kind of bad usage, rejected before any work with one error line and no file left.
# sh texture_usage.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
IN=$(stage "$SRC/tests/cli/unreferenced.obj")
OUT=$T/o/out.obj

case $1 in
texture_help)
  run texture --help
  expect_status 0
  expect_out '^usage: authalic texture IN \[--map SPHERE_MAP\] OUT.obj'
  for opt in --map --projection --lonlat --bake --image --size --preview --render --quiet; do expect_out "$opt"; done
  expect_out 'default 1024x512'
  [ ! -s "$T/log/stderr" ] || fail "--help printed on stderr"
  ;;
sample_help)
  run sample --help
  expect_status 0
  expect_out '^usage: authalic sample IN --grid WxH OUT'
  for opt in --grid --map --normals --attr --report --preview --quiet; do expect_out "$opt"; done
  expect_out 'numpy.load'
  ;;
missing_args)
  run texture
  expect_rejected 'missing input and output'
  run texture "$IN"
  expect_rejected 'missing output'
  run sample "$IN" "$T/o/s.npy"
  expect_rejected 'missing --grid'
  ;;
bad_values)
  run texture "$IN" "$OUT" --projection mercator
  expect_rejected "--projection 'mercator': expected cea, laea or oct"
  run texture "$IN" "$OUT" --bake normal --image "$T/o/t.png" --size 1024
  expect_rejected "--size '1024': expected WxH"
  run texture "$IN" "$OUT" --bake normal --image "$T/o/t.png" --size 0x10
  expect_rejected "--size '0x10'"
  run sample "$IN" --grid 64x32x2 "$T/o/s.npy"
  expect_rejected "--grid '64x32x2'"
  run texture "$IN" "$OUT" --projection laea --bake normal --image "$T/o/t.png" --size 101x50
  expect_rejected 'laea needs an even width'
  run texture "$IN" "$OUT" --area-tol auto --area-target -0.1
  expect_rejected "--area-target '-0.1': expected a number >= 0 or auto"
  ;;
bad_combination)
  run texture "$IN" "$OUT" --bake normal
  expect_rejected '--bake needs --image'
  run texture "$IN" "$OUT" --image "$T/o/t.png"
  expect_rejected '--image needs --bake'
  run texture "$IN" "$OUT" --render "$T/o/r.png"
  expect_rejected '--render needs --bake'
  run texture "$IN" "$OUT" --size 64x32
  expect_rejected '--size applies to --bake only'
  run texture "$IN" "$OUT" --area-target 0.01
  expect_rejected '--area-target: needs --area-tol'
  ;;
bad_outputs)
  run texture "$IN" "$T/o/out.ply"
  expect_rejected 'written as .obj'
  run texture "$IN" "$OUT" --bake normal --image "$T/o/t.jpg"
  expect_rejected "image '.*t.jpg': use .png"
  run sample "$IN" --grid 8x4 "$T/o/s.txt"
  expect_rejected 'use .npy or .csv'
  run texture "$IN" "$IN"
  expect_rejected "output '.*' is an input file"
  cp "$IN" "$T/in/map.obj"
  run texture "$IN" --map "$T/in/map.obj" "$T/in/map.obj"
  expect_rejected "output '.*' is an input file"
  run texture "$IN" "$OUT" --bake normal --image "$T/o/t.png" --preview "$T/o/t.png"
  expect_rejected "is also the --image"
  run texture "$IN" "$OUT" --lonlat "$T/o/missing/ll.txt"
  expect_rejected "directory '$T/o/missing' does not exist"
  ;;
unknown_flag)
  run texture "$IN" "$OUT" --grid 8x4
  expect_rejected "unknown option '--grid'"
  run sample "$IN" --grid 8x4 "$T/o/s.npy" --bake normal
  expect_rejected "unknown option '--bake'"
  run texture "$IN" "$OUT" --proj cea
  expect_rejected "unknown option '--proj'"
  run texture "$IN" "$OUT" --projection cea --projection laea
  expect_rejected "given twice"
  run texture "$IN" "$OUT" extra.obj
  expect_rejected "unexpected extra argument 'extra.obj'"
  ;;
*)
  fail "unknown case $1"
  ;;
esac
exit 0

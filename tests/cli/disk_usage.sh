# disk_usage.sh - argument handling of `authalic disk | annulus | square`: help texts, unknown and
# foreign flags, bad values, bad combinations. Rejections exit 2 with one error line and no file.
# sh disk_usage.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
IN=$SRC/data/disk_bump.obj
[ -f "$IN" ] || skip "$IN is missing (run au_mkdata to generate data/)"
IN=$(stage "$IN")
OUT=$T/o/map.obj
case $1 in
disk_help | annulus_help | square_help)
  cmd=${1%_help}
  run "$cmd" --help
  expect_status 0
  expect_out "^usage: authalic $cmd IN OUT"
  expect_out "--boundary MODE"
  case $cmd in
  annulus) expect_out "--inner-radius R" && expect_out "--outer-loop" ;;
  square) expect_out "--corners I,J,K,L" ;;
  esac
  [ ! -s "$T/log/stderr" ] || fail "--help printed on stderr"
  ;;
unknown_flag)
  run disk "$IN" "$OUT" --frobnicate
  expect_rejected "unknown option '--frobnicate'"
  ;;
foreign_flag)
  # Each command takes only its own domain's options.
  run disk "$IN" "$OUT" --corners 1,2,3,4
  expect_rejected "unknown option '--corners'"
  run square "$IN" "$OUT" --inner-radius 0.5
  expect_rejected "unknown option '--inner-radius'"
  ;;
bad_boundary)
  run disk "$IN" "$OUT" --boundary loose
  expect_rejected "--boundary 'loose': expected slide or fixed"
  ;;
bad_inner_radius)
  for r in 0 1 1.5 -0.2 x; do
    run annulus "$IN" "$OUT" --inner-radius "$r"
    expect_rejected "--inner-radius '$r'"
  done
  ;;
bad_corners)
  for c in 1,2,3 1,2,3,4,5 a,b,c,d 1,,2,3 -1,2,3,4; do
    run square "$IN" "$OUT" --corners "$c"
    expect_rejected "--corners"
  done
  ;;
bad_outer_loop)
  run annulus "$IN" "$OUT" --outer-loop inner
  expect_rejected "--outer-loop 'inner': expected longer, shorter or a vertex index"
  ;;
init_only_combination)
  run disk "$IN" "$OUT" --init-only --boundary fixed
  expect_rejected "--init-only runs no advection"
  ;;
missing_args)
  run square "$IN"
  expect_rejected "missing output file"
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

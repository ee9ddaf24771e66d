# disk_bad_input.sh - meshes of the wrong kind for `authalic disk | annulus | square` are rejected
# with exit status 2, one error line naming the problem, and no output.
# sh disk_bad_input.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
for f in disk_bump annulus_bump ellipsoid; do
  [ -f "$SRC/data/$f.obj" ] || skip "$SRC/data/$f.obj is missing (run au_mkdata to generate data/)"
done
DISK=$(stage "$SRC/data/disk_bump.obj")
ANN=$(stage "$SRC/data/annulus_bump.obj")
CLOSED=$(stage "$SRC/data/ellipsoid.obj")
OUT=$T/o/map.obj
case $1 in
closed_to_disk)
  run disk "$CLOSED" "$OUT" --report "$T/o/r.json"
  expect_rejected "closed mesh given to the disk map: map it onto the sphere"
  expect_err "^authalic: error: $CLOSED:"
  ;;
closed_to_square)
  run square "$CLOSED" "$OUT"
  expect_rejected "closed mesh given to the square map: map it onto the sphere"
  ;;
disk_to_annulus)
  run annulus "$DISK" "$OUT"
  expect_rejected "mesh has 1 boundary loop \(144 vertices\); the annulus map needs 2"
  ;;
annulus_to_disk)
  run disk "$ANN" "$OUT"
  expect_rejected "mesh has 2 boundary loops \(sizes 96, 96\); the disk map needs 1"
  run square "$ANN" "$OUT"
  expect_rejected "the square map needs 1"
  ;;
corners_not_on_boundary)
  # Vertex 0 is the disk's centre.
  run square "$DISK" "$OUT" --corners 0,1700,1750,1790
  expect_rejected "--corners: corner vertex 0 is not on the boundary"
  run square "$DISK" "$OUT" --corners 1700,1750,1750,1790
  expect_rejected "corner vertex 1750 is given twice"
  run square "$DISK" "$OUT" --corners 1700,1750,1760,99999
  expect_rejected "corner vertex 99999 is not on the boundary"
  ;;
outer_loop_not_on_boundary)
  run annulus "$ANN" "$OUT" --outer-loop 500
  expect_rejected "--outer-loop: vertex 500 is on neither boundary loop"
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

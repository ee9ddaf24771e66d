#!/bin/sh
# chord_floor.sh BIN OUTDIR [MESH...] - each mesh mapped twice by `authalic sphere`: by default (the
# chord triangles' areas equalized) and with --spherical-areas (the spherical triangles'), and both maps
# measured in both measures by ../shared/tools/param-eval (per-face mean |r-1|, vertex mean |log r|,
# folds; its sph_ figures for the spherical triangles), with the report's chord floor faces and excess (the share of the area that the
# map's long edges hold above the faces' shares, docs/sphere.md#the-chord-floor) and CPU seconds.
# Default meshes: the generated limb family and the shared meshes a conformal start squeezes hardest.
# Run from the source root: sh bench/chord_floor.sh build/authalic /tmp/floor > table.md
BIN=$1; O=$2; shift 2; mkdir -p "$O"
S=../shared/meshes
if [ $# -eq 0 ]; then
  set -- data/limbs4.obj data/limbs8.obj data/coil.obj data/hammer.obj data/tpose.obj data/octopus.obj \
    $S/screwdriver.off $S/penguin_hr.obj $S/airplane.obj $S/cow.off
fi
echo "| mesh | F | areas | chord per-face | chord vertex | spherical per-face | spherical vertex | floor faces | floor excess | folds | CPU s |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for m in "$@"; do
  [ -f "$m" ] || { echo "| $(basename $m) | missing | | | | | | | | | |"; continue; }
  n=$(basename $m); n=${n%.*}
  for mode in chord spherical; do
    opt=; [ $mode = spherical ] && opt=--spherical-areas
    /usr/bin/time -f "%U %S" -o $O/$n.$mode.time $BIN sphere $m $O/$n.$mode.obj --report $O/$n.$mode.json \
      --quiet $opt 2>$O/$n.$mode.err
    ../shared/tools/param-eval $m $O/$n.$mode.obj --json > $O/$n.$mode.eval.json 2>/dev/null
    /usr/bin/python3 - "$n" "$mode" "$O/$n.$mode.json" "$O/$n.$mode.eval.json" "$O/$n.$mode.time" <<'PY'
import json, sys
n, mode, rp, ep, tp = sys.argv[1:6]
try:
    r = json.load(open(rp)); e = json.load(open(ep)); t = open(tp).read().split()[-2:]
except Exception:
    print("| %s | | %s | failed | | | | | | | |" % (n, mode)); sys.exit(0)
m = r["metrics"]
print("| %s | %d | %s | %.4f | %.4f | %.4f | %.4f | %d | %.4f | %d | %.2f |" % (
    n, r["F"], mode, e["r_mean_abs_dev"], e["vertex_logr_mean_abs"], e["sph_r_mean_abs_dev"],
    e["sph_vertex_logr_mean_abs"], m["chord_floor_faces"], m["chord_floor_excess"], e["folds"],
    float(t[0]) + float(t[1])))
PY
  done
done

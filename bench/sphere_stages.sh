#!/bin/sh
# sphere_stages.sh BIN OUTDIR [MESH...] - `authalic sphere` (default options) per mesh, with the rescue
# stages that ran and the time: per-face mean |r-1|, vertex mean |log r| and folds by
# ../shared/tools/param-eval; steps and stages from the report's convergence block (L lantern retry,
# T twisted retry, S staged retry, P vertex polish, G global polish; upper case: kept, lower case: ran
# and discarded; "t" the strong twisted start, made where every conformal start folds); wall and CPU
# seconds (user + system) of the whole command by /usr/bin/time. This machine is shared: wall seconds
# move with its load, CPU seconds much less. Default meshes: every closed genus-0 mesh of
# ../shared/meshes and the generated limb family of data/.
# Run from the source root: sh bench/sphere_stages.sh build/authalic /tmp/stages > table.md
BIN=$1; O=$2; shift 2; mkdir -p "$O"
S=../shared/meshes
if [ $# -eq 0 ]; then
  set -- $S/spot_lowres.obj $S/cow.off $S/spot.obj $S/hippocampus.obj $S/cheburashka.off $S/blub.obj \
    $S/hand_closed.obj $S/maxplanck.obj $S/bunny.obj $S/nefertiti.obj $S/ferret_brain_sim.off $S/armadillo.obj \
    $S/brain.obj $S/lion_statue.obj $S/penguin_hr.obj $S/screwdriver.off $S/airplane.obj \
    data/limbs4.obj data/limbs8.obj data/coil.obj data/tpose.obj data/hammer.obj
fi
echo "| mesh | F | steps | stages | per-face | vertex | folds | wall s | CPU s |"
echo "|---|---:|---:|---|---:|---:|---:|---:|---:|"
for m in "$@"; do
  [ -f "$m" ] || { echo "| $(basename $m) | missing | | | | | | | |"; continue; }
  n=$(basename $m); n=${n%.*}
  /usr/bin/time -f "%e %U %S" -o $O/$n.time $BIN sphere $m $O/$n.obj --report $O/$n.json --quiet 2>$O/$n.err
  ../shared/tools/param-eval $m $O/$n.obj --json > $O/$n.eval.json 2>/dev/null
  /usr/bin/python3 - "$n" "$O/$n.json" "$O/$n.eval.json" "$O/$n.time" <<'PY'
import json, sys
n, rp, ep, tp = sys.argv[1:5]
try:
    r = json.load(open(rp)); e = json.load(open(ep))
    t = open(tp).read().split()[-3:]
except Exception:
    print("| %s | | | failed | | | | | |" % n); sys.exit(0)
c = r.get("convergence", {})
stages = ""
for key, ch in (("lantern_retry", "L"), ("twisted_start", "T"), ("staged_retry", "S"), ("vertex_polish", "P"),
                ("global_polish", "G")):
    if key in c:
        k = c[key]
        stages += "t" if k.get("conformal_start_folded") else ch if k.get("kept") else ch.lower()
print("| %s | %d | %d | %s | %.4f | %.4f | %d | %.2f | %.2f |" % (
    n, r["F"], r["steps"], stages or "-", e["r_mean_abs_dev"], e["vertex_logr_mean_abs"], e["folds"],
    float(t[0]), float(t[1]) + float(t[2])))
PY
done

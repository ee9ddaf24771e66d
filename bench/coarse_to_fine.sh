#!/bin/sh
# coarse_to_fine.sh BIN OUTDIR [MESH...] - the sphere map from the conformal start and from the
# coarse-to-fine start (--start multilevel, docs/coarse-to-fine.md), one after the other for each mesh in
# the same run (this machine is shared: times move by +-20% and more from run to run, so compare within
# a row). Default meshes: every closed genus-0 mesh of ../shared/meshes (MANIFEST.md) and the limb family
# of data/. Per-face mean |r-1|, vertex mean |log r| and folds by ../shared/tools/param-eval; steps,
# the start that ran, the rescue stages that ran (L lantern retry, T twisted retry, S staged retry, P
# vertex polish, G global polish; lower case: ran and discarded) and the report's total seconds.
# Run from the source root: sh bench/coarse_to_fine.sh build/authalic /tmp/c2f > table.md
BIN=$1; O=$2; shift 2; mkdir -p "$O"
S=../shared/meshes
if [ $# -eq 0 ]; then
  set -- $S/spot_lowres.obj $S/cow.off $S/spot.obj $S/hippocampus.obj $S/cheburashka.off $S/blub.obj \
    $S/hand_closed.obj $S/maxplanck.obj $S/bunny.obj $S/nefertiti.obj $S/ferret_brain_sim.off $S/armadillo.obj \
    $S/brain.obj $S/lion_statue.obj $S/penguin_hr.obj $S/screwdriver.off $S/airplane.obj \
    data/limbs4.obj data/limbs8.obj data/tpose.obj data/coil.obj data/hammer.obj data/octopus.obj
fi
echo "| mesh | F | start | ran | steps | stages | per-face | vertex | folds | total s |"
echo "|---|---:|---|---|---:|---|---:|---:|---:|---:|"
for m in "$@"; do
  [ -f "$m" ] || { echo "| $(basename $m) | missing | | | | | | | | |"; continue; }
  n=$(basename $m); n=${n%.*}
  for st in conformal multilevel; do
    $BIN sphere $m $O/$n.$st.obj --start $st --report $O/$n.$st.json --quiet 2>$O/$n.$st.err
    ../shared/tools/param-eval $m $O/$n.$st.obj --json > $O/$n.$st.eval.json 2>/dev/null
    /usr/bin/python3 - "$n" "$st" "$O/$n.$st.json" "$O/$n.$st.eval.json" <<'EOF'
import json, sys
n, st, rp, ep = sys.argv[1:5]
try:
    r = json.load(open(rp)); e = json.load(open(ep))
except Exception:
    print("| %s | | %s | failed | | | | | | |" % (n, st)); sys.exit(0)
c = r.get("convergence", {})
stages = ""
for key, ch in (("lantern_retry", "L"), ("twisted_start", "T"), ("staged_retry", "S"), ("vertex_polish", "P"),
                ("global_polish", "G")):
    if key in c:
        stages += ch if c[key].get("kept") else ch.lower()
print("| %s | %d | %s | %s | %d | %s | %.4f | %.4f | %d | %.2f |" % (
    n, r["F"], st, r.get("start", "?"), r["steps"], stages or "-", e["r_mean_abs_dev"], e["vertex_logr_mean_abs"],
    e["folds"], r["time"]["total"]))
EOF
  done
done

#!/bin/sh
# thin_limbs.sh BIN OUTDIR - issue 21 table: each thin-limbed mesh (data/ and three shared ones) mapped
# without and with --refine-mesh (2x, and --refine-budget auto), per-face / vertex / folds (and faces) by
# ../shared/tools/param-eval.
# Run from the source root: sh bench/thin_limbs.sh build/authalic /tmp/tl
BIN=$1; O=$2; mkdir -p $O
for m in data/limbs4.obj data/limbs8.obj data/coil.obj data/tpose.obj ../shared/meshes/cow.off ../shared/meshes/cheburashka.off ../shared/meshes/hand_closed.obj; do
  n=$(basename $m); n=${n%.*}
  $BIN sphere $m $O/$n.obj --quiet 2>/dev/null
  u=$(../shared/tools/param-eval $m $O/$n.obj --json | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print('%.4f / %.4f, %d folds' % (d['r_mean_abs_dev'], d['vertex_logr_mean_abs'], d['folds']))")
  $BIN sphere $m $O/${n}_r.obj --refine-mesh $O/${n}_rs.obj --quiet 2>/dev/null
  r=$(../shared/tools/param-eval $O/${n}_rs.obj $O/${n}_r.obj --json | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print('%.4f / %.4f, %d F, %d folds' % (d['r_mean_abs_dev'], d['vertex_logr_mean_abs'], d['F'], d['folds']))" 2>/dev/null || echo "?")
  # --refine-budget auto: 2x, then 3x and 4x until the refined bounds are met (the budget kept in faces).
  $BIN sphere $m $O/${n}_a.obj --refine-mesh $O/${n}_as.obj --refine-budget auto --quiet 2>/dev/null
  a=$(../shared/tools/param-eval $O/${n}_as.obj $O/${n}_a.obj --json | /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print('%.4f / %.4f, %d F, %d folds' % (d['r_mean_abs_dev'], d['vertex_logr_mean_abs'], d['F'], d['folds']))" 2>/dev/null || echo "?")
  echo "| $n | $u | $r | $a |"
done

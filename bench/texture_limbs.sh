#!/bin/sh
# texture_limbs.sh BIN OUTDIR - textures of the thin-limbed family (issue 21, docs/textures.md, "The per-face
# area of a texture, and fold mending"): `authalic texture` in cea, laea and oct with the texture command's own
# map, then ../shared/tools/param-eval OUT OUT --coords vt: texel per-face error, faces, folds, seconds
# (or the error line). Run from the source root: sh bench/texture_limbs.sh build/authalic /tmp/tx
BIN=$1; O=$2; mkdir -p $O
echo "| mesh | projection | per-face (vt) | faces | folds | s |"
echo "|---|---|---|---|---|---|"
for m in limbs4 limbs8 coil tpose; do
  for p in cea laea oct; do
    t0=$(date +%s.%N)
    if $BIN texture data/$m.obj $O/${m}_$p.obj --projection $p --quiet 2>$O/${m}_$p.err; then
      t=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
      ../shared/tools/param-eval $O/${m}_$p.obj $O/${m}_$p.obj --coords vt --domain plane --json |
        /usr/bin/python3 -c "import json,sys; d=json.load(sys.stdin); print('| $m | $p | %.4f | %d | %d | %.2f |' % (d['r_mean_abs_dev'], d['F'], d['folds'], $t))"
    else
      echo "| $m | $p | failed: $(grep error $O/${m}_$p.err | sed 's/.*projection [a-z]*: //') | | | |"
    fi
  done
done

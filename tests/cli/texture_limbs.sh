# texture_limbs.sh - `authalic texture` on a mesh of the thin-limbed family in data/ (issue 21): its
# sphere map lays each limb out as a strip of needles, and splitting a needle that turns over in the
# texture turns its neighbour over, round after round around the limb (docs/textures.md). With each
# projection the texture must come out: exit 0, splits for folding made, no face turned over in
# (u, v), the input's vertices first, two faces more per added vertex, the surface area kept.
# Fails with the old cap of 64 rounds on every mesh here (cea: limbs4 3 folds left, limbs8 36, coil 10,
# tpose 94).
# sh texture_limbs.sh PROG SOURCE_DIR SHARED_DIR MESH   (MESH: limbs4, limbs8, coil or tpose)
. "$(dirname "$0")/lib.sh"
[ -f "$SRC/data/$1.obj" ] || skip "data/$1.obj is absent"
IN=$(stage "$SRC/data/$1.obj")
MAP=$T/in/map.obj
NV=$(obj_nv "$IN")
NF=$(grep -c '^f ' "$IN")
# The texture command's own map, made once for the three projections.
run sphere "$IN" "$MAP" --spherical-areas --quiet
[ "$status" -eq 0 ] || fail "the sphere map of $1 failed"
for p in cea laea oct; do
  rm -f "$T/o/tex.obj"
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --projection $p
  expect_status 0
  es=$(sed -n 's/.*split for folding=\([0-9]*\).*/\1/p' "$T/log/stderr")
  [ -n "$es" ] && [ "$es" -gt 0 ] || fail "$p: no splits for folding in the summary (the case is not exercised)"
  nv=$(obj_nv "$T/o/tex.obj")
  [ "$(grep -c '^f ' "$T/o/tex.obj")" -eq $((NF + 2 * (nv - NV))) ] || fail "$p: faces not two per added vertex"
  expect_vt_upright "$T/o/tex.obj" "$p: "
  $PY - "$IN" "$T/o/tex.obj" "$NV" <<'PYEOF' || fail "$p: the texture mesh (above)"
import sys
import numpy as np
from objmesh import load
X, F = load(sys.argv[1])
Y, G = load(sys.argv[2])
nv = int(sys.argv[3])
area = lambda P, T: 0.5 * np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), axis=1).sum()
a, b = area(X, F), area(Y, G)
same = len(Y) >= nv and np.abs(X - Y[:nv]).max() <= 1e-14 * np.abs(X).max()
ok = same and abs(b / a - 1) <= 1e-9
print("surface area %.12g -> %.12g; input vertices first: %s" % (a, b, same), file=sys.stderr)
sys.exit(0 if ok else 1)
PYEOF
done
exit 0

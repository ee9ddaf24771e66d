# density.sh - `--density FILE`: a per-face density of 4 on one half of the ellipsoid gives that half
# four times the domain area per unit surface area; bad density files exit 2 and write nothing.
# sh density.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
IN=$(stage "$SRC/data/ellipsoid.obj")
OUT=$T/o/map.obj
case "$1" in
half)
  # Per face: 4 where the centroid has x > 0, else 1.
  awk '/^v /{x[++n]=$2} /^f /{split($2,a,"/");split($3,b,"/");split($4,c,"/"); print (x[a[1]]+x[b[1]]+x[c[1]] > 0) ? 4 : 1}' "$IN" >"$T/d.txt"
  run sphere "$IN" "$OUT" --density "$T/d.txt" --quiet
  expect_status 0
  $PY - "$IN" "$OUT" <<'PYEOF' || fail "the dense half does not get 4x the area"
import sys
from objmesh import load
def area(V, f):
    a, b, c = (V[i] for i in f)
    u = [b[k] - a[k] for k in range(3)]; v = [c[k] - a[k] for k in range(3)]
    n = [u[1]*v[2]-u[2]*v[1], u[2]*v[0]-u[0]*v[2], u[0]*v[1]-u[1]*v[0]]
    return 0.5 * sum(x * x for x in n) ** 0.5
X, F = load(sys.argv[1]); P, _ = load(sys.argv[2])
d, s = [0, 0], [0, 0]
for f in F:
    side = 1 if sum(X[i][0] for i in f) > 0 else 0
    d[side] += area(P, f); s[side] += area(X, f)
r = (d[1] / s[1]) / (d[0] / s[0])
print("ratio", r)
sys.exit(0 if abs(r - 4) <= 5e-3 else 1)
PYEOF
  ;;
count)
  printf '1\n2\n3\n' >"$T/d.txt"
  run sphere "$IN" "$OUT" --density "$T/d.txt"
  expect_status 2
  expect_err "d.txt: 3 values; the mesh has [0-9]+ vertices and [0-9]+ faces"
  [ ! -e "$OUT" ] || fail "output written"
  ;;
negative)
  awk '/^v /{print (NR == 5) ? -1 : 1}' "$IN" >"$T/d.txt"
  run sphere "$IN" "$OUT" --density "$T/d.txt"
  expect_status 2
  expect_err "is not a positive finite number"
  [ ! -e "$OUT" ] || fail "output written"
  ;;
missing)
  run sphere "$IN" "$OUT" --density "$T/nothere.txt"
  expect_status 2
  expect_err "nothere.txt: cannot open the density file"
  [ ! -e "$OUT" ] || fail "output written"
  ;;
*) fail "unknown case $1" ;;
esac
exit 0

# squeezed.sh - a map whose flow could not open up squeezed protrusions says how much of the surface is
# left under 1/e of its area share (data/tpose.obj: limbs squeezed by e^-20 and more), and the figure
# agrees with the map (barycentric vertex cells of the chord triangles, counted here with numpy); a
# map without such cells (data/limbs4.obj) does not say it.
# sh squeezed.sh PROG SOURCE_DIR SHARED_DIR
. "$(dirname "$0")/lib.sh"
share() { # share OBJ_IN OBJ_MAP: percent of the surface area whose vertex cells are under 1/e of their share
  $PY - "$1" "$2" <<'PYEOF'
import sys
import numpy as np
def load(p):
    V, F = [], []
    for line in open(p):
        s = line.split()
        if s and s[0] == "v": V.append([float(x) for x in s[1:4]])
        if s and s[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return np.array(V), np.array(F)
X, F = load(sys.argv[1])
P, _ = load(sys.argv[2])
cell = lambda Y: np.bincount(F.ravel(), np.repeat(0.5 * np.linalg.norm(np.cross(Y[F[:, 1]] - Y[F[:, 0]], Y[F[:, 2]] - Y[F[:, 0]]), axis=1) / 3, 3), len(Y))
a, b = cell(X), cell(P)
low = np.log((b / b.sum()) / (a / a.sum())) < -1
print("%.3f %d" % (100 * a[low].sum() / a.sum(), low.sum()))
PYEOF
}
IN=$SRC/data/tpose.obj
[ -f "$IN" ] || skip "data/tpose.obj is absent"
run sphere "$IN" "$T/o/t.obj" --report "$T/o/t.json"
expect_status 0
expect_err "tolerance .* not reached"
said=$(sed -n 's/.*warning: .*: \([0-9.]*\)% of the surface (\([0-9]*\) vertices) is mapped to less than 1\/e of its area share.*/\1 \2/p' "$T/log/stderr")
[ -n "$said" ] || fail "no warning of the squeezed share on tpose"
grep -q 'less than 1/e of its area share' "$T/o/t.json" || fail "the report lacks the warning"
set -- $said $(share "$IN" "$T/o/t.obj")
# The warning rounds to two digits; the vertex count is exact.
$PY -c "import sys; s, n, c, m = map(float, sys.argv[1:]); sys.exit(0 if abs(s - c) <= 0.01 * c + 0.5 and n == m and s >= 50 else 1)" "$@" ||
  fail "warning says $1% ($2 vertices); the map has $3% ($4 vertices)"
run sphere "$SRC/data/limbs4.obj" "$T/o/l.obj"
expect_status 0
if grep -q 'of its area share' "$T/log/stderr"; then fail "limbs4 warned of squeezed cells"; fi
set -- $(share "$SRC/data/limbs4.obj" "$T/o/l.obj")
$PY -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1 else 1)" "$1" || fail "limbs4 has $1% of its surface under 1/e"
exit 0

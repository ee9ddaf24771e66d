# refine_nothing.sh - `authalic sphere --refine-mesh SURF` on a mesh where no chord triangle sits on its
# floor (a regular icosphere, made here) and the flow is stopped before its tolerance: nothing is split,
# the input's mesh is written, and the map is reported as not converged (the warning, and `converged`
# false in the report), as without --refine-mesh.
# sh refine_nothing.sh PROG SOURCE_DIR SHARED_DIR
. "$(dirname "$0")/lib.sh"
IN=$T/in/ico.obj
mkdir -p "$T/in"
$PY - "$IN" <<'PYEOF' || fail "could not make the icosphere"
import sys, math
t = (1 + 5 ** 0.5) / 2
V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
     (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
     (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
     (8, 6, 7), (9, 8, 1)]
V = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in V]
for _ in range(2):
    mid, F2 = {}, []
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(V[a][i] + V[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in p))
            V.append(tuple(x / n for x in p))
            mid[k] = len(V) - 1
        return mid[k]
    for a, b, c in F:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        F2 += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    F = F2
with open(sys.argv[1], "w") as o:
    o.write("# icosphere, level 2\n")
    for v in V: o.write("v %.17g %.17g %.17g\n" % v)
    for f in F: o.write("f %d %d %d\n" % tuple(i + 1 for i in f))
PYEOF
OUT=$T/o/map.obj
SURF=$T/o/surf.obj
run sphere "$IN" "$OUT" --steps 3 --tol 0 --refine-mesh "$SURF" --report "$T/o/r.json"
expect_status 0
expect_err "refined: nothing to split"
expect_err "tolerance 0 not reached"
grep -q '"converged":[[:space:]]*false' "$T/o/r.json" || fail "the report calls the map converged"
[ "$(obj_nv "$SURF")" -eq "$(obj_nv "$IN")" ] || fail "the refined surface has other vertices than the input"
exit 0

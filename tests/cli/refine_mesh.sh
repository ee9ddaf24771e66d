# refine_mesh.sh - `authalic sphere --refine-mesh SURF` on a mesh whose chord floor binds:
# SURF keeps the input's vertices first and unmoved, adds the new ones at their parents' stated
# parameter (SURF.parents.txt), at most BUDGET times the faces (default 2); the map is on the unit
# sphere, and ../shared/tools/param-eval SURF OUT finds 0 folds and issue 21's bounds for a refined map
# (per-face mean |r - 1| <= 0.02, vertex mean |log r| <= 0.005). Skipped without ../shared.
# sh refine_mesh.sh PROG SOURCE_DIR SHARED_DIR MESH [BUDGET [KEPT]]
#   (MESH: a file name in ../shared/meshes, or data/NAME for a mesh of this project; BUDGET auto: the
#   warning lists the budgets tried, 2x first, and KEPT (e.g. 3) is the one kept, within 4x)
. "$(dirname "$0")/lib.sh"
case "$1" in
  data/*)
    PE=$SHARED/tools/param-eval
    [ -x "$PE" ] || skip "$PE is absent"
    [ -f "$SRC/$1" ] || skip "$SRC/$1 is missing (run au_mklimbs to generate data/)"
    IN=$(stage "$SRC/$1") ;;
  *) stage_shared "$1" ;;
esac
BUDGET=${2:-2}
OUT=$T/o/map.obj
SURF=$T/o/surf.obj
run sphere "$IN" "$OUT" --refine-mesh "$SURF" --refine-budget "$BUDGET" --quiet
expect_status 0
CAP=$BUDGET
if [ "$BUDGET" = auto ]; then
  CAP=4
  expect_err "refine budget auto .*: 2x: [0-9]* faces, per-face"
  expect_err " ${3:?KEPT}x: [0-9]* faces, per-face [0-9.]*, vertex [0-9.]* \(kept\)"
fi
[ -f "$SURF" ] && [ -f "$SURF.parents.txt" ] || fail "the refined surface or its parents file is missing"
expect_on_sphere "$OUT" 1e-12
"$PE" "$SURF" "$OUT" --json >"$T/log/pe.json" || fail "param-eval failed"
$PY - "$IN" "$SURF" "$SURF.parents.txt" "$T/log/pe.json" "$CAP" <<'PYEOF' || fail "the refined map (above)"
import json, sys
def read(path):
    V, F = [], []
    for line in open(path):
        t = line.split()
        if t and t[0] == 'v': V.append(tuple(map(float, t[1:4])))
        elif t and t[0] == 'f': F.append(tuple(int(x.split('/')[0]) - 1 for x in t[1:4]))
    return V, F
src, surf, parents, pe = sys.argv[1:5]
if src.endswith('.off'):
    tok = open(src).read().split()
    nv, nf = int(tok[1]), int(tok[2])
    X = [tuple(map(float, tok[4 + 3 * i:7 + 3 * i])) for i in range(nv)]
    F0 = nf
else:
    X, F = read(src)
    F0 = len(F)
V, F = read(surf)
ok = V[:len(X)] == X and len(F) <= float(sys.argv[5]) * F0
for line in open(parents):
    k, a, b, t = line.split()
    k, a, b, t = int(k), int(a), int(b), float(t)
    ok = ok and max(abs((1 - t) * V[a][d] + t * V[b][d] - V[k][d]) for d in range(3)) <= 1e-12 * (1 + max(map(abs, V[k])))
d = json.load(open(pe))
print("refined: %d -> %d faces, per-face %.4f, vertex %.4f, folds %d" % (F0, len(F), d["r_mean_abs_dev"],
      d["vertex_logr_mean_abs"], d["folds"]), file=sys.stderr)
ok = ok and d["folds"] == 0 and d["r_mean_abs_dev"] <= 0.02 and d["vertex_logr_mean_abs"] <= 0.005
sys.exit(0 if ok else 1)
PYEOF
exit 0

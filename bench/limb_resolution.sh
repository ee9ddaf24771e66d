#!/bin/sh
# limb_resolution.sh BIN OUTDIR [MESH] - is the mesh's resolution what keeps a thin-limbed map from equal
# area? (issue 21; docs/sphere.md). MESH (default data/limbs4.obj) is split 1-to-4
# (every edge at its midpoint) once and twice, each mesh mapped from scratch by `BIN sphere` (the
# default options) and measured with ../shared/tools/param-eval: per-face / vertex, faces, time.
# Run from the source root: sh bench/limb_resolution.sh build/authalic /tmp/lr
BIN=$1; O=$2; M=${3:-data/limbs4.obj}
[ -x "$BIN" ] && [ -n "$O" ] || { echo "usage: sh bench/limb_resolution.sh BIN OUTDIR [MESH]" >&2; exit 2; }
mkdir -p "$O"
split4() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
V, F, mid = [], [], {}
for line in open(sys.argv[1]):
    s = line.split()
    if s and s[0] == "v": V.append([float(x) for x in s[1:4]])
    elif s and s[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
def m(a, b):
    k = (min(a, b), max(a, b))
    if k not in mid:
        mid[k] = len(V)
        V.append([(p + q) / 2 for p, q in zip(V[a], V[b])])
    return mid[k]
with open(sys.argv[2], "w") as out:
    G = []
    for a, b, c in F:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        G += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    out.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in V)
    out.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in G)
PY
}
n=$(basename "$M"); n=${n%.*}
cp "$M" "$O/${n}_x1.obj"
split4 "$O/${n}_x1.obj" "$O/${n}_x4.obj"
split4 "$O/${n}_x4.obj" "$O/${n}_x16.obj"
echo "| mesh | faces | per-face / vertex | folds | flow s | polish sweeps |"
echo "|---|--:|---|--:|--:|--:|"
for k in x1 x4 x16; do
  $BIN sphere "$O/${n}_$k.obj" "$O/${n}_${k}_map.obj" --report "$O/${n}_$k.json" --quiet 2>/dev/null
  ../shared/tools/param-eval "$O/${n}_$k.obj" "$O/${n}_${k}_map.obj" --json > "$O/${n}_$k.eval.json"
  /usr/bin/python3 - "$O/${n}_$k.eval.json" "$O/${n}_$k.json" "${n} $k" <<'PY'
import json, sys
e, r = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
vp = r["convergence"].get("vertex_polish", {})
print("| %s | %d | %.4f / %.4f | %d | %.2f | %s |" % (sys.argv[3], e["F"], e["r_mean_abs_dev"], e["vertex_logr_mean_abs"],
      e["folds"], r["time"]["flow"], vp.get("sweeps", "-")))
PY
done

# scripts.sh - workflow.scripts: the workflow's Python scripts on their own, where the cohort tests
# do not reach. The distortion fallback must compute what the report measures (its mean |ln| is
# the report's vertex_logr_mean_abs) for inputs in every format authalic reads (OFF, binary PLY,
# binary STL written here from data/ellipsoid.obj) and for a square map that split edges (a
# 12-gon fanned from one vertex, corners forced so four chords lie along sides); the planar
# preview must draw that map; the resource estimate must read every format's face count.
. "$(dirname "$0")/lib.sh"
d=$WORK/scripts
rm -rf "$d"
mkdir -p "$d" || fail "cannot make $d"
S=$SRC/workflow/scripts
$PY - "$SRC/data/ellipsoid.obj" "$d" <<'PYEOF' || fail "cannot write the test meshes"
import struct, sys
import numpy as np
src, d = sys.argv[1], sys.argv[2]
X, F = [], []
for line in open(src):
    t = line.split()
    if t and t[0] == "v": X.append([float(v) for v in t[1:4]])
    if t and t[0] == "f": F.append([int(v) - 1 for v in t[1:4]])
X, F = np.array(X), np.array(F)
with open(f"{d}/ell.off", "w") as fh:
    fh.write(f"OFF\n# a comment\n{len(X)} {len(F)} 0\n")
    fh.writelines(f"{x} {y} {z}\n" for x, y, z in X)
    fh.writelines(f"3 {a} {b} {c}\n" for a, b, c in F)
v = np.zeros(len(X), dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("q", "u1")])
v["x"], v["y"], v["z"] = X.T
f = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", 3)])
f["n"], f["i"] = 3, F
head = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(X)}\nproperty float x\nproperty float y\n"
        f"property float z\nproperty uchar quality\nelement face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
open(f"{d}/ell.ply", "wb").write(head.encode() + v.tobytes() + f.tobytes())
with open(f"{d}/ell.stl", "wb") as fh:
    fh.write(b"\0" * 80 + struct.pack("<I", len(F)))
    for t in F:
        fh.write(struct.pack("<3f", 0, 0, 0) + X[t].astype("<f4").tobytes() + b"\0\0")
n = 12
a = np.arange(n) * 2 * np.pi / n
with open(f"{d}/fan.obj", "w") as fh:
    fh.writelines(f"v {np.cos(t)} {np.sin(t)} {0.1 * np.sin(3 * t)}\n" for t in a)
    fh.writelines(f"f 1 {i + 1} {i + 2}\n" for i in range(1, n - 1))
PYEOF

# check_fallback NAME IN COMMAND [OPTIONS]: map IN, run the fallback, compare with the report.
check_fallback() {
  local name=$1 in=$2 cmd=$3
  shift 3
  "$PROG" "$cmd" "$in" "$d/$name.map.obj" --report "$d/$name.json" --quiet "$@" 2>"$d/$name.err" ||
    fail "$PROG $cmd $in exited $?: $(cat "$d/$name.err")"
  $PY "$S/distortion_fallback.py" "$in" "$d/$name.map.obj" "$d/$name.txt" || fail "fallback on $in exited $?"
  $PY - "$d/$name.json" "$d/$name.txt" "$d/$name.map.obj" "$name" <<'PYEOF' || fail "fallback on $in (above)"
import json, math, sys
rep = json.load(open(sys.argv[1]))
vals = [float(x) for x in open(sys.argv[2]).read().split()]
nv = sum(1 for l in open(sys.argv[3]) if l.startswith("v "))
want = rep["metrics"]["vertex_logr_mean_abs"]
got = sum(abs(v) for v in vals) / len(vals) * math.log(2)
ok = len(vals) == nv == rep["V"] and abs(got - want) <= 1e-9 * want
print(f"{sys.argv[4]}: {len(vals)} values for V={rep['V']}, mean |ln| {got:.12g}, report {want:.12g}",
      file=sys.stderr if not ok else sys.stdout)
sys.exit(0 if ok else 1)
PYEOF
}

check_fallback obj "$SRC/data/ellipsoid.obj" sphere
check_fallback off "$d/ell.off" sphere
check_fallback ply "$d/ell.ply" sphere
check_fallback stl "$d/ell.stl" sphere
check_fallback fan "$d/fan.obj" square --corners 0,3,6,9
grep -q "split 4 edges" "$d/fan.err" || fail "the fan's square map split no edges: $(cat "$d/fan.err")"
[ "$(wc -l < "$d/fan.txt")" -eq 16 ] || fail "fan: $(wc -l < "$d/fan.txt") values for 12 + 4 vertices"

$PY "$S/preview.py" "$d/fan.obj" "$d/fan.map.obj" "$d/fan.png" --command square --title fan || fail "preview of the split square exited $?"
[ "$(head -c 8 "$d/fan.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "fan.png is not a PNG"

$PY - "$S" "$SRC/data/ellipsoid.obj" "$d" <<'PYEOF' || fail "face counts (above)"
import sys
sys.path.insert(0, sys.argv[1])
import meshio_np
counts = {p: meshio_np.face_count(p) for p in [sys.argv[2]] + [f"{sys.argv[3]}/ell.{e}" for e in ("off", "ply", "stl")]}
bad = {p: n for p, n in counts.items() if n != 2080}
print("face counts:", counts, file=sys.stderr if bad else sys.stdout)
sys.exit(1 if bad else 0)
PYEOF
echo "workflow.scripts: fallback equals the reports on OBJ, OFF, PLY, STL and a split square"

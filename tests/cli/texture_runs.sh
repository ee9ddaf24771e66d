# texture_runs.sh - end-to-end runs of `authalic texture` and `authalic sample` on data/bumpy_star.obj
# with its sphere map: the OBJ's coordinates (seam, poles), baked pictures of the right size, the
# sample grids in .npy and .csv, and bad inputs rejected with no file left.
# sh texture_runs.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
[ -f "$SRC/data/bumpy_star.obj" ] || skip "data/bumpy_star.obj is missing"
IN=$(stage "$SRC/data/bumpy_star.obj")
MAP=$T/in/star_map.obj
NV=$(obj_nv "$IN")
NF=$(grep -c '^f ' "$IN")

make_map() {
  run sphere "$IN" "$MAP" --quiet
  [ "$status" -eq 0 ] || fail "the sphere map of the test mesh failed"
}

# Width and height of a PNG, from its IHDR chunk.
png_size() {
  "$PY" -c 'import struct,sys
d=open(sys.argv[1],"rb").read(24)
assert d[:8]==b"\x89PNG\r\n\x1a\n" and d[12:16]==b"IHDR", "not a PNG"
print("%dx%d" % struct.unpack(">II", d[16:24]))' "$1" 2>"$T/log/py" || fail "$1 is not a PNG: $(cat "$T/log/py")"
}

# Every face of an OBJ with v/vt corners spans less than half the texture in u and v.
expect_faces_compact() {
  awk '$1 == "vt" { n++; u[n] = $2; v[n] = $3 }
       $1 == "f" { if (NF != 4) { print "face with " NF - 1 " corners"; exit 1 }
                   lo = 1e9; hi = -1e9; vlo = 1e9; vhi = -1e9
                   for (i = 2; i <= 4; i++) { if (split($i, c, "/") < 2) { print "corner without vt: " $i; exit 1 }
                     t = c[2]; if (u[t] < lo) lo = u[t]; if (u[t] > hi) hi = u[t]; if (v[t] < vlo) vlo = v[t]; if (v[t] > vhi) vhi = v[t] }
                   if (hi - lo >= 0.5 || vhi - vlo >= 0.5) { print "face " $0 " spans " hi - lo " x " vhi - vlo; exit 1 } }' "$1" >"$T/log/faces" 2>&1 \
    || fail "$1: $(cat "$T/log/faces")"
}

case $1 in
obj_cea)
  make_map
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --lonlat "$T/o/ll.txt"
  expect_status 0
  expect_err 'texture: V=[0-9]+ F=[0-9]+ projection=cea'
  nv=$(obj_nv "$T/o/tex.obj")
  nf=$(grep -c '^f ' "$T/o/tex.obj")
  # Each pole either splits a face (one vertex and two faces more) or is a vertex; each edge split
  # (where a face would flip in (u, v)) adds its midpoint and splits the edge's two faces.
  ps=$(sed -n 's/.*pole splits=\([0-9]*\).*/\1/p' "$T/log/stderr")
  es=$(sed -n 's/.*edge splits=\([0-9]*\).*/\1/p' "$T/log/stderr")
  [ -n "$ps" ] && [ -n "$es" ] && [ "$ps" -le 2 ] || fail "no split counts in the summary"
  [ "$nv" -eq $((NV + ps + es)) ] || fail "$nv vertices for $NV input vertices, $ps pole and $es edge splits"
  [ "$nf" -eq $((NF + 2 * ps + 2 * es)) ] || fail "$nf faces for $NF input faces, $ps pole and $es edge splits"
  expect_vt_upright "$T/o/tex.obj"
  # The input's vertices come first, unchanged (as printed with 17 digits).
  head -n "$(grep -n '^v ' "$IN" | tail -1 | cut -d: -f1)" "$IN" | grep '^v ' | awk '{ printf "%.15g %.15g %.15g\n", $2, $3, $4 }' >"$T/a"
  grep '^v ' "$T/o/tex.obj" | head -n "$NV" | awk '{ printf "%.15g %.15g %.15g\n", $2, $3, $4 }' >"$T/b"
  cmp -s "$T/a" "$T/b" || fail "the input's vertices are not the OBJ's first vertices"
  expect_faces_compact "$T/o/tex.obj"
  # Some faces cross the seam: their u leaves [0, 1].
  awk '$1 == "vt" && ($2 < 0 || $2 > 1) { n++ } END { exit !(n > 0) }' "$T/o/tex.obj" || fail "no vt across the seam"
  [ "$(grep -vc '^#' "$T/o/ll.txt")" -eq "$nv" ] || fail "--lonlat has not one line per vertex"
  awk '!/^#/ { if ($1 < -180 || $1 > 180 || $2 < -90 || $2 > 90) exit 1 }' "$T/o/ll.txt" || fail "longitude/latitude out of range"
  [ "$(ls "$T/o" | tr '\n' ' ')" = "ll.txt tex.obj " ] || fail "unexpected files: $(ls "$T/o")"
  ;;
laea)
  make_map
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --projection laea --quiet
  expect_status 0
  # laea may split faces that would turn over (fold splits): no face turned over in (u, v), the
  # input's vertices first and unchanged, two faces more per added vertex.
  nv=$(obj_nv "$T/o/tex.obj")
  [ "$(grep -c '^f ' "$T/o/tex.obj")" -eq $((NF + 2 * (nv - NV))) ] || fail "faces not two per added vertex"
  expect_vt_upright "$T/o/tex.obj"
  grep '^v ' "$IN" | awk '{ printf "%.15g %.15g %.15g\n", $2, $3, $4 }' >"$T/a"
  grep '^v ' "$T/o/tex.obj" | head -n "$NV" | awk '{ printf "%.15g %.15g %.15g\n", $2, $3, $4 }' >"$T/b"
  cmp -s "$T/a" "$T/b" || fail "the input's vertices are not the OBJ's first vertices"
  # --axis auto: the rotation is printed, the poles leave the map's z axis, still no fold.
  run texture "$IN" --map "$MAP" "$T/o/auto.obj" --projection laea --axis auto
  expect_status 0
  expect_err 'axis=-?[0-9.]+,-?[0-9.]+,-?[0-9.]+'
  grep -q 'axis=0.000000,0.000000,1.000000' "$T/log/stderr" && fail "--axis auto kept the map's z axis"
  grep -q '^# texture frame (rows' "$T/o/auto.obj" || fail "no texture frame in the OBJ"
  expect_vt_upright "$T/o/auto.obj" "--axis auto: "
  awk '$1 == "vt" && ($2 < 0 || $2 > 1 || $3 < 0 || $3 > 1) { exit 1 }' "$T/o/tex.obj" || fail "a vt outside [0, 1]"
  expect_faces_compact "$T/o/tex.obj"
  ;;
bake_normal)
  make_map
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --bake normal --image "$T/o/tex.png" --size 256x128 \
      --preview "$T/o/prev.png" --render "$T/o/render.png" --quiet
  expect_status 0
  [ "$(png_size "$T/o/tex.png")" = 256x128 ] || fail "texture size $(png_size "$T/o/tex.png")"
  [ "$(png_size "$T/o/prev.png")" = 1024x808 ] || fail "preview size $(png_size "$T/o/prev.png")"
  [ "$(png_size "$T/o/render.png")" = 1024x512 ] || fail "render size $(png_size "$T/o/render.png")"
  grep -q '^map_Kd tex.png$' "$T/o/tex.mtl" || fail "the material does not name the texture"
  grep -q '^mtllib tex.mtl$' "$T/o/tex.obj" || fail "the OBJ does not name its material"
  ;;
bake_scalar)
  make_map
  # A per-vertex scalar: the height z of each vertex.
  awk '$1 == "v" { print $4 }' "$IN" >"$T/in/z.txt"
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --bake "$T/in/z.txt" --image "$T/o/z.png" --size 64x32
  expect_status 0
  expect_err 'range=\[-?[0-9.e-]+, [0-9.e-]+\]'
  [ "$(png_size "$T/o/z.png")" = 64x32 ] || fail "texture size"
  # One value too few: rejected as bad input, nothing written.
  sed '$d' "$T/in/z.txt" >"$T/in/z_short.txt"
  rm -f "$T"/o/*
  run texture "$IN" --map "$MAP" "$T/o/tex.obj" --bake "$T/in/z_short.txt" --image "$T/o/z.png"
  expect_rejected "$((NV - 1)) values for $NV vertices"
  ;;
long_names)
  # A baked file and OUT with long paths (both are named in the files written): the material is the
  # whole text, not cut off, and the --lonlat header names OUT. Before, a long --bake path filled the
  # .mtl with NULs past its 261st byte and a long OUT overran --lonlat's buffer.
  make_map
  long=$T/o/$(printf 'd%.0s' $(seq 1 200))/$(printf 'e%.0s' $(seq 1 200))
  mkdir -p "$long"
  awk '$1 == "v" { print $4 }' "$IN" >"$long/z.txt"
  run texture "$IN" --map "$MAP" "$long/tex.obj" --bake "$long/z.txt" --image "$long/z.png" --size 64x32 \
      --lonlat "$long/ll.txt" --quiet
  expect_status 0
  "$PY" -c 'import sys; sys.exit(b"\0" in open(sys.argv[1], "rb").read())' "$long/tex.mtl" || fail "NUL bytes in the material"
  [ "$(tail -1 "$long/tex.mtl")" = "map_Kd z.png" ] || fail "the material ends with: $(tail -c 80 "$long/tex.mtl" | od -c | head -3)"
  [ "$(head -1 "$long/ll.txt")" = "# longitude latitude (degrees) of each vertex of $long/tex.obj" ] \
      || fail "the --lonlat header: $(head -c 120 "$long/ll.txt")"
  [ "$(($(wc -l <"$long/ll.txt") - 1))" -eq "$(grep -c '^v ' "$long/tex.obj")" ] || fail "--lonlat lines"
  ;;
sample)
  make_map
  awk '$1 == "v" { print $2 + $3 }' "$IN" >"$T/in/a.txt"
  run sample "$IN" --map "$MAP" --grid 64x32 "$T/o/s.npy" --normals --attr "$T/in/a.txt" --report "$T/o/r.json"
  expect_status 0
  expect_err 'cell area std/mean=0\.0[0-4]'
  "$PY" - "$T/o/s.npy" "$T/o/r.json" >"$T/log/py" 2>&1 <<'PYEOF' || fail "$(cat "$T/log/py")"
import json, struct, sys
d = open(sys.argv[1], "rb").read()
assert d[:8] == b"\x93NUMPY\x01\x00", "bad magic"
hl = struct.unpack("<H", d[8:10])[0]
head = d[10:10 + hl].decode()
assert (10 + hl) % 64 == 0 and "'shape': (32, 64, 7)" in head and "'<f8'" in head, head
n = (len(d) - 10 - hl) // 8
assert n == 32 * 64 * 7, n
vals = struct.unpack("<%dd" % n, d[10 + hl:])
for i in range(0, n, 7):
    x, y, z, nx, ny, nz, a = vals[i:i + 7]
    assert abs(nx * nx + ny * ny + nz * nz - 1) < 1e-9, "normal not unit"
r = json.load(open(sys.argv[2]))
assert r["grid"] == [64, 32] and r["columns"] == 7 and r["cell_area_cv"] < 0.05, r
try:
    import numpy
    a = numpy.load(sys.argv[1])
    assert a.shape == (32, 64, 7) and a.dtype == numpy.float64
except ImportError:
    pass
PYEOF
  ;;
sample_csv)
  make_map
  run sample "$IN" --map "$MAP" --grid 16x8 "$T/o/s.csv" --quiet
  expect_status 0
  [ "$(wc -l <"$T/o/s.csv")" -eq 129 ] || fail "$(wc -l <"$T/o/s.csv") lines, expected 129"
  head -1 "$T/o/s.csv" | grep -q '^row,col,lon,lat,x,y,z$' || fail "header: $(head -1 "$T/o/s.csv")"
  awk -F, 'NR > 1 && NF != 7 { exit 1 }' "$T/o/s.csv" || fail "a line without 7 fields"
  ;;
bad_map)
  # A map of another mesh, a map off the sphere, a folded map: bad input, nothing written.
  run texture "$IN" --map "$(stage "$SRC/data/spiky_ico.obj")" "$T/o/tex.obj"
  expect_rejected 'not a map of'
  awk '$1 == "v" { print "v", 2 * $2, 2 * $3, 2 * $4; next } { print }' "$IN" >"$T/in/big.obj"
  run texture "$IN" --map "$T/in/big.obj" "$T/o/tex.obj"
  expect_rejected 'not on the sphere'
  make_map
  # Send one vertex to its antipode: the triangles around it turn over.
  awk '$1 == "v" { n++; if (n == 5) { printf "v %.17g %.17g %.17g\n", -$2, -$3, -$4; next } } { print }' "$MAP" >"$T/in/folded.obj"
  run sample "$IN" --map "$T/in/folded.obj" --grid 8x4 "$T/o/s.npy"
  expect_rejected 'folded triangle'
  ;;
mirrored)
  # A mirrored map (every triangle reversed, as for a mesh whose faces turn inwards) is a valid
  # map: the samples are those of the map turned inside out, the cells still equal.
  make_map
  awk '$1 == "v" { printf "v %.17g %.17g %.17g\n", $2, -$3, $4; next } { print }' "$MAP" >"$T/in/mirror.obj"
  run sample "$IN" --map "$T/in/mirror.obj" --grid 32x16 "$T/o/s.csv" --report "$T/o/r.json"
  expect_status 0
  expect_err 'cell area std/mean=0\.0[0-4]'
  # Cell (row r, col c) of the mirrored map is cell (r, W-1-c) of the map itself (y -> -y).
  run sample "$IN" --map "$MAP" --grid 32x16 "$T/o/t.csv" --quiet
  expect_status 0
  awk -F, 'NR == FNR { if (FNR > 1) { a[$1 "," $2] = $5 "," $6 "," $7 }; next }
           FNR > 1 { k = $1 "," (31 - $2); split(a[k], q, ","); d = ($5 - q[1])^2 + ($6 - q[2])^2 + ($7 - q[3])^2; if (d > 1e-18) { print "cell " $1 "," $2 " differs by " d; exit 1 } }' \
      "$T/o/t.csv" "$T/o/s.csv" >"$T/log/cmp" || fail "$(cat "$T/log/cmp")"
  ;;
on_the_fly)
  # Without --map the sphere map is computed first.
  run texture "$(stage "$SRC/data/spiky_ico.obj")" "$T/o/tex.obj" --quiet
  expect_status 0
  expect_faces_compact "$T/o/tex.obj"
  ;;
area_target)
  # --area-tol auto splits until the texture is as exact as the map: the summary names the target
  # (1.25 x the map's per-face error + 0.002) and says it is met, and the OBJ's per-face mean
  # |vt share / surface share - 1|, measured here, is at most that, at no more than 32x the faces.
  run texture "$IN" "$T/o/t.obj" --projection laea --area-tol auto
  expect_status 0
  expect_err 'target [0-9.e-]+ met\)'
  tg=$(sed -n 's/.*target \([0-9.e-]*\) met.*/\1/p' "$T/log/stderr")
  $PY - "$T/o/t.obj" "$tg" "$NF" <<'PYEOF' || fail "the texture misses its target $tg"
import sys
V, T, F = [], [], []
for line in open(sys.argv[1]):
    t = line.split()
    if not t: continue
    if t[0] == "v": V.append([float(x) for x in t[1:4]])
    elif t[0] == "vt": T.append([float(x) for x in t[1:3]])
    elif t[0] == "f": F.append([[int(i) - 1 for i in c.split("/")[:2]] for c in t[1:4]])
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
sa, ta = [], []
for f in F:
    p, q, r = (V[c[0]] for c in f)
    n = cross([q[i] - p[i] for i in range(3)], [r[i] - p[i] for i in range(3)])
    sa.append(0.5 * sum(x * x for x in n) ** 0.5)
    a, b, c = (T[c[1]] for c in f)
    ta.append(0.5 * abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])))
S, A = sum(sa), sum(ta)
e = sum(abs((t / A) / (s / S) - 1) for s, t in zip(sa, ta)) / len(F)
print("per-face %.5f target %s faces %d" % (e, sys.argv[2], len(F)))
sys.exit(0 if e <= float(sys.argv[2]) and len(F) <= 32 * int(sys.argv[3]) * 1.3 else 1)
PYEOF
  ;;
on_the_fly_spherical)
  # Without --map the map drives the spherical triangles' areas only (no chord polish): on this mesh,
  # where `authalic sphere` polishes, its spherical per-face error (sph|r-1| in the summary) is lower
  # than that of the sphere command's map.
  make_map
  run texture "$IN" --map "$MAP" "$T/o/a.obj"
  expect_status 0
  a=$(sed -n 's/.* sph|r-1|=\([^ ]*\) .*/\1/p' "$T/log/stderr")
  run texture "$IN" "$T/o/b.obj"
  expect_status 0
  b=$(sed -n 's/.* sph|r-1|=\([^ ]*\) .*/\1/p' "$T/log/stderr")
  [ -n "$a" ] && [ -n "$b" ] || fail "no sph|r-1| in the summary"
  awk -v a="$a" -v b="$b" 'BEGIN { exit !(b < a) }' || fail "on the fly sph|r-1|=$b, with the sphere map $a"
  expect_faces_compact "$T/o/b.obj"
  # `authalic sphere --spherical-areas` makes that map for --map: the texture from it is the
  # on-the-fly one (the map read back from its 17-digit OBJ: to 1e-12), faces and all.
  run sphere "$IN" "$T/o/s.obj" --spherical-areas --quiet
  expect_status 0
  run texture "$IN" --map "$T/o/s.obj" "$T/o/c.obj" --quiet
  expect_status 0
  $PY - "$T/o/b.obj" "$T/o/c.obj" <<'PYEOF' || fail "the texture from --spherical-areas differs from the on-the-fly one"
import sys
def rows(p):
    out = {}
    for line in open(p):
        t = line.split()
        if t and t[0] in ("v", "vt", "f"):
            out.setdefault(t[0], []).append(t[1:])
    return out
a, b = rows(sys.argv[1]), rows(sys.argv[2])
ok = a["f"] == b["f"] and len(a["v"]) == len(b["v"]) and len(a["vt"]) == len(b["vt"])
for key in ("v", "vt"):
    for x, y in zip(a[key], b[key]):
        ok = ok and max(abs(float(p) - float(q)) for p, q in zip(x, y)) <= 1e-12
sys.exit(0 if ok else 1)
PYEOF
  ;;
*)
  fail "unknown case $1"
  ;;
esac
exit 0

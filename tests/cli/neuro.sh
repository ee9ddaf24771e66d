# neuro.sh - neuroimaging formats end to end (issue 19): what we write is read by nibabel with the
# right values, what nibabel writes we read, FreeSurfer -> ours -> FreeSurfer keeps faces and footer
# byte for byte, Connectome Workbench accepts our sphere, and fsaverage5 maps within the bounds.
# nibabel runs under Debian's /usr/bin/python3 (python3-nibabel); Workbench is wb_command
# (connectome-workbench). A case skips (77, one line) only where its component cannot run.
# sh neuro.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
FS5=$SHARED/neuro/fsaverage5

need_nibabel() {
  $PY -c 'import nibabel, numpy' 2>/dev/null || skip "nibabel is not importable by $PY (apt-get install python3-nibabel)"
}
need_fs5() {
  [ -f "$FS5/white_right.gii.gz" ] && [ -f "$FS5/sulc_right.gii.gz" ] || skip "$FS5 is absent"
}
need_wb() {
  command -v wb_command >/dev/null 2>&1 || skip "wb_command is not installed (apt-get install connectome-workbench)"
}

case "$1" in
nibabel_reads)
  # Our FreeSurfer sphere (radius 100), GIfTI sphere, curv and .shape.gii distortion files, read by
  # nibabel: positions are the OBJ map's times the radius, the faces the input's, the distortion
  # the log2 of the vertex cells' share ratio computed here again.
  need_nibabel
  IN=$(stage "$SRC/data/ellipsoid.obj")
  run sphere "$IN" "$T/o/map.obj" --quiet --distortion "$T/o/d.curv"
  expect_status 0
  run sphere "$IN" "$T/o/lh.sphere" --format freesurfer --radius 100 --quiet --distortion "$T/o/d.shape.gii"
  expect_status 0
  run sphere "$IN" "$T/o/map.surf.gii" --quiet
  expect_status 0
  $PY - "$IN" "$T/o" <<'PYEOF' || fail "nibabel does not read our files with the right values"
import sys, numpy as np, nibabel as nib, nibabel.freesurfer as fs
from objmesh import load as obj
X, F = obj(sys.argv[1]); o = sys.argv[2]
P, PF = obj(o + "/map.obj")
v, f, stamp = fs.read_geometry(o + "/lh.sphere", read_stamp=True)
assert stamp.startswith("created by authalic"), stamp
assert (f == F).all() and (PF == F).all()
assert np.abs(v / 100 - P).max() < 1e-6, np.abs(v / 100 - P).max()
g = nib.load(o + "/map.surf.gii")
assert (g.darrays[1].data == F).all() and np.abs(g.darrays[0].data - P).max() < 1e-6
assert g.darrays[0].meta["GeometricType"] == "Spherical"
def cells(V):
    A = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    c = np.bincount(F.ravel(), np.repeat(A / 3, 3), len(V))
    return c / c.sum()
want = np.log2(cells(P) / cells(X))
d1 = fs.read_morph_data(o + "/d.curv"); d2 = nib.load(o + "/d.shape.gii").darrays[0].data
assert d1.shape == (len(X),) and d2.shape == (len(X),)
print("curv vs numpy", np.abs(d1 - want).max(), "shape.gii vs curv", np.abs(d2 - d1).max())
assert np.abs(d1 - want).max() < 1e-5 and np.abs(d2 - d1).max() < 1e-5
assert nib.load(o + "/d.shape.gii").darrays[0].intent == 2005  # NIFTI_INTENT_SHAPE
PYEOF
  ;;
nibabel_writes)
  # Surfaces and values written by nibabel (FreeSurfer surface and curv, GIfTI surface with float64
  # positions, .func.gii) are read: the map has nibabel's faces, and the values reach sample --attr
  # and --density.
  need_nibabel
  IN=$(stage "$SRC/data/ellipsoid.obj")
  $PY - "$IN" "$T/in" <<'PYEOF' || fail "nibabel could not write the inputs"
import sys, numpy as np, nibabel as nib, nibabel.freesurfer as fs
V, F = [], []
for l in open(sys.argv[1]):
    t = l.split()
    if t and t[0] == "v": V.append([float(x) for x in t[1:4]])
    if t and t[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
V, F, d = np.array(V), np.array(F, dtype=np.int32), sys.argv[2]
fs.write_geometry(d + "/lh.white", V, F, create_stamp="created by nibabel")
fs.write_morph_data(d + "/lh.thickness", 1 + (V[:, 0] > 0).astype(np.float32))
pts = nib.gifti.GiftiDataArray(V.astype(np.float64), intent="NIFTI_INTENT_POINTSET")
tri = nib.gifti.GiftiDataArray(F, intent="NIFTI_INTENT_TRIANGLE")
nib.save(nib.gifti.GiftiImage(darrays=[pts, tri]), d + "/lh.white.surf.gii")
val = nib.gifti.GiftiDataArray(V[:, 2].astype(np.float32), intent="NIFTI_INTENT_NORMAL")
nib.save(nib.gifti.GiftiImage(darrays=[val]), d + "/z.func.gii")
np.savetxt(d + "/faces.txt", F, fmt="%d")
PYEOF
  for f in lh.white lh.white.surf.gii; do
    run sphere "$T/in/$f" "$T/o/$f.obj" --quiet --density "$T/in/lh.thickness"
    expect_status 0
    obj_faces "$T/o/$f.obj" | awk '{ print $1 - 1, $2 - 1, $3 - 1 }' >"$T/o/faces.txt"
    cmp -s "$T/o/faces.txt" "$T/in/faces.txt" || fail "$f: the map's faces are not nibabel's"
  done
  run sample "$T/in/lh.white" --grid 16x8 "$T/o/s.npy" --map "$T/o/lh.white.obj" --attr "$T/in/z.func.gii" \
    --attr "$T/in/lh.thickness" --quiet
  expect_status 0
  $PY - "$T/o/s.npy" <<'PYEOF' || fail "sample --attr did not carry the .func.gii and curv values"
import sys, numpy as np
s = np.load(sys.argv[1])
assert s.shape == (8, 16, 5), s.shape
assert np.abs(s[..., 5 - 2] - s[..., 2]).max() < 1e-5     # z.func.gii holds z: equals the z column
assert s[..., 4].min() >= 1 - 1e-9 and s[..., 4].max() <= 2 + 1e-9 and s[..., 4].min() < 1.5 < s[..., 4].max()
PYEOF
  rm -f "$T/o/faces.txt"
  ;;
fs_roundtrip)
  # FreeSurfer in, FreeSurfer out under an extension-less name: faces and the volume-geometry footer
  # byte for byte, nv and nf the same; --format gifti makes GIfTI of the same name.
  need_nibabel
  IN=$(stage "$SRC/data/ellipsoid.obj")
  $PY - "$IN" "$T/in/rh.white" <<'PYEOF' || fail "nibabel could not write the input"
import sys, numpy as np, nibabel.freesurfer as fs
V, F = [], []
for l in open(sys.argv[1]):
    t = l.split()
    if t and t[0] == "v": V.append([float(x) for x in t[1:4]])
    if t and t[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
vi = {"head": np.array([2, 0, 20], dtype=">i4"), "valid": "1  # volume info valid", "filename": "/data/T1.mgz",
      "volume": np.array([256, 256, 256]), "voxelsize": np.array([1., 1., 1.]), "xras": np.array([-1., 0., 0.]),
      "yras": np.array([0., 0., -1.]), "zras": np.array([0., 1., 0.]), "cras": np.array([5.5, 18., -3.])}
fs.write_geometry(sys.argv[2], np.array(V), np.array(F), create_stamp="created by nibabel", volume_info=vi)
PYEOF
  run sphere "$T/in/rh.white" "$T/o/rh.sphere.authalic" --quiet --radius 100
  expect_status 0
  run sphere "$T/in/rh.white" "$T/o/rh.sphere.gifti" --quiet --format gifti
  expect_status 0
  head -c 5 "$T/o/rh.sphere.gifti" | grep -q '<?xml' || fail "--format gifti did not write GIfTI"
  $PY - "$T/in/rh.white" "$T/o/rh.sphere.authalic" <<'PYEOF' || fail "faces or footer changed"
import sys, nibabel.freesurfer as fs
a, b = (open(p, "rb").read() for p in sys.argv[1:3])
def split(x):
    e = x.index(b"\n\n", 3) + 2
    nv, nf = int.from_bytes(x[e:e + 4], "big"), int.from_bytes(x[e + 4:e + 8], "big")
    v = e + 8 + 12 * nv
    return x[e:e + 8], x[v:v + 12 * nf], x[v + 12 * nf:]
(ca, fa, ta), (cb, fb, tb) = split(a), split(b)
assert ca == cb and fa == fb and ta == tb and len(ta) > 100, (len(ta), len(tb))
m = fs.read_geometry(sys.argv[2], read_metadata=True)[2]
assert m["filename"] == "/data/T1.mgz" and list(m["cras"]) == [5.5, 18.0, -3.0], m
print("footer", len(ta), "bytes kept")
PYEOF
  ;;
fsaverage5)
  # Issue 19's bound: fsaverage5's right white surface at radius 100: 0 folds, per-face mean |r-1|
  # <= 0.02 as param-eval measures it (positions divided by the radius), CortexRight and Spherical.
  need_nibabel
  need_fs5
  [ -x "$SHARED/tools/param-eval" ] || skip "$SHARED/tools/param-eval is absent"
  run sphere "$FS5/white_right.gii.gz" "$T/o/rh.sphere.gii" --radius 100 --quiet
  expect_status 0
  $PY - "$FS5/white_right.gii.gz" "$T/o/rh.sphere.gii" "$T/o" <<'PYEOF' || fail "cannot convert for param-eval"
import sys, numpy as np, nibabel as nib
w, s = nib.load(sys.argv[1]), nib.load(sys.argv[2])
assert s.darrays[0].meta["AnatomicalStructurePrimary"] == "CortexRight"
assert s.darrays[0].meta["GeometricType"] == "Spherical"
r = np.linalg.norm(s.darrays[0].data.astype(float), axis=1)
assert np.abs(r - 100).max() < 1e-3, np.abs(r - 100).max()
for name, V in (("white", w.darrays[0].data.astype(float)), ("sphere", s.darrays[0].data.astype(float) / 100)):
    with open(sys.argv[3] + "/" + name + ".obj", "w") as f:
        f.writelines("v %.9g %.9g %.9g\n" % tuple(p) for p in V)
        f.writelines("f %d %d %d\n" % tuple(t + 1) for t in s.darrays[1].data)
PYEOF
  "$SHARED/tools/param-eval" "$T/o/white.obj" "$T/o/sphere.obj" --json >"$T/o/eval.json" 2>"$T/log/eval" ||
    fail "param-eval failed: $(cat "$T/log/eval")"
  $PY - "$T/o/eval.json" <<'PYEOF' || fail "fsaverage5 misses issue 19's bounds"
import json, sys
j = json.load(open(sys.argv[1]))
print("folds", j["folds"], "mean|r-1|", j["r_mean_abs_dev"], "vertex|log r|", j["vertex_logr_mean_abs"])
assert j["folds"] == 0 and j["r_mean_abs_dev"] <= 0.02
PYEOF
  ;;
workbench)
  # Connectome Workbench reads our sphere: its vertex areas agree with our distortion file (both
  # sides' vertex areas by wb_command), and resampling the white surface from our sphere onto our
  # sphere gives the white surface back.
  # The surface: fsaverage5's right white surface, or without ../shared data/ellipsoid.obj as GIfTI.
  need_nibabel
  need_wb
  if [ -f "$FS5/white_right.gii.gz" ]; then
    gzip -dc "$FS5/white_right.gii.gz" >"$T/in/white.surf.gii" || fail "cannot inflate white_right.gii.gz"
  else
    $PY - "$SRC/data/ellipsoid.obj" "$T/in/white.surf.gii" <<'PYEOF' || fail "nibabel could not write the input"
import sys, numpy as np, nibabel as nib
V, F = [], []
for l in open(sys.argv[1]):
    t = l.split()
    if t and t[0] == "v": V.append([float(x) for x in t[1:4]])
    if t and t[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
pts = nib.gifti.GiftiDataArray(np.array(V, dtype=np.float32), intent="NIFTI_INTENT_POINTSET",
                               meta={"AnatomicalStructurePrimary": "CortexLeft"})
tri = nib.gifti.GiftiDataArray(np.array(F, dtype=np.int32), intent="NIFTI_INTENT_TRIANGLE")
nib.save(nib.gifti.GiftiImage(darrays=[pts, tri]), sys.argv[2])
PYEOF
  fi
  run sphere "$T/in/white.surf.gii" "$T/o/rh.sphere.surf.gii" --radius 100 --quiet --distortion "$T/o/d.shape.gii"
  expect_status 0
  export QT_QPA_PLATFORM=offscreen
  for s in white:"$T/in/white.surf.gii" sphere:"$T/o/rh.sphere.surf.gii"; do
    wb_command -surface-vertex-areas "${s#*:}" "$T/o/${s%%:*}.func.gii" >"$T/log/wb" 2>&1 ||
      fail "wb_command -surface-vertex-areas ${s%%:*}: $(head -c 400 "$T/log/wb")"
  done
  wb_command -surface-resample "$T/in/white.surf.gii" "$T/o/rh.sphere.surf.gii" "$T/o/rh.sphere.surf.gii" BARYCENTRIC \
    "$T/o/res.surf.gii" >"$T/log/wb" 2>&1 || fail "wb_command -surface-resample: $(head -c 400 "$T/log/wb")"
  $PY - "$T/o" "$T/in/white.surf.gii" <<'PYEOF' || fail "Workbench disagrees"
import sys, numpy as np, nibabel as nib
o = sys.argv[1]
a = nib.load(o + "/sphere.func.gii").darrays[0].data.astype(float)
b = nib.load(o + "/white.func.gii").darrays[0].data.astype(float)
d = nib.load(o + "/d.shape.gii").darrays[0].data
diff = np.abs(np.log2((a / a.sum()) / (b / b.sum())) - d).max()
res = np.abs(nib.load(o + "/res.surf.gii").darrays[0].data - nib.load(sys.argv[2]).darrays[0].data).max()
print("wb vertex areas vs our distortion: max diff %.3g; resampled white off by %.3g mm" % (diff, res))
assert diff < 1e-4 and res < 1e-3
PYEOF
  ;;
sample_sulc)
  # The worked example's last step: fsaverage5's sulc on a 64 x 32 equal-area grid through our
  # radius-100 sphere; every cell's value within sulc's range, both signs present.
  need_nibabel
  need_fs5
  run sphere "$FS5/white_right.gii.gz" "$T/o/rh.sphere.gii" --radius 100 --quiet
  expect_status 0
  run sample "$FS5/white_right.gii.gz" --map "$T/o/rh.sphere.gii" --grid 64x32 "$T/o/sulc.npy" \
    --attr "$FS5/sulc_right.gii.gz" --quiet
  expect_status 0
  $PY - "$T/o/sulc.npy" "$FS5/sulc_right.gii.gz" <<'PYEOF' || fail "the sulc grid is wrong"
import sys, numpy as np, nibabel as nib
s, v = np.load(sys.argv[1]), nib.load(sys.argv[2]).darrays[0].data
assert s.shape == (32, 64, 4), s.shape
c = s[..., 3]
assert c.min() >= v.min() - 1e-6 and c.max() <= v.max() + 1e-6 and c.min() < 0 < c.max()
print("sulc grid mean %.4f (vertex mean %.4f)" % (c.mean(), v.mean()))
PYEOF
  # texture --bake takes the GIfTI values too, and a curv file of them (written by --distortion's writer).
  run texture "$FS5/white_right.gii.gz" --map "$T/o/rh.sphere.gii" "$T/o/tex.obj" --bake "$FS5/sulc_right.gii.gz" \
    --image "$T/o/tex.png" --size 64x32 --quiet --distortion "$T/o/tex.distortion"
  expect_status 0
  [ -s "$T/o/tex.png" ] && [ -s "$T/o/tex.distortion" ] || fail "texture wrote no image or no distortion file"
  run texture "$FS5/white_right.gii.gz" --map "$T/o/rh.sphere.gii" "$T/o/tex2.obj" --bake "$T/o/tex.distortion" \
    --image "$T/o/tex2.png" --size 64x32 --quiet
  expect_status 0
  ;;
planar)
  # The planar commands: --distortion as .shape.gii (shares add up: sum 2^d * surface share = 1),
  # GIfTI output with GeometricType Flat, and an extension-less OUT in the input's format (OBJ).
  need_nibabel
  IN=$(stage "$SRC/data/disk_bump.obj")
  run disk "$IN" "$T/o/flat.gii" --quiet --distortion "$T/o/d.shape.gii"
  expect_status 0
  run disk "$IN" "$T/o/flat" --quiet
  expect_status 0
  grep -q '^v ' "$T/o/flat" || fail "an extension-less OUT of an OBJ input is not OBJ"
  $PY - "$IN" "$T/o" <<'PYEOF' || fail "planar distortion or GIfTI wrong"
import sys, numpy as np, nibabel as nib
V, F = [], []
for l in open(sys.argv[1]):
    t = l.split()
    if t and t[0] == "v": V.append([float(x) for x in t[1:4]])
    if t and t[0] == "f": F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
X, F = np.array(V), np.array(F)
g = nib.load(sys.argv[2] + "/flat.gii")
assert g.darrays[0].meta["GeometricType"] == "Flat" and np.abs(g.darrays[0].data[:, 2]).max() == 0
A = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
c = np.bincount(F.ravel(), np.repeat(A / 3, 3), len(X)); c /= c.sum()
d = nib.load(sys.argv[2] + "/d.shape.gii").darrays[0].data.astype(float)
print("sum of map shares", (2 ** d * c).sum())
assert abs((2 ** d * c).sum() - 1) < 1e-5
PYEOF
  ;;
*) fail "unknown case $1" ;;
esac
exit 0

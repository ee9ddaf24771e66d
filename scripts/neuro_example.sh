#!/usr/bin/env bash
# neuro_example.sh - the worked example of docs/neuro.md, with its figures measured: fsaverage5's right
# white surface (../shared/neuro/fsaverage5) to an authalic sphere of radius 100 in GIfTI and
# FreeSurfer form, its distortion files, an equal-area grid of sulc, then the distortion of our sphere
# and of FreeSurfer's own (sphere_right) measured by ../shared/tools/param-eval, and Connectome
# Workbench's vertex areas on our sphere against our distortion file.
# usage: scripts/neuro_example.sh [BUILD_DIR (default build)] [OUT_DIR (default BUILD_DIR/neuro_example)]
# Needs /usr/bin/python3 with nibabel (python3-nibabel) and, for the last figure, wb_command.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/neuro_example}
fs5=$root/../shared/neuro/fsaverage5
eval=$root/../shared/tools/param-eval
PY=/usr/bin/python3
[ -f "$fs5/white_right.gii.gz" ] || { echo "neuro_example.sh: $fs5 is absent" >&2; exit 77; }
mkdir -p "$out"
cd "$out"
A=$build/authalic
W=$fs5/white_right.gii.gz

set -x
"$A" sphere "$W" rh.sphere.authalic.surf.gii --radius 100 --distortion rh.distortion.shape.gii --report rh.sphere.json
"$A" sphere "$W" rh.sphere.authalic --format freesurfer --radius 100 --distortion rh.distortion --quiet
"$A" sample "$W" --map rh.sphere.authalic.surf.gii --grid 128x64 rh.sulc.npy --attr "$fs5/sulc_right.gii.gz" \
  --report rh.sulc.json --quiet
# The same grid through FreeSurfer's own sphere (radius 100, not area-preserving), for comparison.
"$A" sample "$W" --map "$fs5/sphere_right.gii.gz" --grid 128x64 fs.sulc.npy --attr "$fs5/sulc_right.gii.gz" \
  --report fs.sulc.json --quiet
set +x

# param-eval reads OBJ: the white surface, our sphere and FreeSurfer's, each sphere scaled to radius 1.
$PY - "$W" rh.sphere.authalic "$fs5/sphere_right.gii.gz" <<'PYEOF'
import sys, numpy as np, nibabel as nib, nibabel.freesurfer as fs
w = nib.load(sys.argv[1]); F = w.darrays[1].data
def obj(name, V):
    with open(name, "w") as f:
        f.writelines("v %.9g %.9g %.9g\n" % tuple(p) for p in V)
        f.writelines("f %d %d %d\n" % tuple(t + 1) for t in F)
obj("white.obj", w.darrays[0].data.astype(float))
v, f = fs.read_geometry(sys.argv[2]); assert (f == F).all()
obj("ours.obj", v / np.linalg.norm(v, axis=1)[:, None])
s = nib.load(sys.argv[3]); assert (s.darrays[1].data == F).all()
P = s.darrays[0].data.astype(float)
obj("freesurfer.obj", P / np.linalg.norm(P, axis=1)[:, None])
PYEOF
for m in ours freesurfer; do
  "$eval" white.obj "$m.obj" --json >"eval_$m.json"
done
$PY - <<'PYEOF'
import json, numpy as np, nibabel as nib, nibabel.freesurfer as fs
for m in ("ours", "freesurfer"):
    j = json.load(open("eval_%s.json" % m))
    print("%-10s folds %d  per-face mean|r-1| %.4f  std/mean r %.4f  vertex mean|log r| %.5f  mean |Upsilon| %.4f"
          "  mean Lambda %.4f" % (m, j["folds"], j["r_mean_abs_dev"], j["r_cv"], j["vertex_logr_mean_abs"],
                                   j["upsilon_mean_abs"], j["lambda_mean"]))
d = fs.read_morph_data("rh.distortion"); g = nib.load("rh.distortion.shape.gii").darrays[0].data
print("distortion (log2 vertex share ratio): mean |d| %.5f, max |d| %.4f, curv = shape.gii to %.1g"
      % (np.abs(d).mean(), np.abs(d).max(), np.abs(d - g).max()))
for name in ("rh", "fs"):
    s = np.load(name + ".sulc.npy"); r = json.load(open(name + ".sulc.json"))
    print("sulc grid %s through %-10s: cell mean sulc %.4f; surface area of the cells: std/mean %.4f, min %.3f and"
          " max %.3f of the mean" % (s.shape, "ours" if name == "rh" else "FreeSurfer", s[..., 3].mean(),
                                      r["cell_area_cv"], r["cell_area_min_rel"], r["cell_area_max_rel"]))
PYEOF
if command -v wb_command >/dev/null 2>&1; then
  export QT_QPA_PLATFORM=offscreen
  gzip -dc "$W" >white.surf.gii
  wb_command -surface-vertex-areas rh.sphere.authalic.surf.gii wb_sphere_areas.func.gii
  wb_command -surface-vertex-areas white.surf.gii wb_white_areas.func.gii
  wb_command -surface-resample white.surf.gii rh.sphere.authalic.surf.gii rh.sphere.authalic.surf.gii BARYCENTRIC \
    white_resampled.surf.gii
  $PY - <<'PYEOF'
import numpy as np, nibabel as nib
a = nib.load("wb_sphere_areas.func.gii").darrays[0].data.astype(float)
b = nib.load("wb_white_areas.func.gii").darrays[0].data.astype(float)
d = nib.load("rh.distortion.shape.gii").darrays[0].data
r = np.abs(nib.load("white_resampled.surf.gii").darrays[0].data - nib.load("white.surf.gii").darrays[0].data).max()
print("Workbench: sphere area %.1f (4 pi 100^2 = %.1f); log2 of its vertex share ratio vs ours: max diff %.2g;"
      " white resampled through our sphere off by %.2g mm" % (a.sum(), 4e4 * np.pi,
      np.abs(np.log2((a / a.sum()) / (b / b.sum())) - d).max(), r))
PYEOF
fi

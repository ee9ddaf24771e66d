"""test_atlas.py - authalic.atlas: the atlas of any genus through the binding. On the generated double
torus (data/genus2.obj) it is equal area (the flow's per-face error at most 0.02), its vt lie in [0,1]^2, no
vt triangle is turned over, both sides of every edge have one length, the cones keep Gauss-Bonnet, quarter
cones are multiples of 90 degrees, the result equals the program's (`authalic atlas`) bit for bit; flipped faces are re-oriented
with a warning; bad cones and a Moebius strip are refused."""
import math
import os
import subprocess
import warnings

import numpy as np
import pytest

import authalic
from conftest import DATA, ROOT, cli

G2 = os.path.join(DATA, "genus2.obj")


def check_atlas(F, VT, FT):
    assert VT.min() >= 0 and VT.max() <= 1
    a, b, c = VT[FT[:, 0]], VT[FT[:, 1]], VT[FT[:, 2]]
    area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    assert area.min() > 0
    side, worst = {}, 0.0
    for f in range(F.shape[0]):
        for k in range(3):
            i, j = F[f, k], F[f, (k + 1) % 3]
            L = float(np.linalg.norm(VT[FT[f, k]] - VT[FT[f, (k + 1) % 3]]))
            key = (min(i, j), max(i, j))
            if key in side:
                worst = max(worst, abs(side[key] - L))
            else:
                side[key] = L
    assert worst <= 1e-9
    return area.sum()


def test_genus2():
    V, F = authalic.read_mesh(G2)
    VT, FT, info = authalic.atlas(V, F)
    area = check_atlas(F, VT, FT)
    assert info["equal_area"] is True and info["flow"]["face_error"] <= 0.02 < info["flow"]["face_error_start"]
    assert info["genus"] == 2 and info["folds"] == 0 and info["overlap_texels"] == 0
    assert abs(info["coverage"] - area) < 1e-6  # the report's six decimals
    kappa = sum(2 * math.pi - c["angle"] for c in info["cones"])
    assert abs(kappa - 2 * math.pi * (2 - 2 * 2)) < 1e-9
    VT, FT, info = authalic.atlas(V, F, quarter=True)
    check_atlas(F, VT, FT)
    assert all(abs(c["angle_deg"] / 90 - round(c["angle_deg"] / 90)) < 1e-9 for c in info["cones"])


def test_same_as_program(tmp_path):
    out = str(tmp_path / "a.obj")
    r = subprocess.run([cli(), "atlas", G2, out, "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    V, F = authalic.read_mesh(G2)
    VT, FT, _ = authalic.atlas(V, F)
    mine = str(tmp_path / "b.obj")
    authalic.write_mesh(mine, V, F, vt=VT, Ft=FT)
    assert open(out).read() == open(mine).read()


def test_reoriented_and_refused():
    V, F = authalic.read_mesh(G2)
    F2 = F.copy()
    F2[[3, 50]] = F2[[3, 50]][:, [0, 2, 1]]
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        VT, FT, info = authalic.atlas(V, F2)
    assert any("re-oriented 2 of 1600 faces" in str(x.message) for x in w)
    check_atlas(F, VT, FT)
    with pytest.raises(authalic.BadInputError, match="Gauss-Bonnet"):
        authalic.atlas(V, F, cones=[(0, 90)])
    with pytest.raises(authalic.BadInputError, match="max_cones"):
        authalic.atlas(V, F, max_cones=0)
    M = os.path.join(ROOT, "tests", "cli", "bad", "moebius.obj")
    Vm, Fm = authalic.read_mesh(M)
    with pytest.raises(authalic.BadInputError, match=r"non-orientable.*edge \(4, 13\)"):
        authalic.atlas(Vm, Fm)

"""test_torus.py - authalic.torus: the flat-torus map of closed genus-1 meshes through the binding.
Its per-corner vt are seamless (across every edge the two faces' vt differ by one lattice vector at
both ends), positive, of total area 1, on a lattice of determinant 1; the flow brings the per-face
error below the start's; the result equals the program's map byte for byte (OBJ written by
write_mesh with vt/Ft, and `python -m authalic torus`); wrong topologies and options are refused."""
import os
import subprocess
import sys

import numpy as np
import pytest

import authalic
from conftest import DATA, ROOT, cli, shared_mesh

R3 = os.path.join(DATA, "torus_r3.obj")


def seam_error(F, VT, FT, L):
    """The largest deviation from seamlessness: for each directed edge (i, j) of face f and its twin
    (j, i) of face g, vt_f(i) - vt_g(i) and vt_f(j) - vt_g(j) must be equal and a lattice vector."""
    twin = {}
    for f in range(F.shape[0]):
        for k in range(3):
            twin[(F[f, k], F[f, (k + 1) % 3])] = (FT[f, k], FT[f, (k + 1) % 3])
    Linv = np.linalg.inv(np.asarray(L).T)
    worst = 0.0
    for (i, j), (ti, tj) in twin.items():
        tj2, ti2 = twin[(j, i)]
        di, dj = VT[ti] - VT[ti2], VT[tj] - VT[tj2]
        n = Linv @ di
        worst = max(worst, np.abs(di - dj).max(), np.abs(n - np.round(n)).max())
    return worst


def areas(VT, FT):
    p, q, r = VT[FT[:, 0]], VT[FT[:, 1]], VT[FT[:, 2]]
    return 0.5 * ((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))


@pytest.mark.parametrize("lattice", ["conformal", "square"])
def test_seamless_equal_area_map(lattice):
    V, F = authalic.read_mesh(R3)
    VT, FT, info = authalic.torus(V, F, lattice=lattice)
    L = np.array(info["lattice"], dtype=float)
    assert VT.shape[1] == 2 and VT.shape[0] >= V.shape[0] and FT.shape == F.shape
    assert abs(np.linalg.det(L) - 1) <= 1e-12
    if lattice == "square":
        assert np.array_equal(L, np.eye(2))
    A = areas(VT, FT)
    assert A.min() > 0 and abs(A.sum() - 1) <= 1e-9
    assert seam_error(F, VT, FT, L) <= 1e-9
    m = info["metrics"]
    assert m["folds"] == 0 and info["converged"] and info["steps"] >= 1
    assert m["r_mean_abs_dev"] < 0.5 * info["initial_metrics"]["r_mean_abs_dev"]
    # The binding's metrics of the same cut mesh agree with the report's.
    X = np.repeat(np.zeros((1, 3)), VT.shape[0], axis=0)
    X[FT.reshape(-1)] = V[F.reshape(-1)]
    P = np.hstack([VT, np.zeros((VT.shape[0], 1))])
    mine = authalic.metrics(X, FT, P, domain="plane")
    assert abs(mine["r_mean_abs_dev"] - m["r_mean_abs_dev"]) <= 1e-12


def test_map_result_and_init_only():
    V, F = authalic.read_mesh(R3)
    r = authalic.map_mesh(V, F, "torus", init_only=True)
    assert r.uv is None and r.lattice.shape == (2, 2) and r.vt.shape[1] == 2 and r.Ft.shape == F.shape
    assert r.info["steps"] == 0 and r.init_method == "cotan"
    assert np.allclose(r.lattice, np.array(r.info["lattice"]), rtol=0, atol=0)
    d = authalic.map_mesh(*authalic.read_mesh(os.path.join(DATA, "bumpy_star.obj")), "sphere", init_only=True)
    assert d.vt is None and d.Ft is None and d.lattice is None


def test_refused():
    V, F = authalic.read_mesh(R3)
    with pytest.raises(authalic.BadInputError, match="genus 1"):
        authalic.sphere(V, F)
    with pytest.raises(authalic.BadInputError, match="genus 0 .*closed genus-1"):
        authalic.torus(*authalic.read_mesh(os.path.join(DATA, "ellipsoid.obj")))
    with pytest.raises(authalic.BadInputError, match="lattice 'hex'"):
        authalic.torus(V, F, lattice="hex")
    with pytest.raises(authalic.BadInputError, match="lattice: applies to the torus map only"):
        authalic.map_mesh(V, F, "disk", lattice="square")
    with pytest.raises(TypeError):
        authalic.disk(V, F, lattice="square")


def test_write_mesh_vt(tmp_path):
    V, F = authalic.read_mesh(R3)
    VT, FT, _ = authalic.torus(V, F, init_only=True)
    out = tmp_path / "t.obj"
    authalic.write_mesh(out, V, F, vt=VT, Ft=FT)
    lines = out.read_text().splitlines()
    assert sum(ln.startswith("vt ") for ln in lines) == VT.shape[0]
    f0 = next(ln for ln in lines if ln.startswith("f "))
    assert f0.split()[1:] == ["%d/%d" % (F[0, k] + 1, FT[0, k] + 1) for k in range(3)]
    V2, F2 = authalic.read_mesh(out)
    assert np.array_equal(V2, V) and np.array_equal(F2, F)
    for kw, words in [({"vt": VT}, "go together"), ({"vt": VT, "Ft": FT, "uv": V[:, :2]}, "not both"),
                      ({"vt": VT, "Ft": FT[:-1]}, "Ft: %d rows" % (F.shape[0] - 1)),
                      ({"vt": VT[:-5], "Ft": FT}, "outside vt")]:
        with pytest.raises(authalic.BadInputError, match=words):
            authalic.write_mesh(tmp_path / "bad.obj", V, F, **kw)
        assert not (tmp_path / "bad.obj").exists()


@pytest.mark.parametrize("name", ["torus_r3.obj", "bob.obj"])
def test_same_map_as_the_program(tmp_path, name):
    src = R3 if name == "torus_r3.obj" else shared_mesh(name)
    prog = cli()
    subprocess.run([prog, "torus", src, tmp_path / "c.obj", "--quiet"], check=True)
    V, F = authalic.read_mesh(src)
    VT, FT, _ = authalic.torus(V, F)
    authalic.write_mesh(tmp_path / "b.obj", V, F, vt=VT, Ft=FT)
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    p = subprocess.run([sys.executable, "-m", "authalic", "torus", src, tmp_path / "m.obj", "--quiet"], env=env,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    c = (tmp_path / "c.obj").read_bytes()
    assert (tmp_path / "b.obj").read_bytes() == c and (tmp_path / "m.obj").read_bytes() == c
    p = subprocess.run([sys.executable, "-m", "authalic", "torus", src, tmp_path / "m.off"], env=env,
                       capture_output=True, text=True)
    assert p.returncode == 2 and "written as .obj" in p.stderr and not (tmp_path / "m.off").exists()

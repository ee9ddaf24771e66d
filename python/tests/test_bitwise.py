"""test_bitwise.py - authalic.sphere / disk give the very map the `authalic` program writes (read
back from its 17-digit OBJ: exact), with the package's default thread settings."""
import os
import subprocess

import numpy as np
import pytest

import authalic
from conftest import DATA, QUICK, cli, shared_mesh


def program_map(tmp_path, cmd, src):
    out = tmp_path / ("cli_" + os.path.basename(src) + ".obj")
    r = subprocess.run([cli(), cmd, src, out, "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return authalic.read_mesh(out)[0], out


@pytest.mark.parametrize("cmd, name", [("sphere", "bumpy_star.obj"), ("disk", "disk_bump.obj"),
                                       ("sphere", "bunny.obj"), ("sphere", "spot.obj"), ("disk", "brain_disk.obj")])
def test_same_map_as_the_program(tmp_path, cmd, name):
    if os.path.exists(os.path.join(DATA, name)):
        src = os.path.join(DATA, name)
    else:
        if QUICK:
            pytest.skip("the shared meshes are mapped in the normal build only (AUTHALIC_TEST_QUICK)")
        src = shared_mesh(name)
    P_cli, out = program_map(tmp_path, cmd, src)
    V, F = authalic.read_mesh(src)
    if cmd == "sphere":
        P, info = authalic.sphere(V, F)
        assert np.array_equal(P, P_cli)
        authalic.write_mesh(tmp_path / "py.obj", P, F)
    else:
        P, info = authalic.disk(V, F)
        assert np.array_equal(P, P_cli[:, :2]) and not P_cli[:, 2].any()
        r = authalic.map_mesh(V, F, "disk")
        authalic.write_mesh(tmp_path / "py.obj", r.P, r.F, uv=r.uv)
    assert info["folds"] == 0
    assert (tmp_path / "py.obj").read_bytes() == out.read_bytes()


def test_spherical_areas_same_as_the_program(tmp_path):
    """spherical_areas=True is `authalic sphere --spherical-areas` (the texture command's map): the same
    map to the bit, and its spherical figures, which the keyword is for, below the chord ones on a
    mesh with long, thin limbs (data/limbs8.obj: spherical 0.012 / 0.0036, chord 0.32 / 0.22)."""
    src = os.path.join(DATA, "limbs8.obj")
    out = tmp_path / "cli.obj"
    r = subprocess.run([cli(), "sphere", src, out, "--spherical-areas", "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    V, F = authalic.read_mesh(src)
    with pytest.warns(authalic.AuthalicWarning):
        P, info = authalic.sphere(V, F, spherical_areas=True)
    assert np.array_equal(P, authalic.read_mesh(out)[0])
    m = info["metrics"]
    assert m["folds"] == 0
    assert m["sph_r_mean_abs_dev"] <= 0.03 and m["sph_vertex_logr_mean_abs"] <= 0.01
    assert m["sph_r_mean_abs_dev"] < 0.5 * m["r_mean_abs_dev"]
    # The default map is a different one, made for the chord triangles.
    with pytest.warns(authalic.AuthalicWarning):
        P2, info2 = authalic.sphere(V, F)
    assert info2["metrics"]["r_mean_abs_dev"] < m["r_mean_abs_dev"]

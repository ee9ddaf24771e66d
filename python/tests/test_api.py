"""test_api.py - the package's functions: results and their quality, info, metrics, files, errors,
dtypes and memory orders, inputs untouched, results owning their memory, progress and warnings."""
import os
import warnings

import numpy as np
import pytest

import authalic
from conftest import DATA


# ---------------------------------------------------------------- maps and their quality

def test_sphere_on_unit_sphere_without_folds(star, star_map):
    V, F = star
    S, info = star_map
    assert S.shape == V.shape and S.dtype == np.float64
    assert np.abs(np.linalg.norm(S, axis=1) - 1).max() < 1e-12
    assert info["folds"] == 0 and info["metrics"]["folds"] == 0
    assert info["converged"] is True
    assert info["metrics"]["vertex_logr_mean_abs"] <= 2e-3
    assert info["command"] == "sphere" and info["V"] == V.shape[0] and info["F"] == F.shape[0]
    assert info["version"] == authalic.version()


def test_sphere_multilevel_start(star):
    """start="multilevel" (the coarse-to-fine start): a fold-free map on the unit sphere within issue 39's
    bounds, and info says which start made it (the default: the conformal one)."""
    V, F = star
    S, info = authalic.sphere(V, F, start="multilevel")
    assert info["start"] == "multilevel" and info["folds"] == 0
    assert np.abs(np.linalg.norm(S, axis=1) - 1).max() < 1e-12
    assert info["metrics"]["r_mean_abs_dev"] <= 0.03 and info["metrics"]["vertex_logr_mean_abs"] <= 0.01


def test_info_has_the_reports_keys(star_map):
    info = star_map[1]
    for k in ("tool", "version", "command", "input", "output", "V", "F", "steps", "converged", "folds", "time",
              "metrics", "initial_metrics", "convergence", "warnings"):
        assert k in info, k
    assert info["input"] is None and info["output"] is None and info["start"] == "conformal"
    assert set(info["time"]) == {"validate", "init", "flow", "metrics", "total"}
    assert len(info["convergence"]["err"]) == info["steps"] + 1


def test_metrics_equal_the_reports(star, star_map):
    V, F = star
    S, info = star_map
    m = authalic.metrics(V, F, S, domain="sphere")
    assert m == info["metrics"]  # same keys, same doubles (the report writes them exactly)
    m2 = authalic.metrics(V, F, S, per_face=True)
    assert m2["upsilon"].shape == (F.shape[0],) and m2["lambda"].shape == (F.shape[0],)
    assert np.isclose(np.mean(np.abs(m2["upsilon"])), m["upsilon_mean_abs"], rtol=1e-12)


def test_metrics_domain_detected():
    """Without domain=, metrics() takes the domain as param-eval does: a planar map (two columns, or z
    all 0) in the plane (it was measured on the sphere: every face folded), a sphere map on the sphere."""
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    UV, info = authalic.disk(V, F)
    P3 = np.column_stack([UV, np.zeros(UV.shape[0])])
    for P in (UV, P3):
        m = authalic.metrics(V, F, P)
        assert m["domain"] == "plane" and m["folds"] == 0 and m == authalic.metrics(V, F, P, domain="plane")
    assert authalic.metrics(V, F, P3, domain="sphere")["folds"] > 0  # the old default's reading


def test_disk_annulus_square():
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    UV, info = authalic.disk(V, F)
    assert UV.shape == (V.shape[0], 2) and info["command"] == "disk" and info["folds"] == 0
    assert np.linalg.norm(UV, axis=1).max() <= 1 + 1e-12
    assert authalic.metrics(V, F, UV, domain="disk") == info["metrics"]
    UVf, info_f = authalic.disk(V, F, boundary="fixed")
    assert info_f["folds"] == 0

    Sq, info = authalic.square(V, F, steps=5)
    assert info["command"] == "square" and Sq.min() >= -1e-12 and Sq.max() <= 1 + 1e-12
    r = authalic.map_mesh(V, F, "square", steps=5)
    assert np.array_equal(r.P[:, :2], Sq) and np.array_equal(r.uv, Sq)
    assert r.nv_in == V.shape[0] and len(r.corners) == 4

    V, F = authalic.read_mesh(os.path.join(DATA, "annulus_bump.obj"))
    UV, info = authalic.annulus(V, F, inner_radius=0.3, steps=5)
    rad = np.linalg.norm(UV, axis=1)
    assert info["folds"] == 0 and rad.max() <= 1 + 1e-12 and abs(rad.min() - 0.3) < 1e-9


def test_map_mesh_result(star):
    V, F = star
    r = authalic.map_mesh(V, F, "sphere", steps=3)
    assert r.uv is None and r.P0.shape == V.shape and np.array_equal(r.X, V) and np.array_equal(r.F, F)
    assert r.status in ("AU_OK", "AU_W_NOT_CONVERGED") and "sphere" in repr(r)


def test_options_reach_the_library(star):
    V, F = star
    _, a = authalic.sphere(V, F, steps=2, tol=0)
    assert a["steps"] <= 2
    _, b = authalic.sphere(V, F, init_only=True)
    assert b["steps"] == 0 and "initial_metrics" not in b
    _, c = authalic.sphere(V, F, angles=2)
    assert "angle_from" in c["convergence"]
    d = np.linspace(1, 2, V.shape[0])
    S, info = authalic.sphere(V, F, density=d)
    assert info["folds"] == 0
    Sf, _ = authalic.sphere(V, F, density=np.ones(F.shape[0]))
    assert Sf.shape == V.shape


# ---------------------------------------------------------------- files

def test_read_write_round_trip(tmp_path, star, star_map):
    V, F = star
    S = star_map[0]
    for ext in ("obj", "off", "ply"):
        p = str(tmp_path / ("s." + ext))
        authalic.write_mesh(p, S, F)
        S2, F2 = authalic.read_mesh(p)
        assert np.array_equal(S2, S) and np.array_equal(F2, F) and F2.dtype == np.int32
    p = tmp_path / "uv.obj"
    authalic.write_mesh(p, S[:, :2], F, uv=(S[:, :2] + 1) / 2)  # os.PathLike, 2 columns
    text = p.read_text()
    assert text.count("\nvt ") == V.shape[0]
    assert np.array_equal(authalic.read_mesh(p)[0][:, 2], np.zeros(V.shape[0]))


# ---------------------------------------------------------------- errors

def test_bad_input_errors(tmp_path, star):
    V, F = star
    with pytest.raises(authalic.BadInputError) as e:
        authalic.read_mesh(str(tmp_path / "missing.obj"))
    assert isinstance(e.value, ValueError) and isinstance(e.value, authalic.Error)
    assert e.value.name == "AU_E_IO" and "missing.obj" in str(e.value)

    Vd, Fd = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    with pytest.raises(authalic.BadInputError) as e:
        authalic.sphere(Vd, Fd)
    assert e.value.status <= -100 and "\n" not in str(e.value) and str(e.value)

    # Three triangles on one edge.
    Vn = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], float)
    Fn = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    with pytest.raises(authalic.BadInputError) as e:
        authalic.sphere(Vn, Fn)
    assert e.value.name == "AU_E_NONMANIFOLD_EDGE" and "edge" in str(e.value)

    Vbad = V.copy()
    Vbad[3, 1] = np.nan
    with pytest.raises(authalic.BadInputError, match="finite"):
        authalic.sphere(Vbad, F)
    with pytest.raises(authalic.BadInputError, match="out of range"):
        authalic.sphere(V, np.where(F == 0, 2 ** 40, F))  # int64 beyond int32: refused, not wrapped
    with pytest.raises(authalic.BadInputError, match="density"):
        authalic.sphere(V, F, density=-np.ones(V.shape[0]))
    with pytest.raises(authalic.BadInputError, match="density"):
        authalic.sphere(V, F, density=np.ones(7))


@pytest.mark.parametrize("call, match", [
    (lambda V, F: authalic.sphere(V[:, :2], F), "shape"),
    (lambda V, F: authalic.sphere(V, F[:, :2]), "shape"),
    (lambda V, F: authalic.sphere(V.astype(str), F), "dtype"),
    (lambda V, F: authalic.sphere(V, F + 0.5), "whole"),
    (lambda V, F: authalic.sphere(V, F, steps=0), "steps"),
    (lambda V, F: authalic.sphere(V, F, steps=513), "steps"),
    (lambda V, F: authalic.sphere(V, F, tol=-1), "tol"),
    (lambda V, F: authalic.sphere(V, F, angles=51), "angles"),
    (lambda V, F: authalic.sphere(V, F, restore_shapes=2), "restore_shapes"),
    (lambda V, F: authalic.sphere(V, F, init_only=True, steps=3), "init_only"),
    (lambda V, F: authalic.sphere(V, F, progress="yes"), "progress"),
    (lambda V, F: authalic.disk(V, F, boundary="glue"), "boundary"),
    (lambda V, F: authalic.annulus(V, F, inner_radius=1.5), "inner_radius"),
    (lambda V, F: authalic.annulus(V, F, outer_loop="left"), "outer_loop"),
    (lambda V, F: authalic.square(V, F, corners=[1, 2, 3]), "corners"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", corners=[1, 2, 3, 4]), "square"),
    (lambda V, F: authalic.map_mesh(V, F, "plane"), "target"),
    (lambda V, F: authalic.map_mesh(V, F, "torus"), "genus 0 .*closed genus-1"),
    (lambda V, F: authalic.metrics(V, F, V, domain="cube"), "domain"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_budget=3), "refine_mesh"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget=1), "refine_budget"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget=17), "refine_budget"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget="automatic"), "'auto'"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget=-1), "refine_budget"),
    (lambda V, F: authalic.map_mesh(V, F, "disk", refine_mesh=True), "sphere"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh="no"), "refine_mesh"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=True, density=np.ones(V.shape[0])), "density"),
    (lambda V, F: authalic.map_mesh(V, F, "disk", spherical_areas=True), "sphere"),
    (lambda V, F: authalic.sphere(V, F, spherical_areas="yes"), "spherical_areas"),
    (lambda V, F: authalic.sphere(V, F, spherical_areas=1), "spherical_areas"),
    (lambda V, F: authalic.sphere(V, F, balance="False"), "balance"),
    (lambda V, F: authalic.sphere(V, F, balance=0), "balance"),
    (lambda V, F: authalic.sphere(V, F, balance=np.array([0, 1])), "balance"),
    (lambda V, F: authalic.sphere(V, F, refine_faces="yes"), "refine_faces"),
    (lambda V, F: authalic.sphere(V, F, init_only="yes"), "init_only"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", refine_mesh=np.ones(2)), "refine_mesh"),
    (lambda V, F: authalic.sphere(V, F, spherical_areas=True, init_only=True), "init_only"),
    (lambda V, F: authalic.map_mesh(V, F, "sphere", spherical_areas=True, refine_mesh=True), "refine_mesh"),
    (lambda V, F: authalic.sphere(V, F, start="fancy"), "start"),
    (lambda V, F: authalic.sphere(V, F, start=1), "start"),
    (lambda V, F: authalic.map_mesh(V, F, "disk", start="multilevel"), "sphere"),
])
def test_bad_arguments(star, call, match):
    with pytest.raises(authalic.BadInputError, match=match):
        call(*star)


def test_refine_mesh():
    """refine_mesh=True on coil (a long coiled tail, issue 21): the refined mesh keeps the input's
    vertices and faces' count first, at most refine_budget x the faces, its new vertices where parent
    and parent_t say, the map on the unit sphere without folds and nearer equal area than unrefined."""
    V, F = authalic.read_mesh(os.path.join(DATA, "coil.obj"))
    with pytest.warns(authalic.AuthalicWarning):
        plain = authalic.map_mesh(V, F, "sphere")
        r = authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget=3)
    nv, nf = V.shape[0], F.shape[0]
    assert r.nv_in == nv and r.nf_in == nf and 2 * nf < r.F.shape[0] <= 3 * nf
    assert np.array_equal(r.X[:nv], V) and r.parent.shape == (r.X.shape[0] - nv, 2)
    a, b, t = r.parent[:, 0], r.parent[:, 1], r.parent_t
    assert np.all((a < np.arange(nv, r.X.shape[0])) & (b < np.arange(nv, r.X.shape[0])))
    assert np.allclose((1 - t)[:, None] * r.X[a] + t[:, None] * r.X[b], r.X[nv:], rtol=0, atol=1e-12)
    assert np.allclose(np.linalg.norm(r.P, axis=1), 1, rtol=0, atol=1e-12)
    m, m0 = authalic.metrics(r.X, r.F, r.P), authalic.metrics(V, F, plain.P)
    assert m["folds"] == 0
    assert m["r_mean_abs_dev"] < 0.5 * m0["r_mean_abs_dev"] and m["vertex_logr_mean_abs"] < 0.5 * m0["vertex_logr_mean_abs"]
    assert plain.parent is None and plain.parent_t is None


def test_refine_budget_auto():
    """refine_budget="auto" on limbs4 (four thin legs, issue 21): 2x meets per-face 0.02 and vertex 0.005
    there, so it is kept without trying 3x, and the warning says what was tried."""
    V, F = authalic.read_mesh(os.path.join(DATA, "limbs4.obj"))
    with pytest.warns(authalic.AuthalicWarning) as w:
        r = authalic.map_mesh(V, F, "sphere", refine_mesh=True, refine_budget="auto")
    said = [str(x.message) for x in w if "refine budget auto" in str(x.message)]
    assert len(said) == 1 and "2x: %d faces" % r.F.shape[0] in said[0] and "(kept)" in said[0], said
    assert "3x" not in said[0]
    assert F.shape[0] < r.F.shape[0] <= 2 * F.shape[0]
    m = authalic.metrics(r.X, r.F, r.P)
    assert m["folds"] == 0 and m["r_mean_abs_dev"] <= 0.02 and m["vertex_logr_mean_abs"] <= 0.005


def test_bad_option_from_the_library():
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    with pytest.raises(authalic.BadInputError) as e:
        authalic.square(V, F, corners=[0, 1, 2, 3])  # not on the boundary: the library says so
    assert e.value.name == "AU_E_ARG" and str(e.value).startswith("corners:")


def test_cancel_from_progress_is_an_error_not_bad_input(star):
    seen = []
    with pytest.raises(authalic.Error) as e:
        authalic.sphere(*star, progress=lambda k, n, err: seen.append(k) or k >= 2)
    assert e.value.name == "AU_E_CANCELLED" and not isinstance(e.value, ValueError)
    assert seen[-1] == 2


def test_exception_in_progress_is_raised(star):
    class Stop(Exception):
        pass

    def boom(k, n, err):
        raise Stop("from the callback")
    with pytest.raises(Stop):
        authalic.sphere(*star, progress=boom)


def test_progress_callable_and_bar(star, capsys):
    calls = []
    authalic.sphere(*star, progress=lambda k, n, e: calls.append((k, n, e)))
    assert calls and all(n >= k for k, n, _ in calls) and calls[0][1] == 60
    authalic.sphere(*star, steps=3, progress=True)
    assert "authalic" in capsys.readouterr().err


def test_warning_when_not_converged(star):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        _, info = authalic.sphere(*star, steps=1, tol=0)
    assert info["converged"] is False and info["warnings"]
    assert any(issubclass(x.category, authalic.AuthalicWarning) and "tolerance" in str(x.message) for x in w)


# ---------------------------------------------------------------- dtypes, orders, no mutation, ownership

def variants(V, F):
    """The same mesh in other dtypes and memory layouts."""
    big = np.zeros((V.shape[0], 5))
    big[:, 1:4] = V
    Fbig = np.zeros((F.shape[0] * 2, 3), np.int64)
    Fbig[::2] = F
    yield "fortran", np.asfortranarray(V), np.asfortranarray(F)
    yield "int64 faces", V, F.astype(np.int64)
    yield "uint16 faces", V, F.astype(np.uint16)
    yield "float faces", V, F.astype(np.float64)
    yield "column view", big[:, 1:4], F
    yield "strided faces", V, Fbig[::2]
    yield "read-only", ro(V), ro(F)
    yield "lists", V.tolist(), F.tolist()
    yield "longdouble", V.astype(np.longdouble), F


def ro(a):
    a = a.copy()
    a.flags.writeable = False
    return a


def test_dtypes_and_orders_give_the_same_map(star, star_map):
    V, F = star
    S = star_map[0]
    for name, Vx, Fx in variants(V, F):
        before = (np.array(Vx, copy=True), np.array(Fx, copy=True))
        Sx, _ = authalic.sphere(Vx, Fx)
        assert np.array_equal(Sx, S), name
        assert np.array_equal(np.asarray(Vx), before[0]) and np.array_equal(np.asarray(Fx), before[1]), name
    # float32 and integer coordinates convert too (another mesh, so only validity is checked).
    S32, info = authalic.sphere(V.astype(np.float32), F)
    assert info["folds"] == 0
    Vi = np.round(V * 1000).astype(np.int64)
    assert authalic.sphere(Vi, F)[1]["folds"] == 0


def test_inputs_untouched_and_results_own_memory(star):
    V, F = star
    V0, F0 = V.copy(), F.copy()
    d = np.linspace(1, 2, V.shape[0])
    d0 = d.copy()
    r = authalic.map_mesh(V, F, "sphere", density=d, steps=3)
    assert np.array_equal(V, V0) and np.array_equal(F, F0) and np.array_equal(d, d0)
    for a in (r.P, r.P0, r.X, r.F):
        assert a.flags.owndata and a.flags.writeable and a.flags.c_contiguous
        assert not np.shares_memory(a, V) and not np.shares_memory(a, F)
    S, _ = authalic.sphere(V, F, steps=2)
    assert S.flags.owndata
    UV, _ = authalic.disk(*authalic.read_mesh(os.path.join(DATA, "disk_bump.obj")), steps=2)
    assert UV.flags.owndata and UV.flags.c_contiguous


# ---------------------------------------------------------------- documentation

@pytest.mark.parametrize("name", authalic.__all__)
def test_every_public_name_is_documented(name):
    doc = getattr(authalic, name).__doc__
    assert doc and len(doc) > 80, name


def test_help_is_a_manual():
    doc = authalic.sphere.__doc__
    for word in ("steps", "tol", "density", "angles", "refine_faces", "progress", "Returns", "BadInputError",
                 "KeyboardInterrupt", "GIL"):
        assert word in doc, word
    for f in (authalic.disk, authalic.annulus, authalic.square):
        assert "boundary" in f.__doc__ and "Returns (UV, info)" in f.__doc__
    assert "OMP_THREAD_LIMIT" in authalic.__doc__

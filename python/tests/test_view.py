"""test_view.py - authalic.view: the page of a map through the binding. Its data block carries the
surface, the map and per-face log r = -Upsilon of authalic.metrics (the report's figures); a torus map
is found to tile by its own lattice; the page names no URL; a notebook gets it in an isolated frame;
bad maps are refused."""
import base64
import json
import os
import re

import numpy as np
import pytest

import authalic
from conftest import DATA


def page_data(html):
    assert not re.search(r"https?://", html, re.I)
    m = re.search(r'<script type="application/json" id="au-data">(.*?)</script>', html, re.S)
    return json.loads(m.group(1))


def test_sphere_page_has_the_reports_figures():
    V, F = authalic.read_mesh(os.path.join(DATA, "ellipsoid.obj"))
    r = authalic.map_mesh(V, F, "sphere", steps=3)
    v = authalic.view(result=r, attr=V[:, 2], attr_name="height", title="ellipsoid")
    d = page_data(v.html)
    assert d["kind"] == "sphere" and d["nf"] == F.shape[0] and d["attr"]["name"] == "height"
    m = r.info["metrics"]
    assert d["stats"]["folds"] == m["folds"] and d["stats"]["steps"] == r.info["steps"]
    assert abs(d["stats"]["per_face"] - m["r_mean_abs_dev"]) <= 1e-12
    ups = authalic.metrics(V, F, r.P, per_face=True)["upsilon"]
    logr = np.frombuffer(base64.b64decode(d["logr"]), dtype="<f4")
    assert np.allclose(logr, -ups, atol=1e-6)
    assert v._repr_html_().startswith("<iframe srcdoc=") and "<script" not in v._repr_html_()


def test_torus_page_tiles_by_the_lattice():
    V, F = authalic.read_mesh(os.path.join(DATA, "torus_r3.obj"))
    VT, FT, info = authalic.torus(V, F, steps=2)
    d = page_data(authalic.view(V, F, vt=VT, Ft=FT, info=info).html)
    assert d["kind"] == "torus" and d["Ft"] is not None
    # The page's lattice spans the map's: each of its vectors is a whole combination of the other's.
    L, M = np.array(info["lattice"]), np.array(d["lattice"])
    c = np.linalg.solve(L.T, M.T)
    assert np.allclose(c, np.rint(c), atol=1e-6) and abs(abs(np.linalg.det(np.rint(c))) - 1) < 1e-9


def test_planar_page_and_refusals():
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    r = authalic.map_mesh(V, F, "disk", steps=2)
    assert page_data(authalic.view(V, F, P=r.P[:, :2]).html)["kind"] == "plane"
    with pytest.raises(authalic.BadInputError):
        authalic.view(V, F)
    with pytest.raises(authalic.BadInputError):
        authalic.view(V, F, P=r.P, attr=np.zeros(3))
    with pytest.raises(authalic.BadInputError):
        authalic.view(V, F, P=r.P[:-1])

"""test_circles.py - authalic.circles (genus 0, any number of boundary loops onto a circle domain),
map_mesh's circles, square's aspect, and their bad keywords."""
import os

import numpy as np
import pytest

import authalic
from conftest import DATA


def test_circles_on_a_disk_with_three_holes():
    V, F = authalic.read_mesh(os.path.join(DATA, "holes3.obj"))
    UV, info = authalic.circles(V, F)
    m = info["metrics"]
    assert UV.shape == (V.shape[0], 2) and info["command"] == "circles" and info["folds"] == 0
    assert m["r_mean_abs_dev"] <= 0.02 and m["vertex_logr_mean_abs"] <= 0.005
    circles = info["circles"]
    assert len(circles) == 4 and sum(c["outer"] for c in circles) == 1
    # Every loop on its circle: the loop's first vertex here; all of them in tests/cli/circles.sh.
    for c in circles:
        p = UV[c["vertex"]]
        assert abs(np.hypot(*(p - c["center"])) - c["radius"]) < 1e-9
    r = authalic.map_mesh(V, F, "circles")
    assert np.array_equal(r.P[:, :2], UV) and r.circles.shape == (4, 3) and list(r.circle_vertex) == [c["vertex"] for c in circles]
    hole = next(c["vertex"] for c in circles if not c["outer"])
    _, info2 = authalic.circles(V, F, outer=hole, steps=3)
    assert any(c["outer"] and c["vertex"] == hole for c in info2["circles"])


def test_circles_of_one_loop_is_the_disk():
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    assert np.array_equal(authalic.circles(V, F, steps=3)[0], authalic.disk(V, F, steps=3)[0])


def test_square_aspect():
    V, F = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    S, info = authalic.square(V, F, steps=5)
    R, info_r = authalic.square(V, F, steps=5, aspect=(2, 1))
    assert np.allclose(R, S * [1, 0.5], rtol=0, atol=1e-15) and info_r["folds"] == 0
    assert abs(info_r["metrics"]["r_mean_abs_dev"] - info["metrics"]["r_mean_abs_dev"]) < 1e-9


@pytest.mark.parametrize("call, match", [
    (lambda V, F: authalic.circles(V, F, outer=-1), "outer"),
    (lambda V, F: authalic.circles(V, F, outer=0), "outer.*no boundary loop"),
    (lambda V, F: authalic.square(V, F, aspect=0), "aspect"),
    (lambda V, F: authalic.square(V, F, aspect=(1, -2)), "aspect"),
    (lambda V, F: authalic.map_mesh(V, F, "disk", outer=3), "outer: applies to the circles map only"),
])
def test_bad_keywords(call, match):
    V, F = authalic.read_mesh(os.path.join(DATA, "holes3.obj"))
    with pytest.raises(authalic.BadInputError, match=match):
        call(V, F)

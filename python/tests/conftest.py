"""conftest.py - where the tests find the package, the library, the program and the meshes.

The package is imported from python/ of this checkout (not an installed copy); the library is
$AUTHALIC_LIBRARY (ctest and `make test` point it at the build's libauthalic.so.1), else the
package's own search. The program is $AUTHALIC_CLI, else build/authalic. The shared meshes are in
$AUTHALIC_SHARED, else ../shared beside the checkout; tests that need them skip when absent.
"""
import os
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))

import authalic  # noqa: E402  (after the path, and before numpy: see the package docstring)
import numpy as np  # noqa: E402

DATA = os.path.join(ROOT, "data")
SHARED = os.environ.get("AUTHALIC_SHARED") or os.path.join(ROOT, "..", "shared")
CLI = os.environ.get("AUTHALIC_CLI") or os.path.join(ROOT, "build", "authalic")
# Set by the sanitizer build's ctest case: the big meshes there take minutes, the small ones stay.
QUICK = os.environ.get("AUTHALIC_TEST_QUICK") == "1"


def shared_mesh(name):
    """The path of a shared mesh, or a skip saying it is absent."""
    p = os.path.join(SHARED, "meshes", name)
    if not os.path.exists(p):
        pytest.skip("%s absent (no ../shared/meshes)" % name)
    return p


def cli():
    """The program's path, or a skip."""
    if not os.access(CLI, os.X_OK):
        pytest.skip("the authalic program is not built (%s)" % CLI)
    return CLI


def subdivide(V, F):
    """Midpoint subdivision: every triangle into four; the same surface, four times the faces."""
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(E, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    nv, nf = V.shape[0], F.shape[0]
    V2 = np.vstack([V, 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])])
    m01, m12, m20 = nv + inv[:nf], nv + inv[nf:2 * nf], nv + inv[2 * nf:]
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    F2 = np.concatenate([np.stack([a, m01, m20], 1), np.stack([m01, b, m12], 1), np.stack([m20, m12, c], 1),
                         np.stack([m01, m12, m20], 1)])
    return V2, F2.astype(np.int32)


@pytest.fixture(scope="session")
def star():
    """data/bumpy_star.obj: a closed genus-0 mesh of 2562 vertices, mapped in well under a second."""
    return authalic.read_mesh(os.path.join(DATA, "bumpy_star.obj"))


@pytest.fixture(scope="session")
def star_map(star):
    return authalic.sphere(*star)


@pytest.fixture(scope="session")
def disk_mesh():
    return authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))


def pytest_configure(config):
    # Maps cut short on purpose warn that the tolerance was not reached; the tests that care record them.
    config.addinivalue_line("filterwarnings", "ignore::authalic.AuthalicWarning")

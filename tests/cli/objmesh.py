"""objmesh.py - the OBJ reader of the end-to-end tests' Python checks (lib.sh puts tests/cli on
PYTHONPATH): `v` lines and the vertex index of each corner of `f` lines, as numpy arrays."""
import numpy as np


def load(path):
    """(V float64 (n, 3), F int (m, 3), 0-based) from the OBJ file path."""
    V, F = [], []
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if t and t[0] == "v":
                V.append([float(x) for x in t[1:4]])
            elif t and t[0] == "f":
                F.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
    return np.array(V, dtype=float), np.array(F, dtype=int)


def spherical_errors(X, F, P):
    """A sphere map's spherical triangles against the surface's: (per-face mean |r - 1|, vertex mean
    |log r| over barycentric cells, triple products), as param-eval's sph_ figures. P is normalized."""
    P = P / np.linalg.norm(P, axis=1)[:, None]
    a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    sph = 2 * np.arctan2(det, 1 + np.einsum("ij,ij->i", a, b) + np.einsum("ij,ij->i", b, c) + np.einsum("ij,ij->i", c, a))
    surf = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    cell = lambda A: np.bincount(F.ravel(), np.repeat(A / 3, 3), len(X))  # noqa: E731
    pf = np.abs((sph / sph.sum()) / (surf / surf.sum()) - 1).mean()
    ve = np.abs(np.log((cell(sph) / sph.sum()) / (cell(surf) / surf.sum()))).mean()
    return pf, ve, det

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

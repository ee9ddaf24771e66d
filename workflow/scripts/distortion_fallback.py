"""distortion_fallback.py - TEMPORARY stand-in for `authalic ... --distortion FILE`.

    distortion_fallback.py IN MAP.obj OUT.txt [--status S.json]

Remove this file once every map command has `--distortion` (the Snakefile already prefers it: it
asks `authalic sphere --help`). Until then it computes the same per-vertex quantity from the input
mesh and the map: log2(area share of the vertex on the map / area share on the surface), where a
vertex's area is a third of the areas of its triangles (flat triangles, chords on the sphere, as
the reports measure them) and its share is that area over the total. One value per map vertex,
one per line (plain text; the map's vertices are the input's, plus the square map's split-edge
midpoints after them). With --status S.json of a failed row (status != 0) it writes an empty
OUT.txt, like the map rule's own placeholders.
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshio_np  # noqa: E402
import product  # noqa: E402


def vertex_shares(X, F, nv):
    A = meshio_np.face_areas(X, F)
    cell = np.bincount(F.reshape(-1), weights=np.repeat(A / 3.0, 3), minlength=nv)
    return cell / cell.sum()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("map")
    ap.add_argument("out")
    ap.add_argument("--status", default="")
    a = ap.parse_args()
    return product.guarded(lambda: work(a), a.out)


def work(a):
    if a.status and json.load(open(a.status))["status"] != 0:
        open(a.out, "w").close()
        return
    X, F = meshio_np.read_mesh(a.input)
    P, G = meshio_np.read_mesh(a.map)
    Y = meshio_np.surface_for_map(X, F, P, G)
    with np.errstate(divide="ignore"):
        d = np.log2(vertex_shares(P, G, len(P)) / vertex_shares(Y, G, len(P)))
    tmp = a.out + ".tmp"
    np.savetxt(tmp, d, fmt="%.9g")
    os.replace(tmp, a.out)
    return


if __name__ == "__main__":
    sys.exit(main())

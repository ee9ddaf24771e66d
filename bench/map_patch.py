#!/usr/bin/python3
"""map_patch.py - where a sphere map's per-face area error sits: a picture of a patch of the map
(faces coloured by r - 1, r = chord share / surface share, as param-eval) and the figures that say
which faces carry the error (issue 21; docs/sphere.md).

    /usr/bin/python3 bench/map_patch.py SURFACE MAP OUT.png [--face F] [--radius R]

SURFACE and MAP as `param-eval SURFACE MAP` takes them (a refined map: the refined surface). The patch
is the faces with a corner within R radians (0.3) of face F's centroid (default: the face with the
largest |r - 1|), drawn in the Lambert azimuthal equal-area projection about that point, so the
patch's areas are the sphere's. Printed: mean |r - 1| (param-eval's r_mean_abs_dev), the map's median
chord edge against that of equilateral faces of the same count, the share of the error carried by
faces with |r - 1| > 0.3 and by needles (a corner of the chord triangle over 165 degrees), the
chord triangles' total area over the sphere's, and the patch's own mean. Uses the build's library
(read_mesh, metrics) unless AUTHALIC_LIBRARY says otherwise, and matplotlib.
"""
import argparse
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT, "python"))
import authalic  # noqa: E402  (first: it sets the thread defaults before numpy loads OpenBLAS)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402


def fail(text):
    print("map_patch: " + text, file=sys.stderr)
    sys.exit(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("surface")
    ap.add_argument("map")
    ap.add_argument("out")
    ap.add_argument("--face", type=int, default=None)
    ap.add_argument("--radius", type=float, default=0.3)
    a = ap.parse_args()
    try:
        V, F = authalic.read_mesh(a.surface)
        P, F2 = authalic.read_mesh(a.map)
    except authalic.Error as ex:
        fail(str(ex))
    if F.shape != F2.shape or (F != F2).any() or len(V) != len(P):
        fail("%s and %s are not one mesh (their vertex counts and faces must match)" % (a.surface, a.map))
    P = P / np.linalg.norm(P, axis=1)[:, None]
    met = authalic.metrics(V, F, P, domain="sphere", per_face=True)
    r = np.exp(-np.asarray(met["upsilon"]))  # Upsilon = ln(surface share / chord share)
    ok = np.isfinite(r)
    e = np.abs(r - 1)

    a0, b0, c0 = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    L = np.stack([np.linalg.norm(b0 - c0, axis=1), np.linalg.norm(c0 - a0, axis=1), np.linalg.norm(a0 - b0, axis=1)], 1)
    Ls = np.sort(L, 1)
    big = np.degrees(np.arccos(np.clip((Ls[:, 0] ** 2 + Ls[:, 1] ** 2 - Ls[:, 2] ** 2) / (2 * Ls[:, 0] * Ls[:, 1]), -1, 1)))
    chord = 0.5 * np.linalg.norm(np.cross(b0 - a0, c0 - a0), axis=1)
    triple = np.abs(np.einsum("ij,ij->i", a0, np.cross(b0, c0)))
    den = 1 + np.einsum("ij,ij->i", a0, b0) + np.einsum("ij,ij->i", b0, c0) + np.einsum("ij,ij->i", c0, a0)
    sph = 2 * np.arctan2(triple, den)
    tot = e[ok].sum()
    print("faces %d, mean |r-1| %.4f (param-eval: %.4f), vertex %.4f" % (len(F), e[ok].mean(), met["r_mean_abs_dev"],
                                                                       met["vertex_logr_mean_abs"]))
    eq = np.sqrt(4 * np.pi / len(F) * 4 / np.sqrt(3))
    print("median chord edge %.4f (equilateral faces of this count: %.4f)" % (np.median(L), eq))
    for name, k in (("|r-1| > 0.3", e > 0.3), ("needles (a corner > 165 deg)", big > 165)):
        k &= ok
        print("%s: %d faces, %.1f%% of the error" % (name, k.sum(), 100 * e[k].sum() / tot))
    print("chord area / sphere area, all faces: %.4f" % (chord.sum() / sph.sum()))

    if a.face is not None and not 0 <= a.face < len(F):
        fail("--face %d: expected a face number from 0 to %d" % (a.face, len(F) - 1))
    f0 = a.face if a.face is not None else int(np.nanargmax(np.where(ok, e, -1)))
    cen = P[F[f0]].mean(0)
    cen /= np.linalg.norm(cen)
    u = np.cross(cen, [0.0, 0.0, 1.0])
    if np.linalg.norm(u) < 1e-6:
        u = np.cross(cen, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(cen, u)
    near = np.arccos(np.clip(P @ cen, -1, 1)) < a.radius
    sel = np.where(near[F].any(1) & (P[F] @ cen > -0.5).all(1))[0]
    k = np.sqrt(2 / (1 + np.clip(P @ cen, -1 + 1e-12, 1)))
    xy = np.stack([k * (P @ u), k * (P @ w)], 1)
    print("patch: %d faces within %.3g rad of face %d (r - 1 = %.3f), mean |r-1| %.4f" %
          (len(sel), a.radius, f0, r[f0] - 1, np.nanmean(e[sel])))
    fig, ax = plt.subplots(figsize=(9, 8))
    pc = PolyCollection(xy[F[sel]], array=np.clip(r[sel] - 1, -0.3, 0.3), cmap="coolwarm", edgecolors="k",
                        linewidths=0.15)
    pc.set_clim(-0.3, 0.3)
    ax.add_collection(pc)
    ax.autoscale()
    ax.set_aspect("equal")
    fig.colorbar(pc, label="r - 1 (chord share / surface share - 1)")
    ax.set_title("%s: %d faces about face %d, mean |r-1| %.4f" % (os.path.basename(a.map), len(sel), f0,
                                                                  np.nanmean(e[sel])))
    fig.savefig(a.out, dpi=90)


if __name__ == "__main__":
    main()

"""preview.py - the preview picture of one map of the workflow.

    preview.py IN MAP.obj OUT.png --command sphere|disk|annulus|square|torus|circles|atlas [--authalic PROG]
               [--status S.json] [--report R.json] [--title TEXT]

Sphere maps: `authalic texture IN --map MAP T.obj --preview OUT.png` draws the map from +z and -z
coloured by Upsilon with its histograms (T.obj goes to a temporary folder). Planar maps (disk,
annulus, square; the CLI has no preview for them): the map's triangles coloured by
Upsilon = ln(surface area share / map area share) on the same scale (-0.5 blue .. +0.5 red), with
the histogram of Upsilon beside it (matplotlib). Torus maps: the same for the map's per-corner vt
triangles, tiled 3 x 3 by the report's lattice (seamless maps tile with no gap), the fundamental
domain outlined. Atlas maps: the per-corner vt triangles (the charts) in the unit square, outlined,
coloured the same way. With --status S.json of a failed row
(status != 0) it writes an empty OUT.png, like the map rule's placeholders.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshio_np  # noqa: E402
import product  # noqa: E402

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402


def _check(res):
    if res.returncode != 0:
        lines = res.stderr.strip().splitlines()
        raise RuntimeError(f"authalic texture exited {res.returncode}: {lines[-1] if lines else ''}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("map")
    ap.add_argument("out")
    ap.add_argument("--status", default="")
    ap.add_argument("--title", default="")
    ap.add_argument("--report", default="", help="the map's report (the torus's lattice)")
    ap.add_argument("--command", required=True, choices=["sphere", "disk", "annulus", "square", "torus", "circles", "atlas"])
    ap.add_argument("--authalic", default="authalic")
    a = ap.parse_args()
    return product.guarded(lambda: work(a), a.out)


def work(a):
    if a.status and json.load(open(a.status))["status"] != 0:
        open(a.out, "wb").close()
        return
    if a.command == "sphere":
        with tempfile.TemporaryDirectory(prefix="authalic-preview.") as tmp:
            png = os.path.join(tmp, "preview.png")
            res = subprocess.run([a.authalic, "texture", a.input, "--map", a.map, os.path.join(tmp, "t.obj"),
                            "--preview", png, "--quiet"], stdin=subprocess.DEVNULL, capture_output=True, text=True)
            _check(res)
            shutil.copyfile(png, a.out + ".tmp.png")
            os.replace(a.out + ".tmp.png", a.out)
        return
    X, F = meshio_np.read_mesh(a.input)
    P, G = meshio_np.read_mesh(a.map)
    tiles = [(0.0, 0.0)]
    L = None
    if a.command == "torus":
        # The map is in the vt: its triangles, the surface's own (P is the surface), tiled by the lattice.
        VT, FT = meshio_np.read_obj_vt(a.map)
        L = np.array(json.load(open(a.report))["lattice"], dtype=np.float64)
        tiles = [tuple(i * L[0] + j * L[1]) for i in (-1, 0, 1) for j in (-1, 0, 1)]
        Y, P, G = P, VT, FT
        As, Am = meshio_np.face_areas(Y, F), meshio_np.face_areas(P, G)
    elif a.command == "atlas":
        # The vt triangles (the charts) drawn flat in the unit square, outlined; P is the surface.
        VT, FT = meshio_np.read_obj_vt(a.map)
        As, Am = meshio_np.face_areas(P, G), meshio_np.face_areas(VT, FT)
        P, G = VT, FT
        L = np.eye(2)
    else:
        Y = meshio_np.surface_for_map(X, F, P, G)
        As, Am = meshio_np.face_areas(Y, G), meshio_np.face_areas(P[:, :2], G)
    with np.errstate(divide="ignore", invalid="ignore"):
        ups = np.log((As / As.sum()) / (Am / Am.sum()))
    fig, (ax, hx) = plt.subplots(1, 2, figsize=(10, 5), gridspec_kw={"width_ratios": [1.3, 1]})
    # Edges help on small meshes; from 20000 faces they would only darken the picture.
    edges = dict(edgecolors=(0, 0, 0, 0.25), linewidths=0.2) if len(G) * len(tiles) < 20000 else dict(edgecolors="none")
    tri = P[G][:, :, :2]
    pc = PolyCollection(np.concatenate([tri + np.array(t) for t in tiles]), array=np.tile(np.clip(ups, -0.5, 0.5),
                        len(tiles)), cmap="coolwarm", antialiaseds=False, **edges)
    pc.set_clim(-0.5, 0.5)
    ax.add_collection(pc)
    lo = np.min([P[:, :2].min(axis=0) + t for t in tiles], axis=0)
    hi = np.max([P[:, :2].max(axis=0) + t for t in tiles], axis=0)
    ax.set_xlim(lo[0] - 0.02, hi[0] + 0.02)
    ax.set_ylim(lo[1] - 0.02, hi[1] + 0.02)
    if L is not None:
        c = np.array([[0, 0], L[0], L[0] + L[1], L[1], [0, 0]])
        ax.plot(c[:, 0], c[:, 1], color="black", linewidth=1.5)
    ax.set_aspect("equal")
    ax.set_axis_off()
    fig.colorbar(pc, ax=ax, shrink=0.7, label="Upsilon = ln(surface share / map share)")
    fin = ups[np.isfinite(ups)]
    hx.hist(fin, bins=60, color="darkred")
    hx.set_xlabel("Upsilon per face")
    hx.set_ylabel("faces")
    hx.set_title(f"mean |Upsilon| {np.abs(fin).mean():.4f}, {len(G)} faces")
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    tmp = a.out + ".tmp.png"
    fig.savefig(tmp, dpi=80)
    os.replace(tmp, a.out)
    return


if __name__ == "__main__":
    sys.exit(main())

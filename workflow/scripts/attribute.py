"""attribute.py - a per-vertex attribute of the surface drawn through its map (the manifest's
`attribute` column: a text file with one number per vertex of the input, in order).

    attribute.py IN MAP.obj ATTR.txt OUT.png --command sphere|disk|annulus|square|torus|circles|atlas
                 [--authalic PROG] [--status S.json] [--title TEXT]

Sphere maps: the equal-area texture `authalic texture IN --map MAP T.obj --bake ATTR --image OUT.png`
bakes (Lambert cylindrical equal-area, 1024x512, viridis): every texel stands for the same surface
area. Planar maps: the attribute interpolated over the map's triangles (viridis), the square's
split-edge midpoints taking the mean of their edge's ends. Torus maps: the same over the per-corner
vt triangles (each copy of a seam vertex takes its vertex's value). With --status S.json of a failed row
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


def _check(res):
    if res.returncode != 0:
        lines = res.stderr.strip().splitlines()
        raise RuntimeError(f"authalic texture exited {res.returncode}: {lines[-1] if lines else ''}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("map")
    ap.add_argument("attribute")
    ap.add_argument("out")
    ap.add_argument("--command", required=True, choices=["sphere", "disk", "annulus", "square", "torus", "circles", "atlas"])
    ap.add_argument("--authalic", default="authalic")
    ap.add_argument("--status", default="")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    return product.guarded(lambda: work(a), a.out)


def work(a):
    if a.status and json.load(open(a.status))["status"] != 0:
        open(a.out, "wb").close()
        return
    if a.command == "sphere":
        with tempfile.TemporaryDirectory(prefix="authalic-attribute.") as tmp:
            png = os.path.join(tmp, "t.png")
            res = subprocess.run([a.authalic, "texture", a.input, "--map", a.map, os.path.join(tmp, "t.obj"),
                            "--bake", a.attribute, "--image", png, "--quiet"],
                           stdin=subprocess.DEVNULL, capture_output=True, text=True)
            _check(res)
            shutil.copyfile(png, a.out + ".tmp.png")
            os.replace(a.out + ".tmp.png", a.out)
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri
    X, F = meshio_np.read_mesh(a.input)
    P, G = meshio_np.read_mesh(a.map)
    val = np.loadtxt(a.attribute, dtype=np.float64).reshape(-1)
    if len(val) != len(X):
        raise ValueError(f"{a.attribute} has {len(val)} values for {len(X)} vertices of {a.input}")
    if a.command in ("torus", "atlas"):
        VT, FT = meshio_np.read_obj_vt(a.map)
        full = np.zeros(len(VT))
        full[FT.reshape(-1)] = val[G.reshape(-1)]
        P, G = VT, FT
    else:
        full = np.concatenate([val, np.zeros(len(P) - len(X))])
        for k, (u, v) in meshio_np.split_ends(X, F, P, G).items():
            full[k] = 0.5 * (val[u] + val[v])
    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    tc = ax.tripcolor(mtri.Triangulation(P[:, 0], P[:, 1], G), full, shading="gouraud", cmap="viridis")
    fig.colorbar(tc, ax=ax, shrink=0.8, label=os.path.basename(a.attribute))
    ax.set_aspect("equal")
    ax.set_axis_off()
    if a.title:
        ax.set_title(a.title)
    fig.tight_layout()
    fig.savefig(a.out + ".tmp.png", dpi=80)
    os.replace(a.out + ".tmp.png", a.out)
    return


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""limb_stretch.py ORIGINAL MAP - how far an equal-area sphere map must stretch each limb's base ring
(issue 21; docs/sphere.md), for the generated meshes data/limbs4.obj, limbs8.obj and
coil.obj, whose body is the unit ball (a limb: a connected set of vertices off the unit sphere).

A limb is a disk whose rim is its base ring (surface length c) and whose image must have area
a = 4 pi A_limb / A_total on the unit sphere; by the spherical isoperimetric inequality the image's rim
is at least sqrt(a (4 pi - a)) long. Per limb: its base ring's edges, its area share, the least stretch
of the base ring (rim length over c, both at the map's scale sqrt(4 pi / A_total)), the least aspect of
its base band's triangles (stretch squared: equal area), the stretch in MAP, the arc a base-ring edge
spans in MAP, and the chord floor of a face on such an edge whose third corner stands over the edge's
middle, over the limb's median face share.

Run: /usr/bin/python3 bench/limb_stretch.py data/limbs4.obj OUT.obj (OUT from `authalic sphere`)."""
import sys
from collections import Counter, defaultdict

import numpy as np


def load_obj(path):
    V, F = [], []
    with open(path) as fh:
        for line in fh:
            s = line.split()
            if s and s[0] == "v":
                V.append([float(x) for x in s[1:4]])
            elif s and s[0] == "f":
                F.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return np.array(V), np.array(F)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    X, F = load_obj(sys.argv[1])
    P, F2 = load_obj(sys.argv[2])
    if P.shape != X.shape or not np.array_equal(F, F2):
        sys.exit("limb_stretch: the map must have the original's vertices and faces")
    P /= np.linalg.norm(P, axis=1)[:, None]
    S = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    scale = np.sqrt(4 * np.pi / S.sum())
    body = np.abs(np.linalg.norm(X, axis=1) - 1) < 1e-9
    adj = defaultdict(set)
    for f in F:
        for k in range(3):
            adj[f[k]].update((f[(k + 1) % 3], f[(k + 2) % 3]))
    seen = body.copy()
    print("| limb vertices | base ring edges | area share | stretch >= | aspect >= | stretch in map | base edge arc (deg) | mid-apex floor / share |")
    print("|--:|--:|--:|--:|--:|--:|--:|--:|")
    for v0 in range(len(X)):
        if seen[v0]:
            continue
        comp, stack = set(), [v0]
        seen[v0] = True
        while stack:
            v = stack.pop()
            comp.add(v)
            for a in adj[v]:
                if not seen[a]:
                    seen[a] = True
                    stack.append(a)
        inside = np.array([all(v in comp for v in f) for f in F])
        count = Counter()
        for f in F[inside]:
            for k in range(3):
                count[tuple(sorted((f[k], f[(k + 1) % 3])))] += 1
        rim = [e for e, n in count.items() if n == 1]
        c = sum(np.linalg.norm(X[a] - X[b]) for a, b in rim)
        a = scale**2 * S[inside].sum()
        least = np.sqrt(a * (4 * np.pi - a)) / (scale * c)
        arcs = [2 * np.arcsin(np.linalg.norm(P[i] - P[j]) / 2) for i, j in rim]
        stretch = sum(arcs) / (scale * c)
        arc = np.mean(arcs)
        floor = 0.5 * 2 * np.sin(arc / 2) * (1 - np.cos(arc / 2))
        share = scale**2 * np.median(S[inside])
        print("| %d | %d | %.3f | %.1f | %.0f | %.1f | %.1f | %.1f |" % (
            len(comp), len(rim), a / (4 * np.pi), least, least**2, stretch, np.degrees(arc), floor / share))


if __name__ == "__main__":
    main()

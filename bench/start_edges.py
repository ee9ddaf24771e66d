#!/usr/bin/python3
"""start_edges.py SURFACE MAP - how a sphere map (typically a start, --init-only) treats edges and faces.

Prints the longest edge of MAP against SURFACE's (each length divided by the square root of its whole
area: 4 pi on the sphere, the surface's area), the number of edges over 4x and 8x, the mean jump of
log r (spherical triangle area share over surface area share) across interior edges, the mean |log r|
and the worst faces' log r. Used by docs/coarse-to-fine-placement.md. Reads OBJ and OFF."""
import sys
import numpy as np


def load(path):
    V, F = [], []
    if path.endswith('.off'):
        toks = [l.split('#')[0].strip() for l in open(path)]
        toks = [t for t in toks if t]
        i = 0
        if toks[0].startswith('OFF'):
            rest = toks[0][3:].strip()
            if rest:
                toks[0] = rest
            else:
                i = 1
        nv, nf = map(int, toks[i].split()[:2])
        i += 1
        V = [list(map(float, toks[i + k].split()[:3])) for k in range(nv)]
        i += nv
        F = [list(map(int, toks[i + k].split()))[1:4] for k in range(nf)]
    else:
        for l in open(path):
            if l.startswith('v '):
                V.append(list(map(float, l.split()[1:4])))
            elif l.startswith('f '):
                F.append([int(x.split('/')[0]) - 1 for x in l.split()[1:4]])
    return np.array(V), np.array(F)


def main():
    X, F = load(sys.argv[1])
    P, _ = load(sys.argv[2])
    E = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), 1), axis=0)
    As = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    ls = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1) / np.sqrt(As.sum())
    lp = np.linalg.norm(P[E[:, 0]] - P[E[:, 1]], axis=1) / np.sqrt(4 * np.pi)
    r = lp / np.maximum(ls, 1e-300)
    a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    det = np.einsum('ij,ij->i', a, np.cross(b, c))
    Ap = 2 * np.arctan2(det, 1 + np.einsum('ij,ij->i', a, b) + np.einsum('ij,ij->i', b, c) + np.einsum('ij,ij->i', c, a))
    lr = np.log(np.maximum(Ap, 1e-300) / Ap.sum() / (As / As.sum()))
    first, jumps = {}, []
    for f, (i, j, k) in enumerate(F):
        for x, y in ((i, j), (j, k), (k, i)):
            key = (min(x, y), max(x, y))
            if key in first:
                jumps.append(abs(lr[f] - lr[first[key]]))
            else:
                first[key] = f
    print("longest edge %.2f, edges over 4x %d, over 8x %d; jump %.4f, mean |log r| %.4f, worst log r %.2f, %.2f" %
          (r.max(), (r > 4).sum(), (r > 8).sum(), np.mean(jumps), np.abs(lr).mean(), lr.min(), lr.max()))


if __name__ == '__main__':
    main()

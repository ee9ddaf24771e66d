#!/usr/bin/python3
"""multilevel_proto.py - a measured sketch of a two-level start for the sphere flow (not used by the
build or the tests; needs Debian's python3-numpy and python3-scipy). See docs/flow.md.

usage: scripts/multilevel_proto.py MESH.obj [RATIO] [--bin build/authalic]

1. conformal start P0 of the whole mesh (authalic sphere --init-only);
2. every RATIO-th vertex (a seeded random sample) is kept; the coarse triangulation is the convex hull
   of their start positions (the spherical Delaunay triangulation, fold-free by construction);
3. each vertex cell of the surface is split among the corners of the coarse triangle it falls in
   (barycentric weights): the coarse vertices' target areas, written as a per-vertex density;
4. the coarse mesh (its sphere positions as its surface, so that its own conformal start is P0's
   positions again) is mapped by authalic sphere --density;
5. every vertex is carried by the piecewise-linear map from the coarse start to the coarse result.
Prints the coarse run's steps and time, the carried map's folds and its mean |log area ratio|.
"""
import json
import subprocess
import sys

import numpy as np
from scipy.spatial import ConvexHull, cKDTree


def load_obj(fn):
    V, F = [], []
    for line in open(fn):
        if line.startswith('v '):
            V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith('f '):
            F.append([int(x.split('/')[0]) - 1 for x in line.split()[1:4]])
    return np.array(V), np.array(F)


def write_obj(fn, V, F):
    with open(fn, 'w') as fo:
        for p in V:
            fo.write('v %.17g %.17g %.17g\n' % tuple(p))
        for t in F:
            fo.write('f %d %d %d\n' % tuple(t + 1))


def flat_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


def sphere_areas(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    num = np.abs(np.einsum('ij,ij->i', a, np.cross(b, c)))
    den = 1 + np.einsum('ij,ij->i', a, b) + np.einsum('ij,ij->i', b, c) + np.einsum('ij,ij->i', c, a)
    return 2 * np.arctan2(num, den)


def vertex_cells(A, F, n):
    c = np.zeros(n)
    for k in range(3):
        np.add.at(c, F[:, k], A / 3)
    return c


def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    binary = sys.argv[sys.argv.index('--bin') + 1] if '--bin' in sys.argv else 'build/authalic'
    if '--bin' in sys.argv:
        args.remove(binary)
    mesh, ratio = args[0], int(args[1]) if len(args) > 1 else 8
    tmp = '/tmp/authalic_ml_'
    subprocess.run([binary, 'sphere', mesh, tmp + 'p0.obj', '--init-only', '--quiet'], check=True)
    X, F = load_obj(mesh)
    P0, _ = load_obj(tmp + 'p0.obj')
    P0 /= np.linalg.norm(P0, axis=1)[:, None]
    nv = len(X)
    S = np.sort(np.random.default_rng(1).choice(nv, nv // ratio, replace=False))
    PS = P0[S]
    T = ConvexHull(PS).simplices.copy()
    o = np.einsum('ij,ij->i', PS[T[:, 0]], np.cross(PS[T[:, 1]], PS[T[:, 2]]))
    T[o < 0] = T[o < 0][:, [0, 2, 1]]
    incident = [[] for _ in range(len(S))]
    for t, tri in enumerate(T):
        for v in tri:
            incident[v].append(t)
    tree = cKDTree(PS)

    def locate(Q):
        _, near = tree.query(Q, k=3)
        face, bary = -np.ones(len(Q), int), np.zeros((len(Q), 3))
        for q, p in enumerate(Q):
            # The triangle whose smallest relative barycentric coordinate is largest: >= 0 inside it.
            # (An absolute tolerance accepts wrong triangles where the start is squeezed to 1e-7.)
            best, bt, bd = -np.inf, -1, None
            for t in [t for s in near[q] for t in incident[s]] + list(range(len(T))):
                a, b, c = PS[T[t]]
                d = np.array([np.dot(np.cross(b, c), p), np.dot(np.cross(c, a), p), np.dot(np.cross(a, b), p)])
                score = d.min() / np.abs(d).sum()
                if score > best:
                    best, bt, bd = score, t, d
                if score >= 0:
                    break
            bd = np.maximum(bd, 0)
            face[q], bary[q] = bt, bd / bd.sum()
        return face, bary

    vf, vb = locate(P0)
    As = flat_areas(X, F)
    target = np.zeros(len(S))
    for k in range(3):
        np.add.at(target, T[vf, k], vb[:, k] * vertex_cells(As, F, nv))
    density = target / vertex_cells(flat_areas(PS, T), T, len(S))
    write_obj(tmp + 'c.obj', PS, T)
    np.savetxt(tmp + 'd.txt', density)
    subprocess.run([binary, 'sphere', tmp + 'c.obj', tmp + 'cout.obj', '--density', tmp + 'd.txt', '--quiet',
                    '--report', tmp + 'c.json', '--tol', '0.005'])
    rep = json.load(open(tmp + 'c.json'))
    Pc, _ = load_obj(tmp + 'cout.obj')
    Pn = np.einsum('ij,ijk->ik', vb, Pc[T[vf]])
    Pn /= np.linalg.norm(Pn, axis=1)[:, None]
    Pn[S] = Pc
    orient = np.einsum('ij,ij->i', Pn[F[:, 0]], np.cross(Pn[F[:, 1]], Pn[F[:, 2]]))

    def mean_abs_log(P):
        A = sphere_areas(P, F)
        return np.abs(np.log((A / A.sum()) / (As / As.sum()))).mean()

    print('coarse: V=%d F=%d steps=%d init+flow=%.2fs' % (len(S), len(T), rep['steps'],
                                                          rep['time']['init'] + rep['time']['flow']))
    print('carried map: folds=%d face mean|log r| %.4f (conformal start %.4f)' %
          ((orient <= 0).sum(), mean_abs_log(Pn), mean_abs_log(P0)))
    write_obj(tmp + 'carried.obj', Pn, F)


if __name__ == '__main__':
    main()

#!/usr/bin/python3
"""face_areas_proto.py - measured sketches of per-face area steps on a sphere map (not used by the build
or the tests; needs Debian's python3-numpy and python3-scipy). See docs/flow.md.

usage: scripts/face_areas_proto.py MODE SURFACE MAP.obj [options]

MODE gn:     linearized Gauss-Newton steps on the chord triangles' areas, regularized by MU times the
             vertex masses (--reg mass) or the cotan Laplacian of the motion (--reg shear); a step is
             halved until no triangle folds. Prints each step's linear residual (the part of the per-face
             residual the regularized linear step leaves), its largest move over the square root of the
             mean triangle area, and the resulting param-eval-style figures.
MODE jacobi: damped Jacobi sweeps in which every vertex moves, in its tangent plane, to the least-squares
             fit of its own triangles' areas (a local smoother; the residual it cannot reach is global).
MODE dirichlet: the angle step of common/au_ang.c in numpy: Dirichlet energy (surface cotan weights) plus
             BETA times the per-face residual, with the vertex cells held exactly (KKT), a few steps.
options: --mu MU (gn, 1e-2; dirichlet: the trust region, 1) --reg mass|shear (gn) --beta BETA
         (dirichlet, 1000; not the C weight: here scaled by the mean diagonals) --steps N (4)
         --omega W (jacobi, 0.5) --out OUT.obj
"""
import argparse
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla


def load(fn):
    if fn.endswith('.off'):
        t = open(fn).read().split()
        nv, nf = int(t[1]), int(t[2])
        V = np.array(t[4:4 + 3 * nv], float).reshape(nv, 3)
        F = np.array(t[4 + 3 * nv:4 + 3 * nv + 4 * nf], int).reshape(nf, 4)[:, 1:]
        return V, F
    V, F = [], []
    for line in open(fn):
        s = line.split()
        if s and s[0] == 'v':
            V.append([float(x) for x in s[1:4]])
        elif s and s[0] == 'f':
            F.append([int(x.split('/')[0]) - 1 for x in s[1:4]])
    return np.array(V), np.array(F)


def areas(X, F):
    c = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    return 0.5 * np.linalg.norm(c, axis=1), c


def corner_angles(X, F):
    out = []
    for k in range(3):
        u = X[F[:, (k + 1) % 3]] - X[F[:, k]]
        v = X[F[:, (k + 2) % 3]] - X[F[:, k]]
        out.append(np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.sum(u * v, 1)))
    return np.stack(out, 1)


def cotan_laplacian(X, F, nv):
    I, J, W = [], [], []
    for k in range(3):
        i, j, o = F[:, (k + 1) % 3], F[:, (k + 2) % 3], F[:, k]
        u, v = X[i] - X[o], X[j] - X[o]
        ct = np.sum(u * v, 1) / np.linalg.norm(np.cross(u, v), axis=1)
        I += [i, j, i, j]
        J += [j, i, i, j]
        W += [-0.5 * ct, -0.5 * ct, 0.5 * ct, 0.5 * ct]
    return sp.csr_matrix((np.concatenate(W), (np.concatenate(I), np.concatenate(J))), shape=(nv, nv))


class Problem:
    def __init__(self, S, F):
        self.S, self.F, self.nv, self.nf = S, F, len(S), len(F)
        As, _ = areas(S, F)
        self.share = As / As.sum()
        self.vshare = np.zeros(self.nv)
        np.add.at(self.vshare, F.ravel(), np.repeat(self.share / 3, 3))
        self.angS = corner_angles(S, F)

    def stats(self, X):
        F = self.F
        A, c = areas(X, F)
        r = (A / A.sum()) / self.share
        folds = int(np.sum(np.einsum('ij,ij->i', c, X[F[:, 0]] + X[F[:, 1]] + X[F[:, 2]]) <= 0))
        va = np.zeros(self.nv)
        np.add.at(va, F.ravel(), np.repeat(A / 3, 3))
        vert = np.mean(np.abs(np.log((va / A.sum()) / self.vshare)))
        ang = np.degrees(np.mean(np.abs(corner_angles(X, F) - self.angS)))
        return 'r_mad %.5f r_cv %.5f vert %.5f folds %d angle %.3f' % (np.mean(np.abs(r - 1)), np.std(r) / np.mean(r), vert, folds, ang)

    def tangent(self, P):
        a = np.where(np.abs(P[:, 0:1]) < 0.9, np.array([[1, 0, 0]]), np.array([[0, 1, 0]]))
        t1 = np.cross(P, a)
        t1 /= np.linalg.norm(t1, axis=1)[:, None]
        return t1, np.cross(P, t1)

    def face_jacobian(self, P, t1, t2, third=False):
        """Rows: chord triangle areas (third=False) or vertex cells (True); columns: 2 per vertex."""
        F, nf, nv = self.F, self.nf, self.nv
        A, c = areas(P, F)
        n = c / np.linalg.norm(c, axis=1)[:, None]
        rows, cols, vals = [], [], []
        for k in range(3):
            i = F[:, k]
            g = 0.5 * np.cross(n, P[F[:, (k + 2) % 3]] - P[F[:, (k + 1) % 3]])
            g1, g2 = np.sum(g * t1[i], 1), np.sum(g * t2[i], 1)
            targets = [F[:, r] for r in range(3)] if third else [np.arange(nf)]
            for rr in targets:
                w = 1.0 / 3 if third else 1.0
                rows += [rr, rr]
                cols += [2 * i, 2 * i + 1]
                vals += [w * g1, w * g2]
        shape = (nv if third else nf, 2 * nv)
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=shape), A

    def move(self, P, D):
        """Per-vertex fractions, halved at the corners of folded triangles (as the C step control)."""
        F = self.F
        lim = np.ones(self.nv)
        for tries in range(40):
            Q = P + lim[:, None] * D
            Q /= np.linalg.norm(Q, axis=1)[:, None]
            c = np.cross(Q[F[:, 1]] - Q[F[:, 0]], Q[F[:, 2]] - Q[F[:, 0]])
            bad = np.where(np.einsum('ij,ij->i', c, Q[F[:, 0]] + Q[F[:, 1]] + Q[F[:, 2]]) <= 1e-14)[0]
            if len(bad) == 0:
                return Q, lim.mean()
            lim[np.unique(F[bad].ravel())] *= 0.5 if tries < 30 else 0
        return P, 0.0


def run_gn(pb, P, a):
    for it in range(a.steps):
        t1, t2 = pb.tangent(P)
        J, A = pb.face_jacobian(P, t1, t2)
        T = pb.share * A.sum()
        Jw = sp.diags(1 / T) @ J
        b = (T - A) / T
        if a.reg == 'mass':
            m = np.zeros(pb.nv)
            np.add.at(m, pb.F.ravel(), np.repeat(A / 3, 3))
            R = sp.diags(np.repeat(m, 2)) / m.mean()
        else:
            R = sp.kron(cotan_laplacian(P, pb.F, pb.nv), sp.eye(2)) + 1e-8 * sp.eye(2 * pb.nv)
        d = sla.spsolve((Jw.T @ Jw + a.mu * R).tocsc(), Jw.T @ b)
        lin = np.linalg.norm(Jw @ d - b) / np.linalg.norm(b)
        D = d[0::2, None] * t1 + d[1::2, None] * t2
        big = np.max(np.linalg.norm(D, axis=1)) / np.sqrt(A.mean())
        # a global step, halved until nothing folds
        step = 1.0
        while True:
            Q = P + step * D
            Q /= np.linalg.norm(Q, axis=1)[:, None]
            if 'folds 0' in pb.stats(Q) or step < 1e-3:
                break
            step *= 0.5
        P = Q
        print('step %d: linear residual %.3f, largest move %.3g, taken %.3g: %s' % (it, lin, big, step, pb.stats(P)))
    return P


def run_jacobi(pb, P, a):
    F = pb.F
    for it in range(a.steps):
        A, c = areas(P, F)
        n = c / np.linalg.norm(c, axis=1)[:, None]
        T = pb.share * A.sum()
        w = 1 / T ** 2
        t1, t2 = pb.tangent(P)
        M = np.zeros((pb.nv, 3))
        R = np.zeros((pb.nv, 2))
        for k in range(3):
            i = F[:, k]
            g = 0.5 * np.cross(n, P[F[:, (k + 2) % 3]] - P[F[:, (k + 1) % 3]])
            g1, g2 = np.sum(g * t1[i], 1), np.sum(g * t2[i], 1)
            np.add.at(M, i, np.stack([w * g1 * g1, w * g1 * g2, w * g2 * g2], 1))
            np.add.at(R, i, np.stack([w * g1 * (T - A), w * g2 * (T - A)], 1))
        det = M[:, 0] * M[:, 2] - M[:, 1] ** 2
        det = np.where(det > 0, det, np.inf)
        d1 = (M[:, 2] * R[:, 0] - M[:, 1] * R[:, 1]) / det
        d2 = (M[:, 0] * R[:, 1] - M[:, 1] * R[:, 0]) / det
        P, frac = pb.move(P, a.omega * (d1[:, None] * t1 + d2[:, None] * t2))
        if it % max(1, a.steps // 10) == 0 or it == a.steps - 1:
            print('sweep %d: %s' % (it, pb.stats(P)))
    return P


def run_dirichlet(pb, P, a):
    F, nv = pb.F, pb.nv
    L = cotan_laplacian(pb.S, F, nv)
    L3 = sp.kron(L, sp.eye(3)).tocsr()
    for it in range(a.steps):
        t1, t2 = pb.tangent(P)
        idx = np.arange(nv)
        B = sp.csr_matrix((np.concatenate([t1.ravel(), t2.ravel()]),
                           (np.concatenate([np.repeat(3 * idx, 3) + np.tile([0, 1, 2], nv)] * 2),
                            np.concatenate([np.repeat(2 * idx, 3), np.repeat(2 * idx + 1, 3)]))), shape=(3 * nv, 2 * nv))
        Lt = (B.T @ L3 @ B).tocsc()
        g = B.T @ (L3 @ P.ravel())
        Jv, A = pb.face_jacobian(P, t1, t2, third=True)
        Jf, _ = pb.face_jacobian(P, t1, t2)
        va = np.zeros(nv)
        np.add.at(va, F.ravel(), np.repeat(A / 3, 3))
        TV = pb.vshare * A.sum()
        Jn, bn = sp.diags(1 / TV) @ Jv, (TV - va) / TV
        T = pb.share * A.sum()
        Jfn, bf = sp.diags(1 / T) @ Jf, (T - A) / T
        H = Jfn.T @ Jfn
        m = np.zeros(nv)
        np.add.at(m, F.ravel(), np.repeat(A / 3, 3))
        sc = abs(Lt.diagonal()).mean() / m.mean()
        scf = abs(Lt.diagonal()).mean() / H.diagonal().mean()
        K = sp.bmat([[Lt + a.mu * sc * sp.diags(np.repeat(m, 2)) + a.beta * scf * H, Jn.T], [Jn, -1e-12 * sp.eye(nv)]]).tocsc()
        x = sla.spsolve(K, np.concatenate([-g + a.beta * scf * (Jfn.T @ bf), bn]))
        d = x[:2 * nv]
        P, frac = pb.move(P, d[0::2, None] * t1 + d[1::2, None] * t2)
        print('step %d (fraction %.2f): %s' % (it, frac, pb.stats(P)))
    return P


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('mode', choices=['gn', 'jacobi', 'dirichlet'])
    ap.add_argument('surface')
    ap.add_argument('map')
    ap.add_argument('--mu', type=float)
    ap.add_argument('--reg', choices=['mass', 'shear'], default='mass')
    ap.add_argument('--beta', type=float, default=1000)
    ap.add_argument('--steps', type=int, default=4)
    ap.add_argument('--omega', type=float, default=0.5)
    ap.add_argument('--out')
    a = ap.parse_args()
    if a.mu is None:
        a.mu = 1e-2 if a.mode == 'gn' else 1.0
    S, F = load(a.surface)
    P, _ = load(a.map)
    pb = Problem(S, F)
    print('start: %s' % pb.stats(P))
    t0 = time.time()
    P = {'gn': run_gn, 'jacobi': run_jacobi, 'dirichlet': run_dirichlet}[a.mode](pb, P, a)
    print('%.1f s' % (time.time() - t0))
    if a.out:
        with open(a.out, 'w') as fo:
            for p in P:
                fo.write('v %.17g %.17g %.17g\n' % tuple(p))
            for f in F:
                fo.write('f %d %d %d\n' % tuple(f + 1))


if __name__ == '__main__':
    main()

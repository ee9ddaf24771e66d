"""vt_metrics.py - the cohort's metrics of a map held in per-corner vt (the atlas), computed here
because `authalic atlas --report` has no `metrics` block and no --distortion.

    vt_metrics.py MAP.obj [--json]      print the metrics of MAP.obj (its v: the surface, its vt: the map)

metrics(X, F, VT, FT) follows param-eval's definitions (`param-eval IN MAP.obj --coords vt --domain
plane`) and the reports' angle_diff_mean_deg: per face, the affine map from the vt triangle to the
surface triangle, the surface scaled to the map's total area; faces whose area is at most 1e-14 of
the total (either side) are excluded. folds: vt triangles not of the majority orientation.
r_mean_abs_dev, r_cv: the per-face ratio of area shares. vertex_logr_mean_abs: on the mesh cut along
the seams (one vertex per distinct (vertex, vt) pair), as param-eval measures it.
vertex_distortion(...) is the per-vertex quantity of `authalic --distortion` for such a map (the
torus's convention): one value per surface vertex, log2(map share / surface share) of its
barycentric cell, the cell gathering the vt triangles of every copy of a seam vertex.
"""
import json
import math
import os
import struct
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshio_np  # noqa: E402

DEGEN_REL = 1e-14


def _corner_angles(Q):
    """Corner angles (#F by 3) of triangles Q (#F by 3 by 3)."""
    out = np.empty(Q.shape[:2])
    for k in range(3):
        a, b = Q[:, (k + 1) % 3] - Q[:, k], Q[:, (k + 2) % 3] - Q[:, k]
        out[:, k] = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
    return out


def _vertex_logr(Ad, As, F, n):
    vd, vs = (np.bincount(F.ravel(), np.repeat(A / 3, 3), n) for A in (Ad, As))
    ok = (vd > DEGEN_REL * vd.sum()) & (vs > DEGEN_REL * vs.sum())
    return np.abs(np.log((vd[ok] / vd.sum()) / (vs[ok] / vs.sum())))


def metrics(X, F, VT, FT):
    """The cohort's metric columns (cohort.METRICS) of the vt map (VT, FT) of the surface (X, F)."""
    Q = np.zeros((len(F), 3, 3))
    Q[:, :, :2] = VT[FT]
    S = X[F]
    Nd = np.cross(Q[:, 1] - Q[:, 0], Q[:, 2] - Q[:, 0])[:, 2]
    Ad, As = np.abs(Nd) / 2, np.linalg.norm(np.cross(S[:, 1] - S[:, 0], S[:, 2] - S[:, 0]), axis=1) / 2
    ok = (Ad > DEGEN_REL * Ad.sum()) & (As > DEGEN_REL * As.sum())
    major = 1 if (Nd > 0).sum() >= (Nd < 0).sum() else -1
    # Singular values of the affine map domain -> surface (param-eval's singular_values).
    e1, e2 = Q[:, 1] - Q[:, 0], Q[:, 2] - Q[:, 0]
    p1, p2 = S[:, 1] - S[:, 0], S[:, 2] - S[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        l1 = np.linalg.norm(e1, axis=1)
        x2, y2 = np.einsum("ij,ij->i", e1, e2) / l1, 2 * Ad / l1
        j1 = p1 / l1[:, None]
        j2 = (p2 - (x2 / l1)[:, None] * p1) / y2[:, None]
        a, b, c = (np.einsum("ij,ij->i", u, v) for u, v in ((j1, j1), (j1, j2), (j2, j2)))
        gmax = np.sqrt(0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + b * b))
        gmin = 2 * As / (2 * Ad) / gmax
    ups = np.log(gmax[ok] * gmin[ok] * (Ad.sum() / As.sum()))
    lam = np.log(gmax[ok] / gmin[ok])
    r = (Ad[ok] / Ad.sum()) / (As[ok] / As.sum())
    adiff = np.abs(_corner_angles(Q[ok]) - _corner_angles(S[ok]))
    # The mesh cut along the seams: one vertex per distinct (vertex, vt) pair of a corner.
    keys = np.column_stack([F.ravel(), VT[FT].reshape(-1, 2)])
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    lr = _vertex_logr(Ad, As, inv.reshape(-1, 3), len(uniq))
    mean = lambda v: float(np.mean(v)) if len(v) else None  # noqa: E731
    return {"folds": int((Nd * major <= 0).sum()),
            "r_mean_abs_dev": mean(np.abs(r - 1)),
            "vertex_logr_mean_abs": mean(lr),
            "angle_diff_mean_deg": mean(adiff) * 180 / math.pi if adiff.size else None,
            "upsilon_mean_abs": mean(np.abs(ups)),
            "lambda_mean": mean(lam),
            "r_cv": float(np.std(r) / np.mean(r)) if len(r) else None,
            "excluded_faces": int((~ok).sum())}


def vertex_distortion(X, F, VT, FT):
    """log2(map share / surface share) of each surface vertex's barycentric cell, #X."""
    ad, asurf = meshio_np.face_areas(VT, FT), meshio_np.face_areas(X, F)
    cd = np.bincount(F.reshape(-1), np.repeat(ad / 3, 3), len(X))
    cs = np.bincount(F.reshape(-1), np.repeat(asurf / 3, 3), len(X))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log2((cd / cd.sum()) / (cs / cs.sum()))


def write_distortion(path, values, nfaces):
    """A FreeSurfer curv file (as `authalic --distortion` writes it) when PATH ends in .curv, else
    one value a line."""
    tmp = path + ".tmp"
    if path.endswith(".curv"):
        with open(tmp, "wb") as fh:
            fh.write(b"\xff\xff\xff" + struct.pack(">iii", len(values), nfaces, 1))
            fh.write(np.asarray(values, dtype=">f4").tobytes())
    else:
        np.savetxt(tmp, values, fmt="%.9g")
    os.replace(tmp, path)


def read_map(path):
    """(X, F, VT, FT) of a map OBJ with per-corner vt."""
    X, F = meshio_np.read_mesh(path)
    VT, FT = meshio_np.read_obj_vt(path)
    if len(FT) != len(F):
        raise ValueError(f"{path}: {len(F)} faces but {len(FT)} with vt")
    return X, F, VT, FT


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0 if len(sys.argv) > 1 else 2)
    print(json.dumps(metrics(*read_map(sys.argv[1])), indent=1))

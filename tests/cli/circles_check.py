"""circles_check.py - the end-to-end check of a circle-domain map (`authalic circles IN OUT --report R`):
python3 circles_check.py IN OUT R [FACE_MAX VERTEX_MAX]. Exits nonzero naming what is wrong.
OUT keeps IN's vertices and faces, lies in the plane with vt = ((u+1)/2, (v+1)/2) in [0,1]^2, has no
folded triangle, per-face mean |r - 1| <= FACE_MAX (0.02) and vertex mean |log r| over barycentric
cells <= VERTEX_MAX (0.005), as param-eval measures them; R lists one circle per boundary loop, every
loop lies on its circle to 1e-9, the outer one is the unit circle, the holes lie inside it and apart."""
import json
import math
import sys

import numpy as np

import objmesh


def load(path):
    """objmesh.load, or an OFF file's triangles (../shared's beetle.off)."""
    if not path.lower().endswith(".off"):
        return objmesh.load(path)
    tok = [t for line in open(path) for t in line.split("#")[0].split()]
    nv, nf = int(tok[1]), int(tok[2])
    X = np.array(tok[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    F, k = [], 4 + 3 * nv
    for _ in range(nf):
        n = int(tok[k])
        F.append([int(x) for x in tok[k + 1:k + 1 + n]])
        k += 1 + n
    return X, np.array(F, dtype=int)


def read_vt(path):
    return np.array([[float(x) for x in line.split()[1:3]] for line in open(path) if line.startswith("vt ")])


def main():
    src, out, rep = sys.argv[1:4]
    face_max = float(sys.argv[4]) if len(sys.argv) > 4 else 0.02
    vertex_max = float(sys.argv[5]) if len(sys.argv) > 5 else 0.005
    X, FX = load(src)
    P, F = objmesh.load(out)
    r = json.load(open(rep))
    bad = []
    if P.shape != X.shape or not np.array_equal(F, FX):
        sys.exit("vertices or faces differ from the input's")
    VT = read_vt(out)
    if VT.shape != (len(P), 2) or np.abs(VT - 0.5 * (P[:, :2] + 1)).max() > 1e-9:
        bad.append("vt missing or not ((u+1)/2, (v+1)/2)")
    if np.abs(P[:, 2]).max() != 0:
        bad.append("z is not 0")
    a, b, c = P[F[:, 0], :2], P[F[:, 1], :2], P[F[:, 2], :2]
    dom = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    folds = int((dom <= 0).sum())
    surf = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
    ratio = (dom / dom.sum()) / (surf / surf.sum())
    pf = np.abs(ratio - 1).mean()
    cell = lambda A: np.bincount(F.ravel(), np.repeat(A / 3, 3), len(X))  # noqa: E731
    used = cell(surf) > 0
    ve = np.abs(np.log((cell(dom)[used] / dom.sum()) / (cell(surf)[used] / surf.sum()))).mean()
    print("folds %d  per-face %.5f  vertex %.5f" % (folds, pf, ve))
    if folds:
        bad.append("%d folded triangles" % folds)
    if not pf <= face_max:
        bad.append("per-face mean |r-1| %.4g > %g" % (pf, face_max))
    if not ve <= vertex_max:
        bad.append("vertex mean |log r| %.4g > %g" % (ve, vertex_max))
    # boundary loops from the directed edges without a reverse
    d = set(map(tuple, F[:, [0, 1]])) | set(map(tuple, F[:, [1, 2]])) | set(map(tuple, F[:, [2, 0]]))
    nxt = {u: v for u, v in d if (v, u) not in d}
    circles = r.get("circles", [])
    loop_of = {}
    for k, ci in enumerate(circles):
        v = ci["vertex"]
        while v in nxt and v not in loop_of:
            loop_of[v] = k
            v = nxt[v]
    if len(loop_of) != len(nxt):
        bad.append("the report's circles name %d of the %d boundary vertices' loops" % (len(loop_of), len(nxt)))
    dev = max(abs(math.hypot(P[v, 0] - circles[k]["center"][0], P[v, 1] - circles[k]["center"][1]) - circles[k]["radius"])
              for v, k in loop_of.items())
    print("loops %d  largest distance from a circle %.2e" % (len(circles), dev))
    if not dev <= 1e-9:
        bad.append("a boundary vertex is %.3g off its circle" % dev)
    outer = [ci for ci in circles if ci["outer"]]
    if len(outer) != 1 or outer[0]["radius"] != 1 or outer[0]["center"] != [0, 0]:
        bad.append("not exactly one outer circle, the unit circle")
    holes = [ci for ci in circles if not ci["outer"]]
    gaps = [1 - math.hypot(*h["center"]) - h["radius"] for h in holes]
    gaps += [math.hypot(h["center"][0] - g["center"][0], h["center"][1] - g["center"][1]) - h["radius"] - g["radius"]
             for i, h in enumerate(holes) for g in holes[i + 1:]]
    if holes:
        print("smallest gap between circles %.4g" % min(gaps))
        if not min(gaps) > 0 or not all(h["radius"] > 0 for h in holes):
            bad.append("circles overlap or leave the unit circle (gap %.3g)" % min(gaps))
    if bad:
        sys.exit("; ".join(bad))


main()

"""meshio_np.py - small numpy readers for the workflow's scripts: OBJ, OFF, PLY (ASCII and binary), STL.

Only what the workflow needs: vertex positions (#V by 3, float64) and triangles (#F by 3, int64,
0-based). The inputs have already passed `authalic`'s own reader (these scripts only run on rows
whose map succeeded), so the readers are lenient and raise ValueError on anything they do not
understand rather than guessing. Also: an OBJ's per-corner texture coordinates (the torus map's
seamless vt), per-face areas, the face count from a file's header (cheap,
for the scheduler's resource estimates), and the surface positions of the vertices that the square
map appends when it splits an edge.
"""
import os
import re
import struct

import numpy as np


def read_mesh(path):
    """Return (X, F): positions #V by 3 and triangles #F by 3 (0-based) of an OBJ/OFF/PLY/STL file."""
    ext = os.path.splitext(path)[1].lower()
    with open(path, "rb") as fh:
        data = fh.read()
    if ext == ".obj":
        return _read_obj(data)
    if ext == ".off":
        return _read_off(data)
    if ext == ".ply":
        return _read_ply(data)
    if ext == ".stl":
        return _read_stl(data)
    raise ValueError(f"{path}: unknown mesh extension {ext!r}")


def _triangles(faces):
    F = np.asarray(faces, dtype=np.int64).reshape(-1, 3) if len(faces) else np.zeros((0, 3), np.int64)
    return F


def _read_obj(data):
    X, faces = [], []
    for line in data.decode("utf-8", "replace").splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            X.append([float(t[1]), float(t[2]), float(t[3])])
        elif t[0] == "f":
            if len(t) != 4:
                raise ValueError(f"OBJ face with {len(t) - 1} corners: only triangles are read")
            row = []
            for c in t[1:]:
                i = int(c.split("/")[0])
                row.append(i - 1 if i > 0 else len(X) + i)
            faces.append(row)
    return np.array(X, dtype=np.float64).reshape(-1, 3), _triangles(faces)


def _read_off(data):
    lines = []
    for line in data.decode("utf-8", "replace").splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            lines.append(line)
    head = lines[0].split()
    if not head[0].endswith("OFF"):
        raise ValueError("not an OFF file")
    rest = head[1:]
    k = 1
    if not rest:
        rest = lines[1].split()
        k = 2
    nv, nf = int(rest[0]), int(rest[1])
    X = np.array([[float(s) for s in lines[k + i].split()[:3]] for i in range(nv)], dtype=np.float64)
    faces = []
    for i in range(nf):
        t = lines[k + nv + i].split()
        if int(t[0]) != 3:
            raise ValueError("OFF face that is not a triangle")
        faces.append([int(t[1]), int(t[2]), int(t[3])])
    return X.reshape(-1, 3), _triangles(faces)


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def _read_ply(data):
    end = data.find(b"end_header")
    if end < 0:
        raise ValueError("PLY without end_header")
    nl = data.find(b"\n", end)
    header = data[:end].decode("ascii", "replace").splitlines()
    body = data[nl + 1:]
    fmt = None
    elements = []  # [name, count, [(name, type) or (name, ("list", ctype, itype))]]
    for line in header:
        t = line.split()
        if not t:
            continue
        if t[0] == "format":
            fmt = t[1]
        elif t[0] == "element":
            elements.append([t[1], int(t[2]), []])
        elif t[0] == "property":
            if t[1] == "list":
                elements[-1][2].append((t[4], ("list", _PLY_TYPES[t[2]], _PLY_TYPES[t[3]])))
            else:
                elements[-1][2].append((t[2], _PLY_TYPES[t[1]]))
    X = F = None
    if fmt == "ascii":
        tokens = body.split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for pname, ptype in props:
                    if isinstance(ptype, tuple):
                        n = int(tokens[pos]); pos += 1
                        row[pname] = [int(v) for v in tokens[pos:pos + n]]; pos += n
                    else:
                        row[pname] = float(tokens[pos]); pos += 1
                rows.append(row)
            if name == "vertex":
                X = np.array([[r["x"], r["y"], r["z"]] for r in rows], dtype=np.float64)
            elif name == "face":
                key = "vertex_indices" if rows and "vertex_indices" in rows[0] else "vertex_index"
                if any(len(r[key]) != 3 for r in rows):
                    raise ValueError("PLY face that is not a triangle")
                F = _triangles([r[key] for r in rows])
    elif fmt in ("binary_little_endian", "binary_big_endian"):
        bo = "<" if fmt == "binary_little_endian" else ">"
        pos = 0
        for name, count, props in elements:
            if all(not isinstance(p[1], tuple) for p in props):
                dt = np.dtype([(p[0], bo + p[1]) for p in props])
                arr = np.frombuffer(body, dtype=dt, count=count, offset=pos)
                pos += dt.itemsize * count
                if name == "vertex":
                    X = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
                continue
            # Elements with a list property: read row by row (faces are triangles, checked).
            lists = []
            for _ in range(count):
                for pname, ptype in props:
                    if isinstance(ptype, tuple):
                        c = np.dtype(bo + ptype[1]); it = np.dtype(bo + ptype[2])
                        n = int(np.frombuffer(body, c, 1, pos)[0]); pos += c.itemsize
                        vals = np.frombuffer(body, it, n, pos); pos += it.itemsize * n
                        if pname in ("vertex_indices", "vertex_index"):
                            lists.append(vals)
                    else:
                        pos += np.dtype(ptype).itemsize
            if name == "face":
                if any(len(v) != 3 for v in lists):
                    raise ValueError("PLY face that is not a triangle")
                F = _triangles(np.array(lists, dtype=np.int64))
    else:
        raise ValueError(f"PLY format {fmt!r} not understood")
    if X is None or F is None:
        raise ValueError("PLY without vertex or face element")
    return X, F


def _read_stl(data):
    """STL facets welded by exact (float32) position in order of first appearance, as authalic reads them."""
    if len(data) >= 84 and 84 + 50 * struct.unpack("<I", data[80:84])[0] == len(data):
        n = struct.unpack("<I", data[80:84])[0]
        dt = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
        P = np.frombuffer(data, dt, n, 84)["v"].reshape(-1, 3)
    else:
        nums = re.findall(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)", data)
        P = np.array(nums, dtype=np.float64).astype(np.float32).reshape(-1, 3)
    uniq, first, inverse = np.unique(P, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")     # unique rows in order of first appearance
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return uniq[order].astype(np.float64), rank[inverse.reshape(-1)].reshape(-1, 3).astype(np.int64)


def read_obj_vt(path):
    """Return (VT, FT) of an OBJ file written with per-corner texture coordinates (`f v/vt`, the torus
    map): VT #vt by 2, FT #F by 3 (0-based rows of VT, in the order of the faces)."""
    VT, FT = [], []
    with open(path, "rb") as fh:
        for line in fh.read().decode("utf-8", "replace").splitlines():
            t = line.split()
            if not t:
                continue
            if t[0] == "vt":
                VT.append([float(t[1]), float(t[2])])
            elif t[0] == "f":
                try:
                    FT.append([int(c.split("/")[1]) - 1 for c in t[1:4]])
                except (IndexError, ValueError):
                    raise ValueError(f"{path}: a face without texture coordinates: {line.strip()!r}") from None
    return np.array(VT, dtype=np.float64).reshape(-1, 2), _triangles(FT)


def face_areas(X, F):
    """Flat triangle areas, #F (chords on the sphere: the areas param-eval and the reports measure)."""
    if X.shape[1] == 2:
        X = np.hstack([X, np.zeros((len(X), 1))])
    return 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)


def surface_for_map(X, F, P, G):
    """Surface positions for every vertex of a map (P, G) of the surface (X, F), #P by 3.

    The map's vertices are the surface's, plus the midpoints of split edges (split_ends) after them.
    """
    Y = np.vstack([X, np.zeros((len(P) - len(X), 3))]) if len(P) >= len(X) else X
    for k, (u, v) in split_ends(X, F, P, G).items():
        Y[k] = 0.5 * (X[u] + X[v])
    return Y


def split_ends(X, F, P, G):
    """For each map vertex k after the surface's, the ends (u, v) of the surface edge it splits.

    Normally the map has the surface's vertices and faces. The square map may split interior edges
    whose ends lie on one side: each midpoint is appended after the input's vertices (and new faces
    after its faces). A later split can cut a face around an earlier midpoint, so the splits are
    undone from the last one back: the last midpoint has exactly four faces around it, its split
    edge joins two opposite neighbours (an edge of F between input vertices), and merging its faces
    in pairs across that edge gives the mesh before it was split. Its surface position is the
    midpoint of that edge.
    Returns {k: (u, v)} (empty when the map has the surface's vertices); raises ValueError when the
    map cannot be matched to the surface.
    """
    nv = len(X)
    if len(P) < nv or len(G) < len(F) or (len(P) == nv) != (len(G) == len(F)):
        raise ValueError(f"the map has {len(P)} vertices and {len(G)} faces, the surface {nv} and {len(F)}")
    if len(P) == nv:
        return {}
    e = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e.sort(axis=1)
    ein = set(map(tuple, e.tolist()))
    faces = {i: tuple(t) for i, t in enumerate(G.tolist()) if max(t) >= nv}
    around = {}
    for i, t in faces.items():
        for v in t:
            if v >= nv:
                around.setdefault(v, set()).add(i)
    ends = {}
    for k in range(len(P) - 1, nv - 1, -1):
        fk = sorted(around.get(k, ()))
        # Each face rotated to start at k: (k, x, y).
        rot = [faces[i][faces[i].index(k):] + faces[i][:faces[i].index(k)] for i in fk]
        ring = sorted({v for r in rot for v in r[1:]})
        pairs = [(u, v) for i, u in enumerate(ring) for v in ring[i + 1:]
                 if u < nv and v < nv and (u, v) in ein and not any({u, v} <= set(r) for r in rot)]
        if len(fk) != 4 or len(ring) != 4 or len(pairs) != 1:
            raise ValueError(f"map vertex {k} is not the midpoint of one split edge of the surface")
        u, v = pairs[0]
        ends[k] = (u, v)
        for i, r in zip(fk, rot):
            for w in r:
                if w >= nv:
                    around[w].discard(i)
            del faces[i]
            if r[1] in (u, v):  # (k, v, c) was (u, v, c) before the split; (k, u, d) was (v, u, d)
                t = ((v if r[1] == u else u),) + r[1:]
                faces[i] = t
                for w in t:
                    if w >= nv:
                        around.setdefault(w, set()).add(i)
    return ends


def face_count(path):
    """The number of faces of a mesh file, read cheaply (header counts; OBJ: counted 'f' lines).

    Used for resource estimates only; a file it cannot read gives an estimate from its size
    (one face per 20 bytes), or 0 when the file is missing.
    """
    try:
        size = os.path.getsize(path)
    except OSError:
        return 0
    ext = os.path.splitext(path)[1].lower()
    try:
        with open(path, "rb") as fh:
            if ext == ".off":
                toks = []
                for line in fh:
                    line = line.split(b"#", 1)[0].split()
                    toks += line
                    if len(toks) >= 3:
                        break
                toks = toks[1:] if toks[0].endswith(b"OFF") else toks
                return int(toks[1])
            if ext == ".ply":
                for line in fh:
                    t = line.split()
                    if t[:2] == [b"element", b"face"]:
                        return int(t[2])
                    if t[:1] == [b"end_header"]:
                        break
            if ext == ".stl":
                head = fh.read(84)
                if len(head) == 84 and 84 + 50 * struct.unpack("<I", head[80:84])[0] == size:
                    return struct.unpack("<I", head[80:84])[0]
                return (head + fh.read()).count(b"endfacet")
            if ext == ".obj":
                # Overlapping the chunks by two bytes counts a "\nf " that straddles a boundary once.
                n, tail = 0, b"\n"
                while True:
                    chunk = fh.read(1 << 24)
                    if not chunk:
                        return n
                    n += (tail + chunk).count(b"\nf ")
                    tail = chunk[-2:]
    except (ValueError, IndexError, OSError, struct.error):
        pass
    return size // 20

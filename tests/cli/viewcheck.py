"""viewcheck.py - checks of the `authalic view` page (view.sh): the page itself, and what headless Chromium
made of it (its console and its screenshot).

  viewcheck.py page PAGE.html [REPORT.json]   no http(s) URL; the data block parses; its figures match the report's
  viewcheck.py same A.html B.html             the two pages carry the same mesh, map and per-face values
  viewcheck.py shot CONSOLE.log SHOT.png      no JavaScript error; painted; the most squeezed face drawn squeezed
"""
import base64
import json
import re
import sys

import numpy as np


def data(path):
    text = open(path, encoding="utf-8").read()
    url = re.search(r"https?://", text, re.I)
    if url:
        sys.exit(f"{path}: names a URL at byte {url.start()}: {text[url.start():url.start() + 60]!r}")
    m = re.search(r'<script type="application/json" id="au-data">(.*?)</script>', text, re.S)
    if not m:
        sys.exit(f"{path}: no data block")
    return json.loads(m.group(1))


def floats(b64):
    return np.frombuffer(base64.b64decode(b64), dtype="<f4")


def page(path, report=None):
    d = data(path)
    logr = floats(d["logr"])
    if logr.size != d["nf"]:
        sys.exit(f"{path}: {logr.size} per-face values for {d['nf']} faces")
    if report:
        m = json.load(open(report))["metrics"]
        s = d["stats"]
        if s["folds"] != m["folds"] or abs(s["per_face"] - m["r_mean_abs_dev"]) > 1e-9 * max(1, m["r_mean_abs_dev"]):
            sys.exit(f"{path}: figures {s} differ from the report's folds {m['folds']} per-face {m['r_mean_abs_dev']}")
        # The page's per-face log r is the report's per-face r, face by face: their mean |r - 1| agrees.
        r = np.exp(logr[np.isfinite(logr)].astype(float))
        if abs(np.mean(np.abs(r - 1)) - m["r_mean_abs_dev"]) > 1e-5:
            sys.exit(f"{path}: mean |r-1| of the page's faces {np.mean(np.abs(r - 1))} != report {m['r_mean_abs_dev']}")
    print(f"{path}: {d['kind']}, {d['nf']} faces, no URL")


def positions(P):
    q = np.frombuffer(base64.b64decode(P["q"]), dtype="<u2").reshape(-1, P["dim"])
    return np.array(P["min"]) + q / 65535.0 * np.array(P["scale"])


def same(a, b):
    """A map written to a file and read back is the map to its printed digits: the same faces, positions
    within a 16-bit step of their boxes, per-face values within 1e-4."""
    da, db = data(a), data(b)
    for k in ("nv", "nf", "kind", "F", "Ft"):
        if da[k] != db[k]:
            sys.exit(f"{a} and {b} differ in {k}")
    for k in ("X", "M"):
        pa, pb = positions(da[k]), positions(db[k])
        step = np.max(np.array(da[k]["scale"])) / 65535.0
        if pa.shape != pb.shape or np.abs(pa - pb).max() > 1.5 * step:
            sys.exit(f"{a} and {b} differ in {k}")
    for k in ("logr", "lam"):
        fa, fb = floats(da[k]), floats(db[k])
        if not np.allclose(fa, fb, rtol=1e-4, atol=1e-4, equal_nan=True):
            sys.exit(f"{a} and {b} differ in {k}: {np.nanmax(np.abs(fa - fb))}")
    print(f"{a} and {b}: the same map")


def shot(log, png):
    import matplotlib.image as mpimg
    lines = open(log, encoding="utf-8", errors="replace").read().splitlines()
    bad = [x for x in lines if "AUTHALIC_ERROR" in x or "Uncaught" in x]
    if bad:
        sys.exit("JavaScript error: " + bad[0][:300])
    if not any("AUTHALIC_READY" in x for x in lines):
        sys.exit("the page did not finish (no AUTHALIC_READY on the console)")
    probes = [x for x in lines if "AUTHALIC_PROBE" in x]
    if not probes:
        sys.exit("no AUTHALIC_PROBE on the console")
    f = probes[-1].split("AUTHALIC_PROBE", 1)[1].split()
    x, y, want = float(f[0]), float(f[1]), np.array([int(v) for v in f[2:5]])
    img = mpimg.imread(png)
    if img.shape[:2] != (720, 1280):
        sys.exit(f"screenshot is {img.shape[1]}x{img.shape[0]}, expected 1280x720")
    rgb = np.rint(img[:, :, :3] * 255).astype(int)
    background = np.array([32, 33, 36])
    painted = np.abs(rgb - background).max(axis=2) > 8
    frac = painted.mean()
    colours = np.unique(rgb[painted].reshape(-1, 3), axis=0).shape[0]
    if frac < 0.15 or colours < 50:
        sys.exit(f"painted {frac:.1%} of the screenshot in {colours} colours (need 15% and 50)")
    picks = [x for x in lines if "AUTHALIC_PICK" in x]
    pf = picks[-1].split("AUTHALIC_PICK", 1)[1].split() if picks else ["none"]
    if pf[0] != f[6] or len(pf) < 3 or not pf[2].startswith("true"):
        sys.exit(f"the face picked under the most squeezed face's point is {pf[0]}, expected {f[6]} (marked: {pf[2:]})")
    i, j = int(round(y)), int(round(x))
    if not (0 <= i < 720 and 0 <= j < 1280):
        sys.exit(f"the most squeezed face is off the screen at ({x}, {y})")
    got = rgb[i, j]
    # The squeezed end of the scale is blue: the pixel is the scale's colour for that face, and blue.
    if np.abs(got - want).max() > 24 or not got[2] > got[0] + 60:
        sys.exit(f"pixel ({j}, {i}) over the most squeezed face is {got.tolist()}, expected {want.tolist()} (squeezed)")
    print(f"{png}: painted {frac:.1%} in {colours} colours; most squeezed face at ({j}, {i}) is {got.tolist()}")


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"page": page, "same": same, "shot": shot}[cmd](*args)

#!/usr/bin/python3
"""python_overhead.py - what the Python binding adds to a map's time (issue 23: under 5% on bunny).

    /usr/bin/python3 bench/python_overhead.py [MESH] [--rounds N]     (default ../shared/meshes/bunny.obj, 3)

In one process, alternately: (raw) au_map called directly through ctypes on arrays already in the
library's layout, the way a C caller calls it (no helper thread, no conversion, no copy, no JSON),
timed around the call; and (binding) authalic.sphere(V, F), timed around the call, which adds the
argument checks and conversions, the helper thread that makes Ctrl-C work, copying the result out
and the JSON report. Also the binding's own share inside each call: its wall time minus the
library's stage times in info["time"]["total"]. Prints the medians and the overhead in percent.
Uses the build's library unless AUTHALIC_LIBRARY says otherwise. Not a test: the machine's load
moves both columns; the per-call share (binding - library total) is the steadier figure.
"""
import argparse
import ctypes
import os
import statistics
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
os.environ.setdefault("AUTHALIC_LIBRARY", os.path.join(ROOT, "build", "libauthalic.so.1"))

import authalic  # noqa: E402  (first: it sets the thread defaults before numpy loads OpenBLAS)
from authalic import _lib  # noqa: E402


def raw_map(L, V, F):
    """au_map as a C caller calls it; returns the seconds of the call (the result freed after)."""
    res = ctypes.POINTER(_lib.Result)()
    msg = _lib.Msg()
    o = L.au_options_default()
    pv, pf = V.ctypes.data_as(_lib.P_double), F.ctypes.data_as(_lib.P_int)
    t0 = time.perf_counter()
    st = L.au_map(pv, V.shape[0], pf, F.shape[0], 0, ctypes.byref(o), ctypes.byref(res), ctypes.byref(msg))
    t = time.perf_counter() - t0
    L.au_result_free(ctypes.byref(res))
    if st < 0:
        sys.exit("au_map failed: %s" % msg.text.decode())
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh", nargs="?", default=os.path.join(ROOT, "..", "shared", "meshes", "bunny.obj"))
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    V, F = authalic.read_mesh(a.mesh)
    print("mesh %s: %d vertices, %d faces; library %s; OMP_THREAD_LIMIT=%s OPENBLAS_NUM_THREADS=%s" % (
        os.path.basename(a.mesh), V.shape[0], F.shape[0], authalic._L._name, os.environ.get("OMP_THREAD_LIMIT"),
        os.environ.get("OPENBLAS_NUM_THREADS")))
    raw, binding, share = [], [], []
    for k in range(a.rounds):
        raw.append(raw_map(authalic._L, V, F))
        t0 = time.perf_counter()
        S, info = authalic.sphere(V, F)
        binding.append(time.perf_counter() - t0)
        share.append(binding[-1] - info["time"]["total"])
        print("round %d: raw au_map %.3f s   authalic.sphere %.3f s   (of which outside the library's stages %.4f s)"
              % (k + 1, raw[-1], binding[-1], share[-1]))
    r, b, s = statistics.median(raw), statistics.median(binding), statistics.median(share)
    print("median: raw %.3f s, binding %.3f s: %+.1f%% (load-dependent); binding's own share %.4f s = %.2f%% of the map"
          % (r, b, 100 * (b - r) / r, s, 100 * s / r))


if __name__ == "__main__":
    main()

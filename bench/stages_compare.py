#!/usr/bin/python3
"""stages_compare.py BEFORE_DIR AFTER_DIR - one markdown table comparing two runs of bench/sphere_stages.sh
(its OUTDIRs: each mesh's report NAME.json, param-eval's NAME.eval.json and /usr/bin/time's NAME.time):
per mesh the steps, factorizations, per-face mean |r-1|, vertex mean |log r|, folds and CPU seconds before
and after. Run from the source root: /usr/bin/python3 bench/stages_compare.py /tmp/old /tmp/new"""
import json
import os
import sys


def row(d, n):
    try:
        r = json.load(open(os.path.join(d, n + ".json")))
        e = json.load(open(os.path.join(d, n + ".eval.json")))
        t = open(os.path.join(d, n + ".time")).read().split()
    except (OSError, ValueError):
        return None
    return {"F": r["F"], "steps": r["steps"], "fact": r.get("factorizations", "?"), "pf": e["r_mean_abs_dev"],
            "vx": e["vertex_logr_mean_abs"], "folds": e["folds"], "cpu": float(t[-2]) + float(t[-1])}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = sys.argv[1:3]
    names = sorted({f[:-5] for f in os.listdir(b) if f.endswith(".json") and not f.endswith(".eval.json")},
                   key=lambda n: (row(b, n) or {"F": 0})["F"])
    print("| mesh | F | steps | factorizations | per-face | vertex | folds | CPU s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for n in names:
        x, y = row(a, n), row(b, n)
        if not x or not y:
            print("| %s | missing | | | | | | |" % n)
            continue
        print("| %s | %d | %s -> %s | %s -> %s | %.4f -> %.4f | %.4f -> %.4f | %d -> %d | %.2f -> %.2f |" % (
            n, y["F"], x["steps"], y["steps"], x["fact"], y["fact"], x["pf"], y["pf"], x["vx"], y["vx"],
            x["folds"], y["folds"], x["cpu"], y["cpu"]))


main()

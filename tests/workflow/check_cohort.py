"""check_cohort.py - checks a finished cohort of the workflow against its own reports and inputs.

    check_cohort.py OUT MANIFEST PROG [--slurm JOBCOMP_LOG]

Asserts: cohort.tsv has the issue's columns and one row per manifest row, in order; every row's
declared outputs exist; for a mapped row (every id not starting with "bad"): status 0, empty error,
V, F, steps, seconds, folds and the metrics equal to its report.json's values exactly, F equal to
the input's face count, a map with V vertices, a preview PNG, a distortion file with one value per
vertex whose mean |ln| (the fallback's) equals the report's vertex_logr_mean_abs; for a bad row:
status 2, the error line the program itself prints for that input, empty metrics and empty
placeholder files; rows with an attribute file have attribute.png (or, when the file has the wrong
length, an empty one and a note saying so), rows with a density file ran
with --density. cohort.png is a PNG; cohort.md names the failed rows with their error line.
With --slurm: every row ran in a Slurm job that the Slurm job-completion log shows COMPLETED.
Prints one line per failed check and exits 1, else prints a summary line and exits 0.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "workflow", "scripts"))
import meshio_np  # noqa: E402

REQUIRED = ["id", "status", "V", "F", "steps", "seconds", "folds", "r_mean_abs_dev",
            "vertex_logr_mean_abs", "angle_diff_mean_deg", "error"]
METRICS = ["folds", "r_mean_abs_dev", "vertex_logr_mean_abs", "angle_diff_mean_deg"]
PNG = b"\x89PNG\r\n\x1a\n"
problems = []


def check(cond, msg):
    if not cond:
        problems.append(msg)
    return cond


def is_png(path):
    with open(path, "rb") as fh:
        return fh.read(8) == PNG and os.path.getsize(path) > 1000


def own_error_line(prog, command, path):
    """The error line the program prints for this input when run by hand."""
    with tempfile.TemporaryDirectory() as t:
        res = subprocess.run([prog, command, path, os.path.join(t, "m.obj")], capture_output=True, text=True)
    lines = [l for l in res.stderr.splitlines() if l.startswith("authalic: error:")]
    return res.returncode, (lines[-1] if lines else "")


def main(argv):
    out, manifest, prog = argv[:3]
    jobcomp = argv[argv.index("--slurm") + 1] if "--slurm" in argv else None
    base = os.path.dirname(os.path.abspath(manifest))
    with open(manifest) as fh:
        mrows = list(csv.DictReader(fh, delimiter="\t"))
    for r in mrows:
        r["input"] = os.path.normpath(os.path.join(base, r["input"]))
    tsv = os.path.join(out, "cohort.tsv")
    if not check(os.path.exists(tsv), f"{tsv} is missing"):
        return report()
    with open(tsv) as fh:
        rows = list(csv.DictReader(fh, delimiter="\t", quoting=csv.QUOTE_NONE))
        header = rows and list(rows[0].keys())
    missing = [c for c in REQUIRED if c not in (header or [])]
    check(not missing, f"cohort.tsv lacks the columns {missing}")
    check([r["id"] for r in rows] == [r["id"] for r in mrows],
          f"cohort.tsv ids {[r['id'] for r in rows]} differ from the manifest's {[r['id'] for r in mrows]}")
    slurm_ids = {}
    for m, t in zip(mrows, rows):
        i = m["id"]
        d = os.path.join(out, "surfaces", i)
        dist = [f for f in ("distortion.txt", "distortion.curv") if os.path.exists(os.path.join(d, f))]
        for f in ("status.json", "map.obj", "report.json", "preview.png", "log.txt"):
            check(os.path.exists(os.path.join(d, f)), f"{i}: {f} is missing")
        if not check(len(dist) == 1, f"{i}: no distortion file (or two)") or problems:
            continue
        st = json.load(open(os.path.join(d, "status.json")))
        check(str(st["status"]) == t["status"], f"{i}: tsv status {t['status']} but status.json {st['status']}")
        slurm_ids[i] = st.get("slurm_job_id", "")
        if i.startswith("bad"):
            rc, line = own_error_line(prog, m["command"], m["input"])
            check(t["status"] == "2" and rc == 2, f"{i}: status {t['status']} (the program alone: {rc}), expected 2")
            check(t["error"] == line and line, f"{i}: error {t['error']!r}, the program prints {line!r}")
            for c in REQUIRED[2:-1]:
                check(t[c] == "", f"{i}: failed row has {c}={t[c]!r}")
            for f in ("map.obj", "report.json", "preview.png", dist[0]):
                check(os.path.getsize(os.path.join(d, f)) == 0, f"{i}: {f} of a failed row is not empty")
            continue
        check(t["status"] == "0" and t["error"] == "", f"{i}: status {t['status']} error {t['error']!r}")
        rep = json.load(open(os.path.join(d, "report.json")))
        final = rep.get("final") or rep["metrics"]
        want = {"V": rep["V"], "F": rep["F"], "steps": rep["steps"], "seconds": rep["time"]["total"]}
        want.update({k: final[k] for k in METRICS})
        for k, v in want.items():
            try:
                got = float(t[k])
            except ValueError:
                got = None
            check(got == float(v), f"{i}: tsv {k}={t[k]!r}, report {v!r}")
        X, F = meshio_np.read_mesh(m["input"])
        check(rep["F"] >= len(F) and (rep["F"] == len(F) or m["command"] == "square"),
              f"{i}: report F={rep['F']}, the input has {len(F)} faces")
        P, G = meshio_np.read_mesh(os.path.join(d, "map.obj"))
        check(len(P) == rep["V"] and len(G) == rep["F"], f"{i}: map has {len(P)} vertices, {len(G)} faces")
        check(is_png(os.path.join(d, "preview.png")), f"{i}: preview.png is not a PNG picture")
        view = os.path.join(d, "view.html")
        if os.path.exists(view):  # a program with `authalic view`: the page, linked from cohort.md
            page = open(view, encoding="utf-8").read()
            check('id="au-data">{"v":1,' in page and f'"nf":{rep["F"]},' in page and "http://" not in page,
                  f"{i}: view.html is not the page of its {rep['F']}-face map")
            check(f"(surfaces/{i}/view.html)" in open(os.path.join(out, "cohort.md")).read(),
                  f"{i}: cohort.md does not link its view.html")
        if m.get("attribute"):
            nval = len(open(os.path.normpath(os.path.join(base, m["attribute"]))).read().split())
            if nval == len(X):
                check(is_png(os.path.join(d, "attribute.png")), f"{i}: attribute.png is missing or not a PNG")
            else:  # a wrong attribute file: an empty picture and a note, the row still mapped
                check(os.path.getsize(os.path.join(d, "attribute.png")) == 0, f"{i}: attribute.png of a bad attribute file")
                check(t["notes"].startswith("attribute.png: ") and f"{nval} values" in t["notes"],
                      f"{i}: notes {t['notes']!r} do not say the attribute file has {nval} values")
                t["notes"] = ""
        check(t["notes"] == "", f"{i}: notes {t['notes']!r}")
        if m.get("density"):
            dens = os.path.normpath(os.path.join(base, m["density"]))
            check(st["argv"][st["argv"].index("--density") + 1] == dens if "--density" in st["argv"] else False,
                  f"{i}: did not run with --density {dens}: {st['argv']}")
        if dist[0] == "distortion.curv":
            # Written by `authalic --distortion`: a FreeSurfer curv file (float32), read with nibabel.
            import nibabel.freesurfer
            vals = [float(x) for x in nibabel.freesurfer.read_morph_data(os.path.join(d, dist[0]))]
        else:
            vals = [float(x) for x in open(os.path.join(d, dist[0])).read().split()]
        check(len(vals) == len(P), f"{i}: {len(vals)} distortion values for {len(P)} vertices")
        mean = sum(abs(v) for v in vals) / max(len(vals), 1) * math.log(2)
        if m["command"] == "torus":
            # One value per input vertex, a seam vertex's copies in one cell; the report measures the
            # mesh cut along the seams (as param-eval does), so the cells are recomputed here.
            import numpy as np
            VT, FT = meshio_np.read_obj_vt(os.path.join(d, "map.obj"))
            ad, asurf = meshio_np.face_areas(VT, FT), meshio_np.face_areas(P, G)
            cd = np.bincount(G.reshape(-1), np.repeat(ad / 3, 3), len(P))
            cs = np.bincount(G.reshape(-1), np.repeat(asurf / 3, 3), len(P))
            want = np.log2((cd / cd.sum()) / (cs / cs.sum()))
            diff = float(np.abs(np.array(vals) - want).max())
            check(diff <= 1e-6, f"{i}: torus distortion differs from the map's vertex cells by {diff}")
            check(0 < mean <= 1.5 * final["vertex_logr_mean_abs"],
                  f"{i}: torus distortion mean |ln| {mean} vs report {final['vertex_logr_mean_abs']}")
        else:
            # float32 values in a curv file: agreement to float32 rounding
            check(abs(mean - final["vertex_logr_mean_abs"]) <= 1e-6 * final["vertex_logr_mean_abs"] + 1e-9,
                  f"{i}: distortion mean |ln| {mean} vs report vertex_logr_mean_abs {final['vertex_logr_mean_abs']}")
    check(is_png(os.path.join(out, "cohort.png")), "cohort.png is not a PNG picture")
    md = open(os.path.join(out, "cohort.md")).read() if os.path.exists(os.path.join(out, "cohort.md")) else ""
    for t in rows:
        if t["status"] != "0":
            check(t["id"] in md and t["error"] in md, f"cohort.md does not name {t['id']} and its error")
    if jobcomp:
        log = open(jobcomp).read() if os.path.exists(jobcomp) else ""
        done = {w.split("=")[1] for line in log.splitlines() if "JobState=COMPLETED" in line
                for w in line.split() if w.startswith("JobId=")}
        for i, j in slurm_ids.items():
            check(j != "", f"{i}: its map did not run in a Slurm job (no SLURM_JOB_ID)")
            check(j in done, f"{i}: Slurm job {j!r} is not COMPLETED in {jobcomp}")
        check(len(set(slurm_ids.values())) == len(slurm_ids), f"rows share Slurm jobs: {slurm_ids}")
        # map and preview per row, and a distortion job where the fallback wrote distortion.txt
        per_row = 2 + all(os.path.exists(os.path.join(out, "surfaces", t["id"], "distortion.txt")) for t in rows)
        check(len(done) >= per_row * len(rows),
              f"{len(done)} completed Slurm jobs for {len(rows)} rows ({per_row} jobs a row)")
    return report(len(rows))


def report(n=0):
    for p in problems:
        print("FAIL:", p, file=sys.stderr)
    if problems:
        return 1
    print(f"check_cohort: {n} rows agree with their reports, inputs and status files")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

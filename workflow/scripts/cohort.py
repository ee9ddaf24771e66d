"""cohort.py - the cohort summary of the workflow: cohort.tsv, cohort.png and cohort.md.

Called by the Snakefile's `cohort` rule as write_cohort(rows, ...); also a command for reruns by
hand: cohort.py OUT_DIR [ID ...] (without IDs: every surfaces/*/status.json under OUT_DIR).

cohort.tsv has one row per surface, in manifest order. From the row's status.json (run_map.py):
id, status (authalic's exit status), error (its error line, empty when none), command, input,
wall_seconds, slurm_job_id; from its report (authalic --report), empty when the map failed:
V, F, steps, seconds (the report's time.total), converged, folds, r_mean_abs_dev,
vertex_logr_mean_abs, angle_diff_mean_deg, upsilon_mean_abs, lambda_mean, r_cv (all from the
report's final metrics; atlas: from status.json's `metrics`, which run_map.py measures); notes: what went wrong with a mapped surface's other products (a preview,
distortion or attribute script that failed leaves its file empty and its message in FILE.error).
"""
import csv
import glob
import json
import math
import os
import sys

COLUMNS = ["id", "status", "V", "F", "steps", "seconds", "folds", "r_mean_abs_dev",
           "vertex_logr_mean_abs", "angle_diff_mean_deg", "error",
           "command", "input", "converged", "upsilon_mean_abs", "lambda_mean", "r_cv",
           "wall_seconds", "slurm_job_id", "notes"]
METRICS = ["folds", "r_mean_abs_dev", "vertex_logr_mean_abs", "angle_diff_mean_deg",
           "upsilon_mean_abs", "lambda_mean", "r_cv"]


def _fmt(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)  # shortest round-trip form: the tsv holds the report's value exactly
    return str(v).replace("\t", " ").replace("\n", " ")


def read_row(status_path, report_path):
    """One cohort row (a dict over COLUMNS) from a surface's status.json and report.json."""
    st = json.load(open(status_path))
    row = {c: None for c in COLUMNS}
    for k in ("id", "status", "error", "command", "input", "wall_seconds", "slurm_job_id"):
        row[k] = st.get(k)
    notes = [open(e).read().strip() for e in sorted(glob.glob(os.path.join(os.path.dirname(status_path), "*.error")))]
    row["notes"] = "; ".join(notes)
    view = os.path.join(os.path.dirname(status_path), "view.html")
    row["view"] = os.path.exists(view) and os.path.getsize(view) > 0  # linked from cohort.md, not a tsv column
    if st["status"] == 0 and os.path.getsize(report_path) > 0:
        rep = json.load(open(report_path))
        # atlas: its report has vertices/faces, flow.steps, per-stage times and no metrics block;
        # run_map.py measured its map into status.json's `metrics`.
        final = rep.get("final") or rep.get("metrics") or st.get("metrics") or {}
        times = rep.get("time") or {}
        seconds = times.get("total")
        if seconds is None and times:
            seconds = sum(v for v in times.values() if isinstance(v, (int, float)))
        row.update(V=rep.get("V", rep.get("vertices")), F=rep.get("F", rep.get("faces")),
                   steps=rep.get("steps", (rep.get("flow") or {}).get("steps")),
                   seconds=seconds, converged=rep.get("converged"))
        for k in METRICS:
            row[k] = final.get(k, rep.get(k))
    return row


def write_tsv(rows, path):
    with open(path + ".tmp", "w", newline="") as fh:
        w = csv.writer(fh, delimiter="\t", lineterminator="\n", quoting=csv.QUOTE_NONE, escapechar="\\")
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow([_fmt(r[c]) for c in COLUMNS])
    os.replace(path + ".tmp", path)


def _worst(rows, key, n):
    ok = [r for r in rows if r[key] is not None and not (isinstance(r[key], float) and math.isnan(r[key]))]
    return sorted(ok, key=lambda r: r[key], reverse=True)[:n]


PLOTS = [("r_mean_abs_dev", "per-face mean |r-1|", True),
         ("vertex_logr_mean_abs", "vertex mean |log r|", True),
         ("angle_diff_mean_deg", "mean angle difference (deg)", False),
         ("seconds", "seconds (authalic's own)", True)]


def write_png(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ok = [r for r in rows if r["status"] == 0]
    failed = [r for r in rows if r["status"] != 0]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    for ax, (key, label, logx) in zip(axes.flat, PLOTS):
        vals = [r[key] for r in ok if r[key] is not None and r[key] > 0]
        if key == "seconds":  # time against size says more than a histogram of times
            pts = [(r["F"], r[key], r["id"]) for r in ok if r["F"] and r[key]]
            if pts:
                ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=12, color="darkred")
                ax.set_xscale("log")
                ax.set_yscale("log")
                for f, t, name in sorted(pts, key=lambda p: p[1], reverse=True)[:3]:
                    ax.annotate(name, (f, t), fontsize=8, xytext=(3, 3), textcoords="offset points")
            ax.set_xlabel("faces")
            ax.set_ylabel(label)
            continue
        if vals:
            lo, hi = min(vals), max(vals)
            if logx and hi > lo:
                bins = [lo * (hi / lo) ** (i / 30) for i in range(31)]
                ax.set_xscale("log")
            else:
                bins = 30
            ax.hist(vals, bins=bins, color="darkred" if key != "angle_diff_mean_deg" else "steelblue")
            for i, r in enumerate(_worst(ok, key, 3)):
                ax.axvline(r[key], color="k", lw=0.6, ls=":")
                ax.annotate(r["id"], (r[key], 1 - 0.08 * (i + 1)), xycoords=("data", "axes fraction"),
                            ha="right", fontsize=8, rotation=0)
        ax.set_xlabel(label)
        ax.set_ylabel("surfaces")
    title = f"authalic cohort: {len(ok)} mapped, {len(failed)} failed"
    if failed:
        title += " (" + ", ".join(f"{r['id']}: {r['status']}" for r in failed[:6]) + (", ..." if len(failed) > 6 else "") + ")"
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=80)
    plt.close(fig)
    os.replace(path + ".tmp.png", path)


def write_md(rows, path):
    ok = [r for r in rows if r["status"] == 0]
    failed = [r for r in rows if r["status"] != 0]
    out = ["# authalic cohort", "",
           f"{len(rows)} surfaces: {len(ok)} mapped, {len(failed)} failed. "
           "Per-surface rows: `cohort.tsv`; distributions: `cohort.png`; each surface's map, report, "
           "preview, distortion, status and log: `surfaces/ID/`.", ""]
    if ok:
        out += ["| metric | median | worst | worst surfaces |", "|---|---:|---:|---|"]
        for key, label, _ in PLOTS + [("folds", "folds", False)]:
            vals = sorted(r[key] for r in ok if r[key] is not None)
            if not vals:
                continue
            worst = _worst(ok, key, 3)
            out.append(f"| {label} | {vals[len(vals) // 2]:.4g} | {worst[0][key]:.4g} | "
                       + ", ".join(f"{r['id']} ({r[key]:.3g})" for r in worst) + " |")
        notconv = [r["id"] for r in ok if r["converged"] is False]
        out += ["", f"Not converged to the tolerance: {', '.join(notconv) if notconv else 'none'}.", ""]
    views = [r["id"] for r in ok if r.get("view")]
    if views:
        out += ["## Views", "", "Each map as an interactive page (the surface and its map side by side; docs/view.md):", ""]
        out += [", ".join(f"[{i}](surfaces/{i}/view.html)" for i in views), ""]
    noted = [r for r in ok if r["notes"]]
    if noted:
        out += ["## Mapped, but a product failed", "", "| id | notes |", "|---|---|"]
        out += [f"| {r['id']} | {r['notes'].replace('|', '/')} |" for r in noted]
        out += ["", "A fixed input or attribute file redoes its product by itself; otherwise "
                "`--forcerun surfaces/ID/FILE`.", ""]
    if failed:
        out += ["## Failed", "", "| id | status | error |", "|---|---:|---|"]
        out += [f"| {r['id']} | {r['status']} | {(r['error'] or '').replace('|', '/')} |" for r in failed]
        out += ["", "Exit status 2: bad input or options (fix the row and rerun: only it is redone); "
                "1: internal failure. A failed row is not retried unless its input or options change "
                "(or: `--forcerun surfaces/ID/status.json`).", ""]
    with open(path + ".tmp", "w") as fh:
        fh.write("\n".join(out))
    os.replace(path + ".tmp", path)


def write_cohort(ids, out_dir=".", tsv="cohort.tsv", png="cohort.png", md="cohort.md"):
    """Read surfaces/ID/{status,report}.json under out_dir for every id; write the three summaries."""
    rows = [read_row(os.path.join(out_dir, "surfaces", i, "status.json"),
                     os.path.join(out_dir, "surfaces", i, "report.json")) for i in ids]
    write_tsv(rows, os.path.join(out_dir, tsv))
    write_png(rows, os.path.join(out_dir, png))
    write_md(rows, os.path.join(out_dir, md))
    return rows


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    out_dir, ids = argv[0], argv[1:]
    if not ids:
        ids = sorted(d for d in os.listdir(os.path.join(out_dir, "surfaces"))
                     if os.path.exists(os.path.join(out_dir, "surfaces", d, "status.json")))
    write_cohort(ids, out_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""run_map.py - run one `authalic` map for the workflow and record how it ended.

    run_map.py --authalic PROG --command sphere|disk|annulus|square|torus|circles|atlas --input IN --map MAP.obj
               --report R.json --status S.json --log L.txt [--density FILE] [--distortion D] [--html V.html]
               [--options "EXTRA OPTIONS"] [--id ID]

A surface that fails must not stop the cohort, and a rerun must not retry it unless its input or
options change. So this wrapper always exits 0 once it has run the program (whatever the program's
exit status) and always leaves every declared output: on failure MAP, R.json and D are empty files
(0 bytes), and S.json says what happened. S.json holds: id, command, input, status (the program's
exit status; 128+N when it was killed by signal N), error (the program's `authalic: error: ...` line,
else its last line of stderr; empty on success), wall_seconds, argv, host and slurm_job_id (the
SLURM_JOB_ID of the job it ran in, empty outside Slurm). L.txt gets the program's stderr.

Command atlas: its report has no `metrics` block and the program has no --distortion, so after a
successful run this script computes them from MAP (vt_metrics.py, param-eval's definitions): S.json
gets `metrics` (the cohort's metric columns) and D the per-vertex distortion.
"""
import argparse
import json
import os
import shlex
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def atlas_products(map_path, distortion):
    """The metrics of an atlas map (a dict) and, when asked, its distortion file."""
    import vt_metrics
    X, F, VT, FT = vt_metrics.read_map(map_path)
    if distortion:
        vt_metrics.write_distortion(distortion, vt_metrics.vertex_distortion(X, F, VT, FT), len(F))
    return vt_metrics.metrics(X, F, VT, FT)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--authalic", required=True)
    ap.add_argument("--command", required=True)
    ap.add_argument("--input", required=True)
    ap.add_argument("--map", required=True)
    ap.add_argument("--report", required=True)
    ap.add_argument("--status", required=True)
    ap.add_argument("--log", required=True)
    ap.add_argument("--density", default="")
    ap.add_argument("--distortion", default="")
    ap.add_argument("--html", default="", help="the map's interactive page (authalic --html)")
    ap.add_argument("--options", default="")
    ap.add_argument("--id", default="")
    a = ap.parse_args()

    argv = [a.authalic, a.command, a.input, a.map, "--report", a.report]
    if a.density:
        argv += ["--density", a.density]
    if a.distortion and a.command != "atlas":
        argv += ["--distortion", a.distortion]
    if a.html:
        argv += ["--html", a.html]
    argv += shlex.split(a.options)

    outputs = [a.map, a.report] + ([a.distortion] if a.distortion else []) + ([a.html] if a.html else [])
    for p in outputs + [a.status, a.log]:
        os.makedirs(os.path.dirname(os.path.abspath(p)), exist_ok=True)
    t0 = time.monotonic()
    try:
        res = subprocess.run(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        rc, stderr = res.returncode, (res.stdout + res.stderr).decode("utf-8", "replace")
    except OSError as e:  # the program could not be started at all
        rc, stderr = 127, f"authalic: error: cannot run {a.authalic}: {e}\n"
    seconds = time.monotonic() - t0
    # subprocess gives -N for a death by signal N; a shell would say 128+N.
    status = rc if rc >= 0 else 128 - rc
    with open(a.log, "w") as log:
        log.write(stderr)
    error = ""
    if status != 0:
        lines = [l.strip() for l in stderr.splitlines() if l.strip()]
        errs = [l for l in lines if l.startswith("authalic: error:")]
        error = errs[-1] if errs else (lines[-1] if lines else f"exit status {status}, no message")
        if rc < 0:
            error = f"killed by signal {-rc}" + (f" ({error})" if lines else "")
    mine = [a.distortion] if a.command == "atlas" else []  # written below, not by authalic
    missing = [p for p in outputs if p not in mine and not os.path.exists(p)]
    if status == 0 and missing:
        status, error = 1, "authalic exited 0 but did not write " + ", ".join(missing)
    metrics = None
    if status == 0 and a.command == "atlas":
        try:
            metrics = atlas_products(a.map, a.distortion)
        except Exception as e:  # noqa: BLE001 - a map this script cannot read is the row's failure
            status, error = 1, f"authalic atlas exited 0 but its map could not be measured: {type(e).__name__}: {e}"
    if status != 0:
        # Declared outputs must exist for the workflow; empty files stand for "not produced".
        for p in outputs:
            open(p, "wb").close()
    record = {
        "id": a.id, "command": a.command, "input": a.input, "options": a.options,
        "status": status, "error": error, "wall_seconds": round(seconds, 3),
        "argv": argv, "host": socket.gethostname(),
        "slurm_job_id": os.environ.get("SLURM_JOB_ID", ""),
    }
    if metrics is not None:
        record["metrics"] = metrics
    tmp = a.status + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(record, fh, indent=1)
        fh.write("\n")
    os.replace(tmp, a.status)
    return 0


if __name__ == "__main__":
    sys.exit(main())

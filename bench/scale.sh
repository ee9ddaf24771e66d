#!/usr/bin/env bash
# scale.sh - how `authalic sphere` grows with mesh size: generated closed genus-0 meshes of about
# 10k to 1M faces (bench/mkbig.c), each mapped under /usr/bin/time -v; prints a markdown table.
set -u

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$root/build
sizes="10000 30000 100000 300000 1000000"
out=""
args=""
limit=0
eval_max=0
table_only=0

usage() {
  cat <<EOF
usage: bench/scale.sh [--build DIR] [--sizes "10000 30000 ..."] [--out DIR] [--args "..."] [--timeout SEC]
                      [--eval-max FACES] [--table-only]
For each size S it generates DIR/big_S.obj with au_mkbig (skipped when present), runs
'/usr/bin/time -v authalic sphere DIR/big_S.obj DIR/big_S.sphere.obj --report DIR/big_S.json --quiet ARGS'
and tabulates faces, steps, stage times, wall and CPU time, peak memory and the flow's milliseconds per
(step x 1k faces). On a busy machine compare the CPU column (user + system seconds), not the wall one.
  --build DIR      build directory holding authalic and au_mkbig (default: build)
  --sizes LIST     face counts to generate (default: "$sizes")
  --out DIR        where meshes, maps, reports and scale.md go (default: BUILD/scale)
  --args ARGS      extra arguments for authalic, split on spaces (default: none)
  --timeout SEC    stop a map after SEC seconds and count it as failed (default: 0, no limit)
  --eval-max F     also run ../shared/tools/param-eval on maps of at most F faces (default: 0, never)
  --table-only     map nothing; rebuild OUT/scale.md from the results of an earlier run in OUT
Exit status: 0 all maps succeeded, 1 some map failed, 2 bad usage or missing programs.
EOF
}

while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --table-only) table_only=1; shift ;;
    --build|--sizes|--out|--args|--timeout|--eval-max)
      if [ $# -lt 2 ]; then echo "scale: $1 needs a value" >&2; exit 2; fi
      case $1 in
        --build) build=$2 ;; --sizes) sizes=$2 ;; --out) out=$2 ;; --args) args=$2 ;; --timeout) limit=$2 ;;
        --eval-max) eval_max=$2 ;;
      esac
      shift 2 ;;
    *) echo "scale: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case $limit in ''|*[!0-9]*) echo "scale: --timeout needs a whole number of seconds" >&2; exit 2 ;; esac
case $eval_max in ''|*[!0-9]*) echo "scale: --eval-max needs a whole number of faces" >&2; exit 2 ;; esac
[ -n "$out" ] || out=$build/scale
bin=$build/authalic
gen=$build/au_mkbig
for p in "$bin" "$gen"; do
  if [ ! -x "$p" ]; then
    echo "scale: $p is missing; build it first (cmake --build $build --target authalic au_mkbig)" >&2
    exit 2
  fi
done
if [ ! -x /usr/bin/time ] || [ ! -x /usr/bin/python3 ]; then
  echo "scale: /usr/bin/time and /usr/bin/python3 are needed (scripts/setup-debian.sh installs them)" >&2
  exit 2
fi
guard=()
if [ "$limit" -gt 0 ]; then guard=(timeout "$limit"); fi
read -r -a extra <<<"$args"
mkdir -p "$out" || exit 2
evaluator=$(cd "$root/.." && pwd)/shared/tools/param-eval

rows=$out/rows.tsv
failed=0
[ "$table_only" -eq 1 ] && sizes=""
[ "$table_only" -eq 1 ] || : >"$rows" || exit 2
for s in $sizes; do
  mesh=$out/big_$s.obj
  if [ ! -s "$mesh" ]; then
    echo "scale: generating $mesh ..." >&2
    "$gen" "$s" "$mesh" || { echo "scale: au_mkbig $s failed" >&2; exit 1; }
  fi
  base=$out/big_$s
  rm -f "$base.sphere.obj" "$base.json" "$base.time" "$base.err" "$base.eval.json"
  echo "scale: mapping $s faces ..." >&2
  # The timer wraps the guard: Linux passes a reaped child's peak RSS up to its parent.
  /usr/bin/time -v -o "$base.time" ${guard[@]+"${guard[@]}"} "$bin" sphere "$mesh" "$base.sphere.obj" \
    --report "$base.json" --quiet ${extra[@]+"${extra[@]}"} 2>"$base.err" >/dev/null
  rc=$?
  if [ "$rc" -ne 0 ]; then
    failed=1
    echo "scale: $s: exit $rc: $(tail -n 1 "$base.err")" >&2
  fi
  if [ "$rc" -eq 0 ] && [ "$eval_max" -gt 0 ] && [ "$s" -le "$eval_max" ] && [ -x "$evaluator" ]; then
    "$evaluator" "$mesh" "$base.sphere.obj" --json >"$base.eval.json" 2>>"$base.err" || rm -f "$base.eval.json"
  fi
  printf '%s\t%s\t%s\n' "$s" "$rc" "$base" >>"$rows"
done

/usr/bin/python3 - "$rows" "$out/scale.md" "$bin" <<'EOF'
import json, os, re, sys
rows, md, binpath = sys.argv[1], sys.argv[2], sys.argv[3]

def timev(path):
    # Fields of /usr/bin/time -v: wall clock (h:mm:ss or m:ss.cc) and peak RSS in KiB.
    wall = rss = None
    cpu = 0.0
    try:
        for line in open(path):
            line = line.strip()
            if line.startswith("User time (seconds)") or line.startswith("System time (seconds)"):
                cpu += float(line.rsplit(" ", 1)[1])
            elif line.startswith("Elapsed (wall clock) time"):
                t = line.rsplit(" ", 1)[1].split(":")
                wall = sum(float(x) * 60 ** i for i, x in enumerate(reversed(t)))
            elif line.startswith("Maximum resident set size"):
                rss = int(line.rsplit(" ", 1)[1])
    except OSError:
        pass
    return wall, rss, cpu

head = ["target F", "V", "F", "steps", "t_read s", "t_init s", "t_flow s", "wall s", "cpu s", "peak MB",
        "flow ms / (step x 1k F)", "folds", "vertex_logr_mean_abs", "param-eval r_mean_abs_dev", "note"]
out = []
for line in open(rows):
    s, rc, base = line.rstrip("\n").split("\t")
    wall, rss, cpu = timev(base + ".time")
    r = [s] + [""] * (len(head) - 1)
    r[7] = "%.2f" % wall if wall is not None else "-"
    r[8] = "%.2f" % cpu if wall is not None else "-"
    r[9] = "%.0f" % (rss / 1024) if rss is not None else "-"
    rep = None
    if rc == "0":
        try:
            rep = json.load(open(base + ".json"))
        except (OSError, ValueError):
            pass
    if rep:
        tm = rep.get("time", {})
        fin = rep.get("metrics", {})
        st = rep.get("steps", 0)
        nf = rep.get("F", 0)
        r[1], r[2], r[3] = str(rep.get("V", "-")), str(nf), str(st)
        r[4] = "%.2f" % tm.get("read", 0)
        r[5] = "%.2f" % tm.get("init", 0)
        r[6] = "%.2f" % tm.get("flow", 0)
        if st and nf:
            r[10] = "%.3f" % (1000 * tm.get("flow", 0) / (st * nf / 1000))
        r[11] = str(rep.get("folds", "-"))
        v = fin.get("vertex_logr_mean_abs")
        r[12] = "%.3g" % v if isinstance(v, (int, float)) else "-"
        if not rep.get("converged", False):
            r[14] = "not converged"
    else:
        err = ""
        try:
            err = open(base + ".err").read().strip().splitlines()[-1]
        except (OSError, IndexError):
            pass
        r[14] = "FAIL: exit %s: %s" % (rc, err)
    try:
        ev = json.load(open(base + ".eval.json"))
        r[13] = "%.3g" % ev["r_mean_abs_dev"]
    except (OSError, ValueError, KeyError, TypeError):
        r[13] = "-"
    out.append(r)
w = [max(len(h), *(len(x[i]) for x in out)) if out else len(h) for i, h in enumerate(head)]
lines = ["authalic sphere scaling on generated meshes (%s; bench/scale.sh)" % binpath, "",
         "| " + " | ".join(h.ljust(w[i]) for i, h in enumerate(head)) + " |",
         "|" + "|".join("-" * (w[i] + 2) for i in range(len(head))) + "|"]
for x in out:
    lines.append("| " + " | ".join(x[i].rjust(w[i]) if i < 14 else x[i].ljust(w[i]) for i in range(len(head))) + " |")
text = "\n".join(lines) + "\n"
open(md, "w").write(text)
sys.stdout.write(text)
EOF
exit $failed

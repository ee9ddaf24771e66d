#!/usr/bin/env bash
# bench.sh - maps the closed genus-0 meshes of ../shared/meshes onto the sphere and tabulates time, memory and quality.
set -u

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
shared=$(cd "$root/.." && pwd)/shared
all_meshes="spot_lowres.obj cow.off spot.obj hippocampus.obj cheburashka.off blub.obj hand_closed.obj
maxplanck.obj bunny.obj nefertiti.obj ferret_brain_sim.off armadillo.obj brain.obj lion_statue.obj"
meshes=$all_meshes
out=$root/build/bench
bin=$root/build/authalic
args=""
limit=0
runs=1
results=""
extras=1

usage() {
  cat <<EOF
usage: bench/bench.sh [--meshes "a.obj b.off"] [--out DIR] [--args "..."] [--bin PATH] [--timeout SEC] [--runs N]
                      [--results FILE [--no-extras]]
Maps each mesh with 'authalic sphere IN OUT.obj --report R.json --quiet ARGS' under /usr/bin/time,
evaluates the result with ../shared/tools/param-eval, prints a table and writes it to DIR/bench.md.
  --meshes LIST  meshes of ../shared/meshes to run (default: all 14 closed genus-0 meshes)
  --out DIR      where maps, reports and bench.md go (default: build/bench)
  --args ARGS    extra arguments for authalic, split on spaces (default: none)
  --bin PATH     the authalic program (default: build/authalic)
  --timeout SEC  stop a map after SEC seconds and count it as failed (default: 0, no limit)
  --runs N       map each mesh N times and keep the run with the least init + flow time (the maps are
                 the same; on a shared machine the times of one run vary by 20% and more) (default: 1)
  --results FILE the committed results page (make bench: bench/RESULTS.md): a header with the date, the
                 commit, the CPU model, its cores and the load average at the start (the machine may be
                 shared), then this table, bench/planar.sh's planar maps and bench/thin_limbs.sh's table
  --no-extras    with --results: the sphere table only (no planar maps, no thin limbs)
Exit status: 0 all maps ran (or ../shared/meshes is absent), 1 some map failed, 2 bad usage.
EOF
}

while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --no-extras) extras=0; shift ;;
    --meshes|--out|--args|--bin|--timeout|--runs|--results)
      if [ $# -lt 2 ]; then echo "bench: $1 needs a value" >&2; exit 2; fi
      case $1 in
        --meshes) meshes=$2 ;; --out) out=$2 ;; --args) args=$2 ;; --bin) bin=$2 ;; --timeout) limit=$2 ;;
        --runs) runs=$2 ;; --results) results=$2 ;;
      esac
      shift 2 ;;
    *) echo "bench: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case $limit in ''|*[!0-9]*) echo "bench: --timeout needs a whole number of seconds" >&2; exit 2 ;; esac
case $runs in ''|*[!0-9]*|0) echo "bench: --runs needs a whole number >= 1" >&2; exit 2 ;; esac

if [ ! -d "$shared/meshes" ]; then
  echo "bench: $shared/meshes is absent; nothing to benchmark (skipped)"
  exit 0
fi
if [ ! -x "$bin" ]; then
  echo "bench: $bin is missing; build it first (cmake --build build --target authalic)" >&2
  exit 2
fi
if [ ! -x /usr/bin/python3 ]; then
  echo "bench: /usr/bin/python3 is needed for param-eval and the table" >&2
  exit 2
fi
timer=()
if [ -x /usr/bin/time ]; then timer=(/usr/bin/time -f %M -o "$out/.rss"); else echo "bench: /usr/bin/time is absent; no peak memory" >&2; fi
guard=()
if [ "$limit" -gt 0 ]; then guard=(timeout "$limit"); fi
read -r -a extra <<<"$args"
mkdir -p "$out" || exit 2
load_start=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)
tsv=$out/results.tsv
: >"$tsv" || exit 2

# One row per mesh: name, status, wall seconds, peak KiB, report path, param-eval path, message.
for m in $meshes; do
  in=$shared/meshes/$m
  base=$out/${m%.*}
  rm -f "$base.obj" "$base.json" "$base.eval.json" "$base.err"
  if [ ! -f "$in" ]; then
    printf '%s\tFAIL\t\t\t\t\t%s\n' "$m" "no such mesh in $shared/meshes" >>"$tsv"
    echo "bench: $m: no such mesh" >&2
    continue
  fi
  echo "bench: $m ..." >&2
  t0=$(date +%s.%N)
  # The timer wraps the guard: Linux passes a reaped child's peak RSS up to its parent, so %M is authalic's.
  ${timer[@]+"${timer[@]}"} ${guard[@]+"${guard[@]}"} "$bin" sphere "$in" "$base.obj" --report "$base.json" \
    --quiet ${extra[@]+"${extra[@]}"} 2>"$base.err" >/dev/null
  rc=$?
  t1=$(date +%s.%N)
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
  # /usr/bin/time appends a "Command exited with non-zero status" line before the number on failure.
  rss=$( [ -f "$out/.rss" ] && tail -n 1 "$out/.rss" | tr -dc '0-9' )
  rm -f "$out/.rss"
  if [ $rc -ne 0 ]; then
    msg=$(grep . "$base.err" 2>/dev/null | tail -n 1 | tr '\t|' '  ' | cut -c1-200)
    [ $rc -eq 124 ] && [ "$limit" -gt 0 ] && msg="timed out after $limit s"
    printf '%s\tFAIL\t%s\t%s\t%s\t\t%s\n' "$m" "$wall" "$rss" "$base.json" "exit $rc: ${msg:-no message}" >>"$tsv"
    echo "bench: $m: FAIL (exit $rc) ${msg}" >&2
    continue
  fi
  if ! /usr/bin/python3 "$shared/tools/param-eval" "$in" "$base.obj" --json >"$base.eval.json" 2>"$base.err"; then
    msg=$(grep . "$base.err" | tail -n 1 | tr '\t|' '  ' | cut -c1-200)
    printf '%s\tEVAL\t%s\t%s\t%s\t\t%s\n' "$m" "$wall" "$rss" "$base.json" "param-eval failed: $msg" >>"$tsv"
    echo "bench: $m: param-eval failed: $msg" >&2
    continue
  fi
  # Further runs: keep the report (and wall time) of the fastest init + flow.
  for ((r = 2; r <= runs; r++)); do
    t0=$(date +%s.%N)
    "$bin" sphere "$in" "$base.try.obj" --report "$base.try.json" --quiet ${extra[@]+"${extra[@]}"} 2>/dev/null >/dev/null || break
    t1=$(date +%s.%N)
    if /usr/bin/python3 -c 'import json, sys
t = [json.load(open(p))["time"] for p in sys.argv[1:3]]
sys.exit(0 if t[1]["init"] + t[1]["flow"] < t[0]["init"] + t[0]["flow"] else 1)' "$base.json" "$base.try.json"; then
      mv "$base.try.json" "$base.json"
      wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
    fi
  done
  rm -f "$base.try.obj" "$base.try.json"
  printf '%s\tok\t%s\t%s\t%s\t%s\t\n' "$m" "$wall" "$rss" "$base.json" "$base.eval.json" >>"$tsv"
done

# The table (Markdown, so bench.md renders and the terminal copy stays readable).
/usr/bin/python3 - "$tsv" "$out/bench.md" "$bin" "$args" "$runs" <<'EOF'
import json, sys

results, md, binary, args, runs = sys.argv[1:6]


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def get(d, *paths):
    """The first present value among dotted key paths, else None."""
    for p in paths:
        v = d
        for k in p.split('.'):
            v = v.get(k) if isinstance(v, dict) else None
        if v is not None:
            return v
    return None


def num(v, f):
    return f % v if isinstance(v, (int, float)) and not isinstance(v, bool) else '-'


head = ['mesh', 'F', 'steps', 't_init s', 't_flow s', 't_total s', 'wall s', 'peak MB',
        'folds', 'r_mean_abs_dev', 'r_cv', 'vertex_logr_mean_abs', 'lambda_mean', 'angle °', 'note']
rows, failed = [], 0
with open(results) as f:
    for line in f:
        name, status, wall, rss, rpath, epath, msg = (line.rstrip('\n').split('\t') + [''] * 7)[:7]
        rep, ev = load(rpath) if rpath else {}, load(epath) if epath else {}
        t = get(rep, 'time', 'timings') or {}
        wall_v = float(wall) if wall else None
        mb = int(rss) / 1024 if rss else None
        note = msg
        if status == 'ok':
            conv = get(rep, 'converged')
            note = 'not converged' if conv is not None and not conv else ''
            if get(rep, 'convergence.lantern_retry.kept'):
                note = (note + '; ' if note else '') + 'lantern retry kept'
        else:
            failed += 1
            note = ('FAIL: ' if status == 'FAIL' else '') + msg
        rows.append([name, num(get(ev, 'F') or get(rep, 'nf', 'F', 'mesh.F', 'input.F'), '%d'),
                     num(get(rep, 'steps', 'flow.steps', 'advect.steps'), '%d'),
                     num(get(t, 'init'), '%.3f'), num(get(t, 'flow'), '%.3f'), num(get(t, 'total'), '%.3f'),
                     num(wall_v, '%.2f'), num(mb, '%.1f'), num(get(ev, 'folds'), '%d'),
                     num(get(ev, 'r_mean_abs_dev'), '%.3g'), num(get(ev, 'r_cv'), '%.3g'),
                     num(get(ev, 'vertex_logr_mean_abs'), '%.3g'), num(get(ev, 'lambda_mean'), '%.3g'),
                     num(get(rep, 'metrics.angle_diff_mean_deg'), '%.2f'), note])

width = [max(len(str(r[i])) for r in rows + [head]) for i in range(len(head))]
def line(cells):
    return '| ' + ' | '.join(str(c).ljust(w) if i in (0, len(head) - 1) else str(c).rjust(w)
                             for i, (c, w) in enumerate(zip(cells, width))) + ' |'
sep = '|' + '|'.join(('-' * (w + 2)) if i in (0, len(head) - 1) else ('-' * (w + 1) + ':')
                     for i, w in enumerate(width)) + '|'
text = '\n'.join([f"authalic sphere benchmark ({binary}{' ' + args if args else ''}); "
                  + (f"times: the fastest of {runs} runs; " if runs != '1' else '')
                  + "quality columns from ../shared/tools/param-eval (angle: the report's mean |angle difference|)",
                  '', line(head), sep]
                 + [line(r) for r in rows]) + '\n'
sys.stdout.write(text)
with open(md, 'w') as f:
    f.write(text)
print(f"\n{len(rows) - failed} of {len(rows)} meshes mapped; table in {md}")
sys.exit(1 if failed else 0)
EOF
rc=$?
[ -n "$results" ] || exit $rc

# The results page: the machine and its load first, since the times depend on both.
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)
ncpu=$(grep -c '^processor' /proc/cpuinfo)
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
page=$out/RESULTS.md.tmp
{
  echo "# Benchmark results"
  echo
  echo "Regenerated by \`make bench\` (\`bash bench/bench.sh --results bench/RESULTS.md\`); the scripts are described in"
  echo "[README.md](README.md). Times are wall-clock seconds of one run on a machine that may be shared: read them"
  echo "against the load average below (on a few cores, other work slows a run several-fold)."
  echo
  echo "| | |"
  echo "|---|---|"
  echo "| date (UTC) | $(date -u '+%Y-%m-%d %H:%M') |"
  echo "| commit | $commit |"
  echo "| CPU | ${cpu:-unknown}, $ncpu logical cores (/proc/cpuinfo) |"
  echo "| load average at start (1, 5, 15 min) | ${load_start:-unknown} |"
  echo "| sphere meshes | $( [ "$meshes" = "$all_meshes" ] && echo "all 14 closed genus-0 meshes of ../shared/meshes" || echo "subset: $meshes") |"
  echo "| extra arguments | ${args:-none} |"
  echo
  echo "## Sphere: \`authalic sphere\` on the closed genus-0 meshes"
  echo
  tail -n +3 "$out/bench.md"
  if [ $extras = 1 ]; then
    echo
    echo "## Planar domains: \`bench/planar.sh\`"
    echo
    echo "One line per map: steps, steps undone, init + flow seconds, mean angle difference (degrees), then"
    echo "param-eval \`--coords v\`: folds, per-face mean |r-1| (r_mad), vertex mean |log r|, r_cv, boundary deviations."
    echo
    echo '```'
    bash "$root/bench/planar.sh" --bin "$bin"
    echo '```'
    echo
    echo "## Thin limbs: \`bench/thin_limbs.sh\`"
    echo
    echo "Per-face mean |r-1| / vertex mean |log r| by param-eval; the refined maps against their refined surface."
    echo
    echo "| mesh | default map | --refine-mesh (2x faces) | --refine-budget auto |"
    echo "|---|---|---|---|"
    (cd "$root" && sh bench/thin_limbs.sh "$bin" "$out/thin_limbs")
  fi
  echo
  echo "Load average at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)."
} >"$page" && mv "$page" "$results" || { echo "bench: cannot write $results" >&2; exit 2; }
echo "bench: results page written to $results" >&2
exit $rc

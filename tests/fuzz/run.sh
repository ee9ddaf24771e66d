#!/usr/bin/env bash
# run.sh - run every libFuzzer target of tests/fuzz for a bounded time; any finding fails.
# usage: tests/fuzz/run.sh BUILD_DIR [SECONDS_PER_TARGET (default 60)] [TARGET...]
# SECONDS_PER_TARGET 0 only replays the seeds and the saved corpus once (a quick regression run).
# Each target starts from its seeds (tests/fuzz/corpus/<kind>/, which also holds the regression
# files of earlier findings, plus tests/cli/bad/ for the readers) and from what earlier runs found
# (BUILD_DIR/corpus/<target>/). A crash, leak, undefined behaviour, timeout (one input taking more
# than 5 s in a reader, 20 s in the CLI) or memory blow-up (> 2 GB) stops the target; the input is
# saved as BUILD_DIR/findings/<target>/crash-* (or leak-*, timeout-*, oom-*) and the run exits 1.
# A reader input slower than 2 s (slow-unit-*) is saved there too and also counts as a finding: a
# reader that needs seconds for a 16 KB file can be made to hang with a larger one.
# Reproduce a finding: BUILD_DIR/<target> FILE; shrink it: BUILD_DIR/<target> -minimize_crash=1 FILE.
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
if [ $# -lt 1 ]; then
  echo "usage: tests/fuzz/run.sh BUILD_DIR [SECONDS_PER_TARGET] [TARGET...]" >&2
  exit 2
fi
build=$(cd "$1" && pwd) || exit 2
secs=${2:-60}
case $secs in ''|*[!0-9]*) echo "run.sh: SECONDS_PER_TARGET must be a whole number" >&2; exit 2 ;; esac
shift $(( $# >= 2 ? 2 : 1 ))
targets=${*:-fuzz_read_obj fuzz_read_off fuzz_read_ply fuzz_read_stl fuzz_read_freesurfer fuzz_read_gifti fuzz_cli}

# gifticlib's own leaks on malformed files are not findings (tests/fuzz/lsan.supp says which).
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
failed=""
for t in $targets; do
  exe=$build/$t
  if [ ! -x "$exe" ]; then
    echo "run.sh: $exe is missing (make fuzz builds it)" >&2
    exit 2
  fi
  case $t in
    fuzz_read_*) kind=${t#fuzz_read_}; seeds=("$root/tests/fuzz/corpus/$kind" "$root/tests/cli/bad"); maxlen=16384; limit=5; slow=2 ;;
    fuzz_cli) kind=cli; seeds=("$root/tests/fuzz/corpus/cli"); maxlen=512; limit=20; slow=20 ;;
    *) echo "run.sh: unknown target $t" >&2; exit 2 ;;
  esac
  mkdir -p "$build/corpus/$t" "$build/findings/$t" "$build/logs" || exit 2
  rm -f "$build/findings/$t"/*
  log=$build/logs/$t.log
  echo "run.sh: $t for ${secs}s ..." >&2
  if [ "$secs" -eq 0 ]; then budget=-runs=0; else budget=-max_total_time=$secs; fi
  # Paths are absolute: fuzz_cli works inside its own scratch folder.
  "$exe" "$budget" -max_len="$maxlen" -timeout="$limit" -report_slow_units="$slow" -rss_limit_mb=2048 -print_final_stats=1 \
    -dict="$root/tests/fuzz/$kind.dict" -artifact_prefix="$build/findings/$t/" \
    "$build/corpus/$t" "${seeds[@]}" >"$log" 2>&1
  rc=$?
  if [ $rc -eq 0 ] && [ -n "$(ls -A "$build/findings/$t")" ]; then rc=1; fi
  stats=$(grep -E '^stat::number_of_executed_units|^stat::new_units_added' "$log" | tr '\n' ' ')
  if [ $rc -ne 0 ]; then
    failed="$failed $t"
    echo "run.sh: $t FAILED (exit $rc); log $log; findings:" >&2
    ls "$build/findings/$t" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -n 10 >&2
  else
    echo "run.sh: $t ok ($stats)" >&2
  fi
done
if [ -n "$failed" ]; then
  echo "run.sh: findings in:$failed" >&2
  exit 1
fi
echo "run.sh: all fuzz targets ran ${secs}s without findings" >&2
exit 0

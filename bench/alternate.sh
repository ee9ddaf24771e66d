#!/bin/bash
# alternate.sh - the whole command's wall time of two builds of `authalic`, run alternately (old, new,
# old, new, ...) so that both see the same machine state, on bunny, lion_statue and brain_disk (or
# the meshes given). Prints per mesh the median of each build and the ratio new/old.
# usage: bench/alternate.sh --old BIN --new BIN [--runs N] [MESH.obj:COMMAND ...]   (exit 0; 2 bad usage)
set -u
here=$(cd "$(dirname "$0")" && pwd)
old="" new="" runs=5
while [ $# -gt 0 ]; do
  case $1 in
  --old) old=$2; shift 2 ;;
  --new) new=$2; shift 2 ;;
  --runs) runs=$2; shift 2 ;;
  --*) echo "usage: bench/alternate.sh --old BIN --new BIN [--runs N] [MESH:COMMAND ...]" >&2; exit 2 ;;
  *) break ;;
  esac
done
[ -x "$old" ] && [ -x "$new" ] || { echo "usage: bench/alternate.sh --old BIN --new BIN [--runs N] [MESH:COMMAND ...]" >&2; exit 2; }
S=$here/../../shared/meshes
[ $# -gt 0 ] || set -- "$S/bunny.obj:sphere" "$S/lion_statue.obj:sphere" "$S/brain_disk.obj:disk"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
for spec in "$@"; do
  mesh=${spec%:*} cmd=${spec##*:}
  [ -f "$mesh" ] || { echo "$(basename "$mesh"): missing"; continue; }
  : >"$T/old" && : >"$T/new"
  for ((i = 0; i < runs; i++)); do
    for which in old new; do
      bin=${!which}
      t0=$(date +%s.%N)
      "$bin" "$cmd" "$mesh" "$T/out.obj" --quiet || echo "$which failed on $mesh" >&2
      t1=$(date +%s.%N)
      awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f\n", b - a}' >>"$T/$which"
    done
  done
  mo=$(median <"$T/old") mn=$(median <"$T/new")
  printf '%-16s %-7s old %.3f s  new %.3f s  new/old %.3f  (%d runs each, medians; old: %s)\n' "$(basename "$mesh")" \
    "$cmd" "$mo" "$mn" "$(awk -v a="$mn" -v b="$mo" 'BEGIN {print a / b}')" "$runs" "$(tr '\n' ' ' <"$T/old")"
done
exit 0

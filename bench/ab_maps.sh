#!/bin/sh
# ab_maps.sh BIN_A BIN_B MESH... - `authalic sphere` by two builds on each mesh, once each: whether the
# two maps are the same byte for byte, and each run's minor page faults, CPU (user + system) and wall
# seconds by /usr/bin/time. Page faults are a count, not a time, so they compare two builds even on a
# loaded machine where seconds move by 50% and more (bench/ab_time.sh takes the least of several runs).
# Run from the source root: sh bench/ab_maps.sh OLD/authalic build/authalic ../shared/meshes/bunny.obj
A=$1; B=$2; shift 2
T=$(mktemp -d)
echo "| mesh | same map | A faults | B faults | A CPU s | B CPU s | A wall s | B wall s |"
echo "|---|---|---:|---:|---:|---:|---:|---:|"
for m in "$@"; do
  [ -f "$m" ] || { echo "ab_maps.sh: $m is missing, skipped" >&2; continue; }
  n=$(basename "$m"); n=${n%.*}
  /usr/bin/time -f "%R %U %S %e" -o $T/a "$A" sphere "$m" $T/a.obj --quiet 2>/dev/null
  /usr/bin/time -f "%R %U %S %e" -o $T/b "$B" sphere "$m" $T/b.obj --quiet 2>/dev/null
  if cmp -s $T/a.obj $T/b.obj; then same=yes; else same=no; fi
  set -- $(tail -1 $T/a) $(tail -1 $T/b)
  echo "| $n | $same | $1 | $5 | $(echo "$2 + $3" | bc) | $(echo "$6 + $7" | bc) | $4 | $8 |"
done
rm -rf $T

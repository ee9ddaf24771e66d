#!/bin/sh
# ab_time.sh BIN_A BIN_B RUNS MESH... - `authalic sphere` by two builds on each mesh, the runs interleaved
# (A, B, A, B, ...) so that both see the same load; prints per mesh and build the least wall and the least
# CPU (user + system) seconds over RUNS runs by /usr/bin/time. On a shared machine one run's seconds move
# by 50% and more; the least of interleaved runs compares two builds fairly.
# Run from the source root: sh bench/ab_time.sh OLD/authalic build/authalic 3 ../shared/meshes/cow.off
A=$1; B=$2; N=$3; shift 3
T=$(mktemp -d)
echo "| mesh | A wall s | B wall s | A CPU s | B CPU s |"
echo "|---|---:|---:|---:|---:|"
for m in "$@"; do
  n=$(basename $m); n=${n%.*}
  : > $T/a; : > $T/b
  i=0
  while [ $i -lt $N ]; do
    /usr/bin/time -f "%e %U %S" -a -o $T/a $A sphere $m $T/o.obj --quiet 2>/dev/null
    /usr/bin/time -f "%e %U %S" -a -o $T/b $B sphere $m $T/o.obj --quiet 2>/dev/null
    i=$((i + 1))
  done
  /usr/bin/python3 - "$n" $T/a $T/b <<'PY'
import sys
n, a, b = sys.argv[1:4]
def best(p):
    rows = [list(map(float, l.split()[-3:])) for l in open(p) if len(l.split()) >= 3]
    return min(r[0] for r in rows), min(r[1] + r[2] for r in rows)
(aw, ac), (bw, bc) = best(a), best(b)
print("| %s | %.2f | %.2f | %.2f | %.2f |" % (n, aw, bw, ac, bc))
PY
done
rm -rf $T

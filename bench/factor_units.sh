#!/bin/sh
# factor_units.sh BUILD [MESH [RUNS]] - a whole `authalic sphere` command in units of one single-thread
# factorization of the mesh's cotan Laplacian (bench/cotan_factor.c), measured in the same run, so that
# the figure holds on a shared or slower machine (issue 39: bunny <= 14). Each run times the command
# (wall seconds by /usr/bin/time) and a factorization just before it; prints each run and the median
# ratio, and the report's count of sparse factorizations (its "factorizations").
# Run from the source root: sh bench/factor_units.sh build ../shared/meshes/bunny.obj 3
B=$1; M=${2:-../shared/meshes/bunny.obj}; N=${3:-3}
[ -f "$M" ] || { echo "factor_units.sh: $M is missing"; exit 0; }
T=$(mktemp -d)
i=0
while [ $i -lt $N ]; do
  f=$($B/au_cotan_factor "$M" 9) || exit 1
  /usr/bin/time -f "%e" -o $T/time $B/authalic sphere "$M" $T/out.obj --report $T/r.json --quiet 2>/dev/null
  c=$(tail -1 $T/time)
  n=$(/usr/bin/python3 -c "import json; print(json.load(open('$T/r.json')).get('factorizations', '?'))")
  echo "run $i: command $c s, one factorization $f s, ratio $(/usr/bin/python3 -c "print('%.1f' % ($c / $f))"), factorizations $n"
  echo "$c $f" >> $T/runs
  i=$((i + 1))
done
/usr/bin/python3 -c "
import statistics
r = [float(a) / float(b) for a, b in (l.split() for l in open('$T/runs'))]
print('median ratio %.1f over %d runs' % (statistics.median(r), len(r)))"
rm -rf $T

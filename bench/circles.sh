#!/bin/sh
# circles.sh - `authalic circles` against the evaluator and against the planar maps it generalizes:
#   1. the generated circle-domain cases (data/holes*.obj, data/face_holes.obj) and ../shared's
#      beetle.off (11 loops): param-eval --domain plane (folds, per-face mean |r-1|, vertex mean |log r|),
#      every loop on its reported circle, circles disjoint and inside the unit circle, time per face;
#   2. every ../shared disk and annulus mesh: circles beside disk / annulus (param-eval per-face);
#   3. square --aspect 2:1 on brain_disk.
# sh bench/circles.sh BUILD_DIR [SHARED_DIR]   (one run at a time: the machine is shared)
B=${1:?usage: circles.sh BUILD_DIR [SHARED_DIR]}
S=${2:-$(dirname "$0")/../../shared}
SRC=$(cd "$(dirname "$0")/.." && pwd)
P=$B/authalic
PE=$S/tools/param-eval
PY=/usr/bin/python3
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT

# pe IN OUT: "folds per-face vertex" by param-eval
pe() { $PY "$PE" "$1" "$2" --domain plane --json | $PY -c "import json,sys;d=json.load(sys.stdin);print(d['folds'],'%.4f'%d['r_mean_abs_dev'],'%.4f'%d['vertex_logr_mean_abs'])"; }

# circles_check IN OUT REPORT: the loops' worst distance from their circles, the smallest gap between
# circles and to the unit circle, steps and seconds per 1000 faces.
circles_check() {
  $PY - "$2" "$3" <<'EOF'
import json, math, sys
V, F = [], []
for line in open(sys.argv[1]):
    t = line.split()
    if t and t[0] == 'v': V.append((float(t[1]), float(t[2])))
    elif t and t[0] == 'f': F.append([int(x.split('/')[0]) - 1 for x in t[1:4]])
r = json.load(open(sys.argv[2]))
d = {(a, b) for a, b, c in F} | {(b, c) for a, b, c in F} | {(c, a) for a, b, c in F}
nxt = {a: b for a, b in d if (b, a) not in d}
loop_of = {}
for c in r['circles']:
    v = c['vertex']
    while v not in loop_of:
        loop_of[v] = c['vertex']
        v = nxt[v]
C = {c['vertex']: c for c in r['circles']}
dev = max(abs(math.hypot(V[v][0] - C[l]['center'][0], V[v][1] - C[l]['center'][1]) - C[l]['radius']) for v, l in loop_of.items())
holes = [c for c in r['circles'] if not c['outer']]
gap = min([1 - math.hypot(*c['center']) - c['radius'] for c in holes] +
          [math.hypot(a['center'][0] - b['center'][0], a['center'][1] - b['center'][1]) - a['radius'] - b['radius']
           for i, a in enumerate(holes) for b in holes[i + 1:]])
print('on-circle %.1e  min-gap %.4f  steps %d  s/kface %.4f' % (dev, gap, r['steps'], r['time']['total'] / len(F) * 1000))
EOF
}

echo "## circle domains"
for IN in "$SRC"/data/holes3.obj "$SRC"/data/holes10.obj "$SRC"/data/holes40.obj "$SRC"/data/face_holes.obj "$S"/meshes/beetle.off; do
  [ -f "$IN" ] || continue
  $P circles "$IN" "$T/c.obj" --report "$T/c.json" --quiet || continue
  echo "$(basename "$IN"): param-eval $(pe "$IN" "$T/c.obj")  $(circles_check "$IN" "$T/c.obj" "$T/c.json")"
done
if [ -f "$S/meshes/brain_disk.obj" ]; then
  $P disk "$S/meshes/brain_disk.obj" "$T/d.obj" --report "$T/d.json" --quiet &&
    $PY -c "import json;r=json.load(open('$T/d.json'));print('brain_disk (disk): s/kface %.4f' % (r['time']['total'] / r['F'] * 1000))"
fi

echo "## circles against disk and annulus (param-eval per-face mean |r-1|)"
for m in hand_lowres.obj demosthenes.obj camelhead.off cowhead.obj face.obj mountain.obj brain_disk.obj amoeba_annulus.obj sophie.obj; do
  IN=$S/meshes/$m
  [ -f "$IN" ] || continue
  case $m in amoeba_annulus.obj | sophie.obj) cmd=annulus ;; *) cmd=disk ;; esac
  $P $cmd "$IN" "$T/a.obj" --quiet && $P circles "$IN" "$T/b.obj" --quiet || { echo "$m: failed"; continue; }
  echo "$m: $cmd $(pe "$IN" "$T/a.obj")  circles $(pe "$IN" "$T/b.obj")"
done

echo "## square --aspect 2:1"
if [ -f "$S/meshes/brain_disk.obj" ]; then
  $P square "$S/meshes/brain_disk.obj" "$T/s.obj" --aspect 2:1 --quiet && echo "brain_disk: $(pe "$S/meshes/brain_disk.obj" "$T/s.obj")"
fi

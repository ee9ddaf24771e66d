#!/bin/bash
# planar.sh - the planar maps of ../shared/meshes, one line each: the seven disk meshes onto the disk,
# the two annuli onto the annulus, face and mountain onto the square (sliding and fixed sides).
# Columns: steps, steps undone, init + flow seconds, the report's mean |angle difference| in degrees,
# then param-eval (--coords v): folds, per-face mean |r - 1|, vertex mean |log r|, r_cv and its
# boundary deviations.
# usage: bench/planar.sh [--bin PATH] [--args "..."]   (exit 0; 2 on bad usage)
set -u
here=$(cd "$(dirname "$0")" && pwd)
bin=$here/../build/authalic args=""
while [ $# -gt 0 ]; do
  case $1 in
  --bin) bin=$2; shift 2 ;;
  --args) args=$2; shift 2 ;;
  *) echo "usage: bench/planar.sh [--bin PATH] [--args \"...\"]" >&2; exit 2 ;;
  esac
done
S=$here/../../shared/meshes
[ -d "$S" ] || { echo "planar.sh: $S is missing; nothing to map"; exit 0; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
run() {
  cmd=$1 m=$2; shift 2
  # shellcheck disable=SC2086
  "$bin" "$cmd" "$S/$m" "$T/out.obj" --quiet --report "$T/r.json" "$@" $args 2>/dev/null
  rc=$?
  if [ $rc -ne 0 ]; then echo "$cmd $m $* rc=$rc"; return; fi
  a=$(/usr/bin/python3 -c "import json;d=json.load(open('$T/r.json'));t=d['time'];c=d['convergence'];print('steps %d undone %d %.2f s angle %.2f'%(d['steps'],c['undone'],t['init']+t['flow'],d['metrics']['angle_diff_mean_deg']))")
  b=$("$S/../tools/param-eval" "$S/$m" "$T/out.obj" --coords v --json | /usr/bin/python3 -c "
import json,sys;d=json.load(sys.stdin)
dev=' '.join('%s=%.2g'%(k,v) for k,v in d.items() if k.endswith('max_dev') and isinstance(v,float))
print('folds %d r_mad %.4f vertex %.5f r_cv %.4f %s'%(d['folds'],d['r_mean_abs_dev'],d['vertex_logr_mean_abs'],d['r_cv'],dev))")
  echo "$cmd $m $* $args: $a $b"
}
for m in hand_lowres.obj demosthenes.obj camelhead.off cowhead.obj face.obj mountain.obj brain_disk.obj; do run disk $m; done
for m in amoeba_annulus.obj sophie.obj; do run annulus $m; done
for m in face.obj mountain.obj; do run square $m; run square $m --boundary fixed; done
exit 0

#!/bin/bash
# guard.sh - the maps of every mesh in ../shared/meshes (sphere for the closed genus-0 ones; disk,
# annulus and square for the open ones), written with a given program into a directory, so that two
# builds can be compared byte for byte (`cmp`) after a refactoring.
# usage: bench/guard.sh --bin PATH --out DIR [--compare DIR]   (exit 0 ok; 1 on a difference; 2 bad usage)
set -u
here=$(cd "$(dirname "$0")" && pwd)
bin="" out="" cmpdir=""
while [ $# -gt 0 ]; do
  case $1 in
  --bin) bin=$2; shift 2 ;;
  --out) out=$2; shift 2 ;;
  --compare) cmpdir=$2; shift 2 ;;
  *) echo "usage: bench/guard.sh --bin PATH --out DIR [--compare DIR]" >&2; exit 2 ;;
  esac
done
[ -n "$bin" ] && [ -n "$out" ] || { echo "usage: bench/guard.sh --bin PATH --out DIR [--compare DIR]" >&2; exit 2; }
S=$here/../../shared/meshes
[ -d "$S" ] || { echo "guard.sh: $S is missing; nothing to map"; exit 0; }
mkdir -p "$out"
rc=0
map() {
  cmd=$1 m=$2; shift 2
  name=${cmd}_${m%.*}$(echo "$*" | tr -d ' -').obj
  "$bin" "$cmd" "$S/$m" "$out/$name" --quiet "$@" 2>"$out/$name.err"
  echo "$cmd $m $*: rc=$?" >>"$out/status.txt"
  if [ -n "$cmpdir" ]; then
    if cmp -s "$out/$name" "$cmpdir/$name"; then echo "same  $name"; else echo "DIFF  $name"; rc=1; fi
  fi
}
: >"$out/status.txt"
for m in spot_lowres.obj cow.off spot.obj hippocampus.obj cheburashka.off blub.obj hand_closed.obj maxplanck.obj \
  bunny.obj nefertiti.obj ferret_brain_sim.off armadillo.obj brain.obj lion_statue.obj; do map sphere $m; done
for m in hand_lowres.obj demosthenes.obj camelhead.off cowhead.obj face.obj mountain.obj brain_disk.obj; do map disk $m; done
for m in amoeba_annulus.obj sophie.obj; do map annulus $m; done
for m in face.obj mountain.obj; do map square $m; done
map sphere spot.obj --angles 5
map disk face.obj --refine-faces
exit $rc

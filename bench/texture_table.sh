#!/bin/sh
# texture_table.sh - the table of issue 18: for every closed genus-0 mesh of ../shared/meshes and
# every projection, the texture OBJ measured against itself (param-eval --coords vt --domain plane:
# each face's vt area against its surface area): folded vt faces, per-face mean |r-1| next to the
# sphere map's own, the bound 1.25 x map + 0.002, and the texture's total surface area against the
# input's. Also the floor: the map's per-face mean |r-1| with spherical triangle areas (`authalic
# texture` prints it as sph|r-1|), which a straight texture triangle's area tends to as faces shrink,
# so no projection can be expected below it; "floor <= bound" says whether the bound is reachable at
# all with this map, "vt / floor" how far the texture is from it.
#
#   sh bench/texture_table.sh [BUILD_DIR] [OUT_DIR] [MESH ...]
#
# BUILD_DIR defaults to build, OUT_DIR to /tmp/au_texture_table. Sphere maps are kept in
# OUT_DIR/maps and reused when present (the texture step is what is measured). Meshes are names in
# ../shared/meshes without extension (default: all 14 genus-0 ones). Projections: $PROJ (default
# "cea laea oct"); extra texture options: $TEXOPTS (e.g. "--axis auto"); MAPS=spherical makes the
# missing maps with BUILD_DIR/au_sphere_areas_map (spherical areas only, the map `authalic texture`
# computes without --map) instead of `authalic sphere`. Prints one Markdown row per mesh and
# projection.
set -eu
HERE=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${1:-build}
case $BUILD in /*) ;; *) BUILD=$HERE/$BUILD ;; esac
OUT=${2:-/tmp/au_texture_table}
[ $# -ge 2 ] && shift 2 || shift $#
SHARED=$HERE/../shared
EVAL=$SHARED/tools/param-eval
MESHES=${*:-"spot_lowres cow spot hippocampus cheburashka blub hand_closed maxplanck bunny nefertiti ferret_brain_sim armadillo brain lion_statue"}
PROJ=${PROJ:-"cea laea oct"}
TEXOPTS=${TEXOPTS:-}
mkdir -p "$OUT/maps"
[ -x "$EVAL" ] || { echo "texture_table.sh: $EVAL is missing" >&2; exit 2; }

# A key of param-eval's JSON.
key() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); v=d.get(sys.argv[2]); print(v if v is not None else "nan")' "$1" "$2"; }

echo "| mesh | projection | sphere map per-face | bound | floor (spherical) | floor <= bound | folded vt | vt per-face | vt / floor | bound met | split fold/area | area rel. diff | texture s |"
echo "|---|---|---:|---:|---:|---|---:|---:|---:|---|---|---:|---:|"
for m in $MESHES; do
  IN=$(ls "$SHARED/meshes/$m".* 2>/dev/null | head -1)
  [ -n "$IN" ] || { echo "texture_table.sh: no mesh $m" >&2; continue; }
  MAP=$OUT/maps/$m.obj
  if [ ! -f "$MAP" ]; then
    if [ "${MAPS:-}" = spherical ]; then "$BUILD/au_sphere_areas_map" "$IN" "$MAP" >/dev/null
    else "$BUILD/authalic" sphere "$IN" "$MAP" --quiet; fi
  fi
  "$EVAL" "$IN" "$MAP" --json >"$OUT/$m.map.json"
  rmap=$(key "$OUT/$m.map.json" r_mean_abs_dev)
  area_in=$(key "$OUT/$m.map.json" surface_area)
  for p in $PROJ; do
    TEX=$OUT/$m.$p.obj
    t0=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$BUILD/authalic" texture "$IN" --map "$MAP" "$TEX" --projection "$p" $TEXOPTS 2>"$OUT/$m.$p.log" || {
      echo "| $m | $p | failed: $(tail -1 "$OUT/$m.$p.log") |"; continue; }
    t1=$(date +%s.%N)
    "$EVAL" "$TEX" "$TEX" --coords vt --domain plane --json >"$OUT/$m.$p.json"
    splits=$(sed -n 's/.*split for folding=\([0-9]*\) for area=\([0-9]*\).*/\1\/\2/p' "$OUT/$m.$p.log")
    floor=$(sed -n 's/.* sph|r-1|=\([^ ]*\) .*/\1/p' "$OUT/$m.$p.log")
    python3 - "$OUT/$m.$p.json" "$rmap" "$area_in" "$m" "$p" "${splits:-n/a}" "$t0" "$t1" "${floor:-nan}" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
rmap, ain, floor = float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[9])
bound = 1.25 * rmap + 0.002
r, folds = d['r_mean_abs_dev'], d['folds']
ok = 'yes' if folds == 0 and r <= bound else 'NO'
reach = 'yes' if floor <= bound else 'NO'
print(f"| {sys.argv[4]} | {sys.argv[5]} | {rmap:.4f} | {bound:.4f} | {floor:.4f} | {reach} | {folds} | {r:.4f} | "
      f"{r / floor:.2f} | {ok} | {sys.argv[6]} | {abs(d['surface_area'] - ain) / ain:.1e} | "
      f"{float(sys.argv[8]) - float(sys.argv[7]):.1f} |")
EOF
  done
done

# lib.sh - helpers of the workflow tests (bash, sourced). Every script is called as
#   bash SCRIPT.sh PROG SOURCE_DIR SHARED_DIR WORK_DIR
# with PROG the built `authalic`, WORK_DIR a folder in the build tree the test may fill (kept after
# the test for inspection; local.sh and rerun.sh share WORK_DIR/local). Exit 0 pass, 1 fail, 77 skip.

PROG=$1
SRC=$2
SHARED=$3
WORK=$4
PY=/usr/bin/python3
SNAKEFILE=$SRC/workflow/Snakefile
CHECK=$SRC/tests/workflow/check_cohort.py
export WF_SCRIPTS=$SRC/workflow/scripts

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

skip() {
  echo "SKIP: $*" >&2
  exit 77
}

command -v snakemake >/dev/null 2>&1 || skip "no snakemake (scripts/setup-debian.sh installs it)"
$PY -c 'import numpy, matplotlib' 2>/dev/null || skip "no numpy or matplotlib for $PY (scripts/setup-debian.sh)"
[ -x "$PROG" ] || fail "no program at $PROG"

# make_cohort DIR: copies seven meshes (../shared/meshes when present, data/ otherwise) and one file
# of the bad-input corpus into DIR/in and writes DIR/manifest.tsv (absolute paths, and one row with
# a relative path, which the manifest's folder anchors). Every command appears; one row has options;
# the first (sphere) row has a density file and an attribute file, the fourth (disk) and the seventh
# (torus) an attribute, the sixth one of the wrong length.
make_cohort() {
  local d=$1 rows
  mkdir -p "$d/in" || fail "cannot make $d/in"
  if [ -d "$SHARED/meshes" ]; then
    rows="spot_lowres:spot_lowres.obj:sphere: cow:cow.off:sphere:--steps_30 hippocampus:hippocampus.obj:sphere:
          hand_disk:hand_lowres.obj:disk: hand_square:hand_lowres.obj:square: amoeba:amoeba_annulus.obj:annulus:
          bob:bob.obj:torus:"
    MESHDIR=$SHARED/meshes
  else
    rows="ellipsoid:ellipsoid.obj:sphere: spiky:spiky_ico.obj:sphere:--steps_30 dumbbell:dumbbell.obj:sphere:
          disk_bump:disk_bump.obj:disk: holed_square:holed_sphere.obj:square: annulus_bump:annulus_bump.obj:annulus:
          torus_r3:torus_r3.obj:torus:"
    MESHDIR=$SRC/data
  fi
  printf 'id\tinput\tcommand\toptions\tdensity\tattribute\n' > "$d/manifest.tsv"
  local r id file cmd opts n=0 path dens attr
  for r in $rows; do
    IFS=: read -r id file cmd opts <<< "$r"
    n=$((n + 1))
    cp -p "$MESHDIR/$file" "$d/in/" || fail "cannot copy $MESHDIR/$file"
    # The first row names its input relative to the manifest's folder; the others absolutely.
    if [ $n = 1 ]; then path=in/$file; else path=$d/in/$file; fi
    dens= attr=
    if [ $n = 1 ] || [ $n = 4 ] || [ $n = 7 ]; then
      # Per-vertex files: attribute = height z; density = 2 on the upper half, 1 below.
      $PY - "$d/in/$file" "$d/in/$id" <<'PYEOF' || fail "cannot write the per-vertex files of $file"
import os, sys
sys.path.insert(0, os.environ["WF_SCRIPTS"])
import meshio_np
import numpy as np
X, F = meshio_np.read_mesh(sys.argv[1])
np.savetxt(sys.argv[2] + ".attribute.txt", X[:, 2])
np.savetxt(sys.argv[2] + ".density.txt", 1.0 + (X[:, 2] > np.median(X[:, 2])))
PYEOF
      attr=$d/in/$id.attribute.txt
      [ $n = 1 ] && dens=$d/in/$id.density.txt
    fi
    # The sixth row gets the fourth row's attribute file, of the wrong length: its map succeeds,
    # its attribute picture fails, and that must show in cohort.tsv's notes, not stop the cohort.
    [ $n = 6 ] && attr=$(awk -F'\t' 'NR == 5 {print $6}' "$d/manifest.tsv")
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$id" "$path" "$cmd" "${opts//_/ }" "$dens" "$attr" >> "$d/manifest.tsv"
  done
  cp "$SRC/tests/cli/bad/index_range.obj" "$d/in/bad_index.obj" || fail "cannot copy the bad input"
  printf 'bad_index\t%s\tsphere\t\t\t\n' "$d/in/bad_index.obj" >> "$d/manifest.tsv"
}

# run_workflow OUT MANIFEST LOG [more snakemake arguments]: the issue's fixed invocation.
run_workflow() {
  local out=$1 manifest=$2 log=$3
  shift 3
  snakemake -s "$SNAKEFILE" --cores 2 --directory "$out" --config manifest="$manifest" authalic="$PROG" \
    "$@" >"$log" 2>&1
}

# mtimes OUT: "path mtime_ns" for every file of the cohort's outputs, sorted.
mtimes() {
  (cd "$1" && find surfaces cohort.tsv cohort.png cohort.md -type f -printf '%p %T@\n' | sort)
}

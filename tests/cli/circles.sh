# circles.sh - `authalic circles` end to end (and `square --aspect`): maps of the project's holed disks
# checked by circles_check.py (0 folds, per-face <= 0.02, vertex <= 0.005, loops on their circles to
# 1e-9, circles disjoint and inside the unit circle), the disk and annulus cases against `disk` and
# `annulus`, --outer, and the bad inputs (exit 2, a message that names the problem, nothing written).
# sh circles.sh PROG SOURCE_DIR SHARED_DIR CASE [MESH]
. "$(dirname "$0")/lib.sh"
CASE=$1
MESH=$2
OUT=$T/o/map.obj
REP=$T/o/report.json

need() {
  [ -f "$SRC/data/$1" ] || skip "$SRC/data/$1 is missing (run au_mkdata to generate data/)"
  IN=$(stage "$SRC/data/$1")
}

# per_face OUT IN: param-eval's per-face mean |r-1| of the planar map OUT of IN, computed here.
per_face() {
  $PY - "$1" "$2" <<'PYEOF'
import sys
import numpy as np
import objmesh
P, F = objmesh.load(sys.argv[1])
X, _ = objmesh.load(sys.argv[2])
a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
dom = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
surf = 0.5 * np.linalg.norm(np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]), axis=1)
print("%.6f" % np.abs((dom / dom.sum()) / (surf / surf.sum()) - 1).mean())
PYEOF
}

# refused PATTERN: the last run exited 2, said PATTERN on stderr and wrote nothing.
refused() {
  expect_status 2
  grep -q -- "$1" "$T/log/stderr" || fail "stderr does not say '$1'"
  [ -z "$(ls -A "$T/o")" ] || fail "files were left behind: $(ls -A "$T/o")"
}

# edit IN OUT PYTHON: OUT is IN with its faces F (numpy, 0-based) changed by the PYTHON statements.
edit() {
  $PY - "$1" "$2" "$3" <<'PYEOF' || fail "cannot make the test mesh"
import sys
import numpy as np
import objmesh
X, F = objmesh.load(sys.argv[1])
exec(sys.argv[3])
with open(sys.argv[2], "w") as fh:
    fh.writelines("v %.17g %.17g %.17g\n" % tuple(p) for p in X)
    fh.writelines("f %d %d %d\n" % tuple(f + 1) for f in F)
PYEOF
}

case $CASE in
  run)
    # A mesh of data/, or of ../shared/meshes (skipped where absent).
    if [ -f "$SRC/data/$MESH" ]; then IN=$(stage "$SRC/data/$MESH"); else stage_shared "$MESH"; fi
    run circles "$IN" "$OUT" --report "$REP" --quiet
    expect_status 0
    $PY "$(dirname "$0")/circles_check.py" "$IN" "$OUT" "$REP" || fail "the circle-domain map is wrong"
    ;;
  disk)
    # One loop: the disk map itself.
    need disk_bump.obj
    run circles "$IN" "$OUT" --quiet
    expect_status 0
    run disk "$IN" "$T/disk.obj" --quiet
    expect_status 0
    cmp -s "$OUT" "$T/disk.obj" || fail "circles on one loop differs from disk"
    ;;
  annulus)
    # Two loops: an annulus whose hole may move; per-face error within 10% of the annulus map's.
    need annulus_bump.obj
    run circles "$IN" "$OUT" --report "$REP" --quiet
    expect_status 0
    $PY "$(dirname "$0")/circles_check.py" "$IN" "$OUT" "$REP" || fail "the circle-domain map is wrong"
    run annulus "$IN" "$T/ann.obj" --quiet
    expect_status 0
    c=$(per_face "$OUT" "$IN") a=$(per_face "$T/ann.obj" "$IN")
    echo "per-face: circles $c, annulus $a"
    $PY -c "import sys; sys.exit(not $c <= 1.1 * $a)" || fail "circles per-face $c is over 1.1 x annulus's $a"
    ;;
  outer)
    # --outer V puts V's loop on the unit circle: here a hole's loop of holes3 (its vertex 0 is on the rim).
    need holes3.obj
    run circles "$IN" "$OUT" --report "$REP" --quiet
    expect_status 0
    V=$($PY -c "import json; print([c['vertex'] for c in json.load(open('$REP'))['circles'] if not c['outer']][0])")
    rm -f "$OUT" "$REP"
    run circles "$IN" "$OUT" --report "$REP" --outer "$V" --quiet
    expect_status 0
    $PY -c "import json, sys; c = json.load(open('$REP'))['circles']; sys.exit(not any(x['outer'] and x['vertex'] == $V for x in c))" ||
      fail "vertex $V's loop is not the outer circle"
    # A valid map (the disk's rim becomes a large hole: a hard case, so no bound on the areas here).
    $PY "$(dirname "$0")/circles_check.py" "$IN" "$OUT" "$REP" 1 1 || fail "the circle-domain map is wrong"
    ;;
  bad_outer)
    need holes3.obj
    run circles "$IN" "$OUT" --outer 0 --quiet # vertex 0: the disk's centre, on no loop
    refused "outer.*vertex 0 is on no boundary loop"
    ;;
  bad_closed)
    need ellipsoid.obj
    run circles "$IN" "$OUT" --report "$REP"
    refused "closed.*sphere"
    ;;
  bad_genus)
    # A torus with one face removed: genus 1 and a boundary loop.
    need torus_r2.obj
    edit "$IN" "$T/in/torus_hole.obj" "F = F[1:]"
    run circles "$T/in/torus_hole.obj" "$OUT" --report "$REP"
    refused "genus 1.*authalic atlas"
    ;;
  bad_shared_vertex)
    # disk_bump without two opposite faces of vertex 7's fan: two holes meet at vertex 7.
    need disk_bump.obj
    edit "$IN" "$T/in/pinched.obj" "
fan = [f for f in range(len(F)) if 7 in F[f]]
F = np.delete(F, [fan[0], fan[3]], axis=0)"
    run circles "$T/in/pinched.obj" "$OUT" --report "$REP"
    refused "vertex 7 is non-manifold"
    ;;
  bad_chord)
    # disk_bump without all but one face of vertex 7's fan: the face left joins two vertices of the
    # hole's loop by an edge across the surface.
    need disk_bump.obj
    edit "$IN" "$T/in/chord.obj" "
fan = [f for f in range(len(F)) if 7 in F[f]]
F = np.delete(F, fan[1:], axis=0)"
    run circles "$T/in/chord.obj" "$OUT" --report "$REP"
    refused "edge (.*) joins two vertices of one hole's boundary loop"
    ;;
  aspect)
    # square --aspect 2:1: the rectangle [0,1] x [0,1/2], fold-free, per-face <= 0.02.
    need disk_bump.obj
    run square "$IN" "$OUT" --aspect 2:1 --report "$REP" --quiet
    expect_status 0
    $PY - "$OUT" "$REP" <<'PYEOF' || fail "the rectangle map is wrong"
import json, sys
import numpy as np
import objmesh
P, F = objmesh.load(sys.argv[1])
pf = json.load(open(sys.argv[2]))["metrics"]["r_mean_abs_dev"]
a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
dom = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
print("x in [%g, %g], y in [%g, %g], folds %d, per-face %.4f" % (P[:, 0].min(), P[:, 0].max(), P[:, 1].min(), P[:, 1].max(), (dom <= 0).sum(), pf))
ok = abs(P[:, 0].min()) < 1e-12 and abs(P[:, 0].max() - 1) < 1e-12 and abs(P[:, 1].min()) < 1e-12 and abs(P[:, 1].max() - 0.5) < 1e-12
sys.exit(0 if ok and (dom > 0).all() and pf <= 0.02 else 1)
PYEOF
    grep -q "^vt " "$OUT" || fail "no vt"
    ;;
  bad_aspect)
    need disk_bump.obj
    for v in 2 0:1 2:-1 x:1; do
      run square "$IN" "$OUT" --aspect "$v"
      refused "aspect"
    done
    ;;
  help)
    run circles --help
    expect_status 0
    grep -q -- "--outer" "$T/log/stdout" || fail "the help does not list --outer"
    ;;
  *) fail "unknown case $CASE" ;;
esac
exit 0

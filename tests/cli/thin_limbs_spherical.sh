# thin_limbs_spherical.sh - `authalic sphere --spherical-areas` (the texture command's map) on a mesh of
# the generated thin-limbed family in data/ (issue 21): on the sphere's own triangles the map meets the
# issue's unrefined bounds, per-face mean |r - 1| <= 0.03 and vertex mean |log r| <= 0.01 (numpy here;
# param-eval's sph_ figures agree when ../shared is there), with no spherical triangle turned over, and
# the report's sph_ metrics and the summary line say the same. tpose failed with shape restoring kept on (0.0623 / 0.0291: a shape
# restoring step undone at every other solve).
# sh thin_limbs_spherical.sh PROG SOURCE_DIR SHARED_DIR MESH   (MESH: limbs4, limbs8, coil or tpose)
. "$(dirname "$0")/lib.sh"
[ -f "$SRC/data/$1.obj" ] || skip "data/$1.obj is absent"
IN=$(stage "$SRC/data/$1.obj")
OUT=$T/o/map.obj
run sphere "$IN" "$OUT" --spherical-areas --report "$T/o/r.json"
expect_status 0
expect_on_sphere "$OUT" 1e-12
# The chord floor does not hold spherical triangles: no warning of it (limbs8 and tpose, which miss the
# tolerance, had one under an older rule).
if grep -q 'chord area down' "$T/log/stderr"; then fail "a map of spherical areas warned of the chord floor"; fi
said=$(sed -n 's/^authalic: sphere: .* sph|r-1|=\([^ ]*\) sph vertex|log r|=\([^ ]*\) time=.*/\1 \2/p' "$T/log/stderr")
[ -n "$said" ] || fail "no spherical figures in the summary line"
$PY - "$IN" "$OUT" "$T/o/r.json" $said <<'PYEOF' >"$T/log/sph" || fail "the spherical triangles of $1's map (above)"
import json, sys
from objmesh import load, spherical_errors
X, F = load(sys.argv[1])
pf, ve, det = spherical_errors(X, F, load(sys.argv[2])[0])
m = json.load(open(sys.argv[3]))["metrics"]
print("spherical per-face %.4f, vertex %.4f (report %.4f, %.4f), %d turned over" % (
    pf, ve, m["sph_r_mean_abs_dev"], m["sph_vertex_logr_mean_abs"], (det <= 0).sum()), file=sys.stderr)
same = abs(pf - m["sph_r_mean_abs_dev"]) <= 1e-6 * (1 + pf) and abs(ve - m["sph_vertex_logr_mean_abs"]) <= 1e-6 * (1 + ve)
# The summary prints the report's doubles (numpy's agree to 1e-6, not always to the last digit shown).
same = same and sys.argv[4] == "%.3g" % m["sph_r_mean_abs_dev"] and sys.argv[5] == "%.3g" % m["sph_vertex_logr_mean_abs"]
print("%.9g %.9g" % (pf, ve))
sys.exit(0 if (det > 0).all() and pf <= 0.03 and ve <= 0.01 and same else 1)
PYEOF
# The independent evaluator's spherical figures, where ../shared is there.
PE=$SHARED/tools/param-eval
if [ -x "$PE" ]; then
  "$PE" "$IN" "$OUT" --json >"$T/log/pe.json" || fail "param-eval failed"
  $PY - "$T/log/pe.json" $(cat "$T/log/sph") <<'PYEOF' || fail "param-eval disagrees (above)"
import json, sys
d = json.load(open(sys.argv[1]))
pf, ve = float(sys.argv[2]), float(sys.argv[3])
print("param-eval: sph per-face %.4f, vertex %.4f, folds %d" % (d["sph_r_mean_abs_dev"], d["sph_vertex_logr_mean_abs"], d["folds"]), file=sys.stderr)
sys.exit(0 if d["folds"] == 0 and abs(d["sph_r_mean_abs_dev"] - pf) <= 1e-6 and abs(d["sph_vertex_logr_mean_abs"] - ve) <= 1e-6 else 1)
PYEOF
fi
exit 0

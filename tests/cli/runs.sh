# runs.sh - successful runs on a small mesh: replacing an earlier result, options that change the
# run (--steps, --tol, --no-balance, --start), and what --quiet leaves on stderr.
# sh runs.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
IN=$(stage "$SRC/tests/cli/unreferenced.obj")
OUT=$T/o/map.off
REP=$T/o/r.json

case $1 in
replace_existing)
  # An earlier result is replaced whole, keeps its permissions, and no temporary file is left.
  echo "an earlier result" >"$OUT"
  chmod 640 "$OUT"
  run sphere "$IN" "$OUT" --quiet
  expect_status 0
  head -1 "$OUT" | grep -q '^OFF$' || fail "the output was not replaced by an OFF file"
  [ "$(sed -n 2p "$OUT")" = "$(obj_nv "$IN") $(grep -c '^f ' "$IN") 0" ] || fail "OFF counts: $(sed -n 2p "$OUT")"
  [ "$(stat -c %a "$OUT")" = 640 ] || fail "mode $(stat -c %a "$OUT"), expected 640"
  [ "$(ls -A "$T/o")" = "map.off" ] || fail "files left beside the output: $(ls -A "$T/o")"
  ;;
not_converged)
  # One step cannot reach the tolerance: still exit 0, with a warning on stderr and in the report.
  # (On this small mesh one step and the polishes reach any tolerance but 0: the global polish ends at
  # 3e-16.)
  run sphere "$IN" "$OUT" --steps 1 --tol 0 --report "$REP" --quiet
  expect_status 0
  expect_err "^authalic: warning: $IN: tolerance 0 not reached in 1 steps"
  $PY -c '
import json, sys
r = json.load(open(sys.argv[1]))
ok = r["steps"] == 1 and not r["converged"] and r["folds"] == 0 and len(r["convergence"]["err"]) == 2
ok = ok and any("not reached" in w for w in r["warnings"])
sys.exit(0 if ok else "report: steps %s converged %s warnings %s" % (r["steps"], r["converged"], r["warnings"]))
' "$REP" || fail "the report does not show the unconverged run"
  ;;
start)
  # --start multilevel (the coarse-to-fine start) on spiky_ico: a fold-free map within issue 39's bounds,
  # and the report says which start made it; --start conformal names the conformal one.
  SP=$(stage "$SRC/data/spiky_ico.obj")
  for st in multilevel conformal; do
    run sphere "$SP" "$T/o/$st.obj" --start $st --report "$T/o/$st.json" --quiet
    expect_status 0
    $PY -c '
import json, sys
r = json.load(open(sys.argv[1])); m = r["metrics"]
ok = r["start"] == sys.argv[2] and r["folds"] == 0 and m["r_mean_abs_dev"] <= 0.03 and m["vertex_logr_mean_abs"] <= 0.01
sys.exit(0 if ok else "report: start %s folds %s per-face %s vertex %s" % (r["start"], r["folds"], m["r_mean_abs_dev"],
                                                                         m["vertex_logr_mean_abs"]))
' "$T/o/$st.json" $st || fail "--start $st: the report does not show a good map from that start"
  done
  ;;
options)
  # --tol 0.5 stops early; --no-balance changes the start; both runs stay fold-free on the sphere.
  run sphere "$IN" "$T/o/a.obj" --tol 0.5 --report "$T/o/a.json" --quiet
  expect_status 0
  run sphere "$IN" "$T/o/b.obj" --no-balance --report "$T/o/b.json" --quiet
  expect_status 0
  run sphere "$IN" "$T/o/c.obj" --report "$T/o/c.json" --quiet
  expect_status 0
  run sphere "$IN" "$T/o/d.obj" --refine-faces --report "$T/o/d.json" --quiet
  expect_status 0
  run sphere "$IN" "$T/o/e.obj" --angles 3 --report "$T/o/e.json" --quiet
  expect_status 0
  for f in a b c d e; do expect_on_sphere "$T/o/$f.obj" 1e-12; done
  $PY -c '
import json, sys
a, b, c, d, e = (json.load(open(p)) for p in sys.argv[1:6])
def err(r): return r["convergence"]["err"][-1]
if not (a["converged"] and err(a) <= 0.5 and a["steps"] < c["steps"]):
    sys.exit("--tol 0.5: steps %d (default tol: %d), err %g" % (a["steps"], c["steps"], err(a)))
if b["initial_metrics"] == c["initial_metrics"]:
    sys.exit("--no-balance did not change the initial map")
# --refine-faces: more steps, for a lower per-face error.
fa, fd = c["metrics"]["r_mean_abs_dev"], d["metrics"]["r_mean_abs_dev"]
if not (d["steps"] > c["steps"] and fd < fa):
    sys.exit("--refine-faces: steps %d (default %d), per-face %g (default %g)" % (d["steps"], c["steps"], fd, fa))
# --angles 3: three steps after those of the flow (they replace its chord polish when the spherical
# part ends near the tolerance, so they may start before the default run ends); the cells come closer.
ca = e["convergence"].get("angle_from")
if not (0 < ca <= c["steps"] and e["steps"] == ca + 3 and "angle_from" not in c["convergence"]
        and e["metrics"]["vertex_logr_mean_abs"] < 0.5 * c["metrics"]["vertex_logr_mean_abs"]):
    sys.exit("--angles 3: from %s, %d steps (default %d), vertex %g (default %g)" % (ca, e["steps"], c["steps"],
             e["metrics"]["vertex_logr_mean_abs"], c["metrics"]["vertex_logr_mean_abs"]))
if any(r["folds"] for r in (a, b, c, d, e)):
    sys.exit("folds")
' "$T/o/a.json" "$T/o/b.json" "$T/o/c.json" "$T/o/d.json" "$T/o/e.json" || fail "the options did not act"
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

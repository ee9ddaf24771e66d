# param_eval.sh - the report's metrics agree with the independent evaluator
# AU_SHARED_DIR/tools/param-eval on the same map (skipped where it is absent).
# sh param_eval.sh PROG SOURCE_DIR SHARED_DIR MESH   (MESH relative to the source dir)
. "$(dirname "$0")/lib.sh"
PE=$SHARED/tools/param-eval
[ -f "$PE" ] || skip "$PE is absent"
[ -f "$SRC/$1" ] || skip "$SRC/$1 is missing (run au_mkdata to generate data/)"
IN=$(stage "$SRC/$1")
OUT=$T/o/map.obj
REP=$T/o/report.json

run sphere "$IN" "$OUT" --report "$REP" --quiet
expect_status 0
$PY "$PE" "$IN" "$OUT" --domain sphere --json >"$T/pe.json" 2>"$T/log/stderr" || fail "param-eval failed"
$PY - "$REP" "$T/pe.json" <<'PYEOF' || fail "the report disagrees with param-eval"
import json, sys
ours, theirs = json.load(open(sys.argv[1]))["metrics"], json.load(open(sys.argv[2]))
bad = []
for k in ("r_mean_abs_dev", "r_cv", "upsilon_mean_abs", "lambda_mean", "vertex_logr_mean_abs", "folds"):
    a, b = ours[k], theirs[k]
    if a is None or b is None or abs(a - b) > 1e-6 * max(1.0, abs(b)):
        bad.append("%s: authalic %r, param-eval %r" % (k, a, b))
    else:
        print("%-22s %.9g %.9g" % (k, a, b))
if theirs["folds"] != 0:
    bad.append("param-eval counts %d folds" % theirs["folds"])
if bad:
    sys.exit("\n".join(bad))
PYEOF
exit 0

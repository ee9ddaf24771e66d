# circles.sh - workflow.circles: a manifest row with command circles (data/holes3.obj, 4 loops) runs
# through the cohort workflow: status 0, no folds, per-face <= 0.02 and vertex <= 0.005 in cohort.tsv,
# a map and a preview written.
. "$(dirname "$0")/lib.sh"
d=$WORK/circles
rm -rf "$d" && mkdir -p "$d" || fail "cannot make $d"
[ -f "$SRC/data/holes3.obj" ] || skip "$SRC/data/holes3.obj is missing (run au_mkdata to generate data/)"
printf 'id\tinput\tcommand\toptions\tdensity\tattribute\nholes3\t%s\tcircles\t\t\t\n' "$SRC/data/holes3.obj" > "$d/manifest.tsv"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run.log" || { tail -30 "$d/run.log" >&2; fail "snakemake exited $?"; }
$PY - "$d/out/cohort.tsv" <<'PYEOF' || fail "cohort.tsv (above)"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
r = rows[0]
print({k: r[k] for k in ("id", "command", "status", "folds", "r_mean_abs_dev", "vertex_logr_mean_abs")})
sys.exit(not (len(rows) == 1 and r["command"] == "circles" and r["status"] == "0" and r["folds"] == "0"
              and float(r["r_mean_abs_dev"]) <= 0.02 and float(r["vertex_logr_mean_abs"]) <= 0.005))
PYEOF
n=$(find "$d/out/surfaces" -name '*.obj' -size +0 | wc -l)
p=$(find "$d/out/surfaces" -name '*.png' -size +0 | wc -l)
[ "$n" -ge 1 ] && [ "$p" -ge 1 ] || fail "no map or no preview in $d/out/surfaces"
echo "workflow.circles: ok"

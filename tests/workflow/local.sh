# local.sh - workflow.local: the cohort on seven meshes (every command) and one bad input, two cores, on this machine.
# Leaves WORK/local for workflow.rerun (a ctest fixture).
. "$(dirname "$0")/lib.sh"
d=$WORK/local
rm -rf "$d"
make_cohort "$d"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run1.log" || { tail -30 "$d/run1.log" >&2; fail "snakemake exited $? (the bad row must not fail the workflow)"; }
$PY "$CHECK" "$d/out" "$d/manifest.tsv" "$PROG" || fail "the cohort's outputs (above)"
n=$(grep -c "^rule map:" "$d/run1.log")
[ "$n" -eq 8 ] || fail "$n map jobs ran for 8 rows"
echo "workflow.local: 8 rows, $(grep -c 'Finished job' "$d/run1.log") jobs"

# rerun.sh - workflow.rerun: on workflow.local's finished cohort, a second run does nothing (output
# mtimes unchanged); touching one row's input redoes exactly that row (and the summary); changing one
# row's options in the manifest redoes exactly that row, with the new options.
. "$(dirname "$0")/lib.sh"
d=$WORK/local
[ -s "$d/out/cohort.tsv" ] || fail "no finished cohort in $d (workflow.local sets it up)"

# changed_rows BEFORE AFTER: the ids whose files under surfaces/ changed (or appeared), one line.
changed_rows() {
  diff "$1" "$2" | sed -n 's#^> surfaces/\([^/]*\)/.*#\1#p' | sort -u | tr '\n' ' ' | sed 's/ $//'
}
# map_jobs LOG: the ids of the map jobs a run made, one line.
map_jobs() {
  awk '/^rule map:/ {m = 1} m && /wildcards: id=/ {sub(/.*id=/, ""); print; m = 0}' "$1" | sort | tr '\n' ' ' | sed 's/ $//'
}

# 1. Nothing to do: snakemake says so, and no file is rewritten.
mtimes "$d/out" > "$d/mtimes.0"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run2.log" || fail "second run exited $?"
grep -q "Nothing to be done" "$d/run2.log" || { cat "$d/run2.log" >&2; fail "the second run did something"; }
mtimes "$d/out" > "$d/mtimes.1"
cmp -s "$d/mtimes.0" "$d/mtimes.1" || { diff "$d/mtimes.0" "$d/mtimes.1" >&2; fail "the second run changed files"; }

# 2. Touch the input of the third row (a file no other row uses): that row and the summary only.
row=$(awk -F'\t' 'NR == 4 {print $1}' "$d/manifest.tsv")
input=$(awk -F'\t' 'NR == 4 {print $2}' "$d/manifest.tsv")
sleep 1  # mtimes of 1 s resolution on some file systems
touch "$input"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run3.log" || fail "run after touching $input exited $?"
mtimes "$d/out" > "$d/mtimes.2"
[ "$(map_jobs "$d/run3.log")" = "$row" ] || fail "touching $row's input ran map jobs for: '$(map_jobs "$d/run3.log")'"
[ "$(changed_rows "$d/mtimes.1" "$d/mtimes.2")" = "$row" ] ||
  fail "touching $row's input changed the files of: '$(changed_rows "$d/mtimes.1" "$d/mtimes.2")'"
for f in status.json map.obj report.json preview.png; do
  grep -q "^surfaces/$row/$f " "$d/mtimes.2" && ! grep -qx "$(grep "^surfaces/$row/$f " "$d/mtimes.2")" "$d/mtimes.1" ||
    fail "$row/$f was not redone"
done
! grep -qx "$(grep '^cohort.tsv ' "$d/mtimes.2")" "$d/mtimes.1" || fail "cohort.tsv was not rewritten"
$PY "$CHECK" "$d/out" "$d/manifest.tsv" "$PROG" || fail "the cohort after the touch (above)"

# 3. New options for the fourth row in the manifest: that row only, run with them.
row=$(awk -F'\t' 'NR == 5 {print $1}' "$d/manifest.tsv")
awk -F'\t' -v OFS='\t' 'NR == 5 {$4 = "--steps 25"} {print}' "$d/manifest.tsv" > "$d/manifest.new" &&
  mv "$d/manifest.new" "$d/manifest.tsv"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run4.log" || fail "run after new options exited $?"
mtimes "$d/out" > "$d/mtimes.3"
[ "$(map_jobs "$d/run4.log")" = "$row" ] || fail "new options for $row ran map jobs for: '$(map_jobs "$d/run4.log")'"
[ "$(changed_rows "$d/mtimes.2" "$d/mtimes.3")" = "$row" ] ||
  fail "new options for $row changed the files of: '$(changed_rows "$d/mtimes.2" "$d/mtimes.3")'"
$PY -c 'import json, sys; a = json.load(open(sys.argv[1]))["argv"]; sys.exit(0 if a[-2:] == ["--steps", "25"] else 1)' \
  "$d/out/surfaces/$row/status.json" || fail "$row did not run with --steps 25"
$PY "$CHECK" "$d/out" "$d/manifest.tsv" "$PROG" || fail "the cohort after the new options (above)"

# 4. And then nothing again.
run_workflow "$d/out" "$d/manifest.tsv" "$d/run5.log" || fail "last run exited $?"
grep -q "Nothing to be done" "$d/run5.log" || fail "the run after the reruns did something"
echo "workflow.rerun: nothing redone twice; touch redid $(awk -F'\t' 'NR == 4 {print $1}' "$d/manifest.tsv") only, new options redid $row only"

# slurm.sh - workflow.slurm: the same cohort through a real Slurm. Starts a one-node Slurm on this
# machine (slurm_lib.sh: slurmctld, slurmd and munged with a generated slurm.conf in WORK/slurm),
# runs the workflow with the Slurm profile (workflow/profiles/slurm: Snakemake's --slurm), checks
# the outputs as workflow.local does and that every row ran in a Slurm job that Slurm logged as
# COMPLETED, and stops the daemons (by their PIDs). Skips only when the daemons cannot be started
# (not root, or the Slurm packages missing).
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/slurm_lib.sh"
d=$WORK/slurm
rm -rf "$d"
mkdir -p "$d/daemons" || fail "cannot make $d"
trap slurm_stop EXIT
if ! slurm_start "$d/daemons" 2>"$d/why"; then
  # Where the daemons cannot run at all this is a skip; where they could but did not, a failure.
  if [ "$(id -u)" -ne 0 ] || [ ! -x /usr/sbin/slurmd ] || [ ! -x /usr/sbin/slurmctld ] || [ ! -x /usr/sbin/munged ]; then
    skip "cannot start Slurm here: $(head -1 "$d/why")"
  fi
  fail "Slurm did not start: $(head -1 "$d/why")"
fi
export USER=${USER:-$(id -un)}  # Snakemake's Slurm executor reads it
make_cohort "$d"
# From the cohort's folder with relative paths, as a user types it: the jobs, which read the
# Snakefile again on the node in OUT, must still find the manifest.
cd "$d" || fail "cannot cd to $d"
snakemake -s "$SNAKEFILE" --profile "$SRC/workflow/profiles/slurm" --directory out \
  --config manifest=manifest.tsv authalic="$PROG" >"$d/run1.log" 2>&1 ||
  { tail -40 "$d/run1.log" >&2; fail "snakemake --profile workflow/profiles/slurm exited $?"; }
n=$(grep -c "has been submitted with SLURM jobid" "$d/run1.log")
# 8 rows x (map, preview) + 4 attribute pictures, and 8 distortion jobs where authalic has no
# --distortion (the map job writes it otherwise); the cohort summary runs locally.
want=20
"$PROG" sphere --help 2>&1 | grep -q -- '--distortion' || want=28
[ "$n" -eq "$want" ] || fail "$n jobs submitted to Slurm, expected $want (8 rows x map, preview[, distortion]; 4 attributes)"
$PY "$CHECK" "$d/out" "$d/manifest.tsv" "$PROG" --slurm "$d/daemons/jobcomp.log" || fail "the cohort's outputs (above)"
# A second run through Slurm has nothing to submit.
snakemake -s "$SNAKEFILE" --profile "$SRC/workflow/profiles/slurm" --directory out \
  --config manifest=manifest.tsv authalic="$PROG" >"$d/run2.log" 2>&1 || fail "second run exited $?"
grep -q "Nothing to be done" "$d/run2.log" || fail "the second run through Slurm did something"
echo "workflow.slurm: $n Slurm jobs, $(grep -c 'JobState=COMPLETED' "$d/daemons/jobcomp.log") completed in Slurm's log"

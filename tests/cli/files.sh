# files.sh - file-system failures: missing input, a directory as input, an output in a missing
# directory, an output that is a directory, and an existing output left untouched by a failed run.
# sh files.sh PROG SOURCE_DIR SHARED_DIR CASE
. "$(dirname "$0")/lib.sh"
GOOD=$(stage "$SRC/tests/cli/unreferenced.obj")

case $1 in
missing_input)
  run sphere "$T/no-such-file.obj" "$T/o/out.obj"
  expect_rejected 'no-such-file\.obj.*(no such file|cannot open)'
  ;;
dir_input)
  mkdir "$T/dir.obj"
  run sphere "$T/dir.obj" "$T/o/out.obj"
  expect_rejected 'directory'
  ;;
missing_outdir)
  run sphere "$GOOD" "$T/o/missing/out.obj"
  expect_rejected "directory '$T/o/missing' does not exist"
  [ ! -e "$T/o/missing" ] || fail "the missing directory was created"
  run sphere "$GOOD" "$T/o/out.obj" --report "$T/o/missing/r.json"
  expect_rejected "directory '$T/o/missing' does not exist"
  ;;
out_is_dir)
  mkdir "$T/o/d.obj"
  run sphere "$GOOD" "$T/o/d.obj"
  expect_status 2
  expect_one_error_line
  expect_err 'is a directory'
  [ -d "$T/o/d.obj" ] && [ -z "$(ls -A "$T/o/d.obj")" ] || fail "the directory was changed"
  ;;
interrupted)
  # SIGTERM at twelve moments spread over a whole run (the first one at its start, the last ones in
  # or after the write): each run either dies of the signal and leaves nothing, or had finished and
  # left the complete output alone. Nothing else may remain beside it (no hidden temporary). The run
  # takes a tenth of a second; under a loaded ctest the reference run can take longer than the
  # later ones, so the first moment is at the start, where a run is always still going.
  IN=$(stage "$SRC/data/spiky_ico.obj")
  t0=$(date +%s%N)
  run sphere "$IN" "$T/full.obj" --report "$T/full.json" --quiet
  expect_status 0
  t1=$(date +%s%N)
  lines=$(wc -l <"$T/full.obj")
  killed=0
  for i in 0 1 2 3 4 5 6 7 8 9 10 11; do
    rm -rf "$T/o" && mkdir "$T/o"
    "$PROG" sphere "$IN" "$T/o/out.obj" --report "$T/o/r.json" --quiet >"$T/log/stdout" 2>"$T/log/stderr" &
    pid=$!
    sleep "$(awk -v a="$t0" -v b="$t1" -v i="$i" 'BEGIN { printf "%.3f", (b - a) * 1e-9 * i / 10 + 0.001 }')"
    kill -TERM "$pid" 2>/dev/null
    wait "$pid"
    status=$?
    left=$(ls -A "$T/o" | tr '\n' ' ')
    if [ "$status" -eq 143 ] && [ -z "$left" ]; then
      killed=$((killed + 1))
    elif [ "$status" -eq 143 ]; then
      # Killed after the output was renamed into place (on its way out, e.g. in the sanitizer's exit
      # checks): the output is the finished one, nothing else may be there.
      [ "$left" = "out.obj r.json " ] || fail "a run killed at moment $i left: $left"
      [ "$(wc -l <"$T/o/out.obj")" -eq "$lines" ] || fail "a run killed at moment $i left an incomplete output"
    else
      expect_status 0
      [ "$left" = "out.obj r.json " ] || fail "a finished run left: $left"
      [ "$(wc -l <"$T/o/out.obj")" -eq "$lines" ] || fail "a finished run left an incomplete output"
    fi
  done
  [ "$killed" -gt 0 ] || fail "no run was interrupted"
  ;;
interrupted_write)
  # SIGTERM while the output is being written, deterministically: strace holds the process at its
  # first fsync (the map's temporary is written, not yet renamed) or its second (the map waits under
  # its temporary name while the report is written). The handler must remove every temporary.
  command -v strace >/dev/null 2>&1 || skip "strace is not installed"
  strace -f -o /dev/null true 2>/dev/null || skip "strace cannot trace here (ptrace not permitted)"
  IN=$(stage "$SRC/data/spiky_ico.obj")
  for when in 1 2; do
    rm -rf "$T/o" && mkdir "$T/o"
    strace -f -o /dev/null -e trace=fsync -e inject=fsync:delay_enter=3000000:when=$when \
      "$PROG" sphere "$IN" "$T/o/out.obj" --report "$T/o/r.json" --quiet >"$T/log/stdout" 2>"$T/log/stderr" &
    spid=$!
    while [ "$(ls -A "$T/o" | wc -l)" -lt "$when" ]; do
      kill -0 "$spid" 2>/dev/null || fail "the run ended before its write was held (fsync $when)"
      sleep 0.05
    done
    during=$(ls -A "$T/o" | tr '\n' ' ')
    kill -TERM "$(pgrep -P "$spid")"
    wait "$spid"
    status=$?
    expect_status 143
    left=$(ls -A "$T/o" | tr '\n' ' ')
    [ -z "$left" ] || fail "interrupted at fsync $when (files then: $during), left: $left"
  done
  ;;
keep_existing)
  # The run fails late (in validation, after the output name was accepted).
  printf 'the previous result\n' >"$T/o/out.obj"
  cp "$T/o/out.obj" "$T/keep"
  run sphere "$(stage "$SRC/tests/cli/bad/torus.obj")" "$T/o/out.obj" --report "$T/o/r.json"
  expect_status 2
  expect_one_error_line
  cmp -s "$T/o/out.obj" "$T/keep" || fail "the existing output was changed by a failed run"
  [ "$(ls -A "$T/o")" = "out.obj" ] || fail "files left beside the output: $(ls -A "$T/o")"
  ;;
*)
  fail "unknown case '$1'"
  ;;
esac
exit 0

# bad_input.sh - one file of the bad-input corpus (tests/cli/bad/) is rejected with exit status 2,
# one error line naming the file and the problem, and no output: neither where none was before,
# nor over an existing file (which keeps its bytes).
# sh bad_input.sh PROG SOURCE_DIR SHARED_DIR FILE REGEX
. "$(dirname "$0")/lib.sh"
[ -f "$SRC/tests/cli/bad/$1" ] || fail "corpus file $SRC/tests/cli/bad/$1 is missing"
IN=$(stage "$SRC/tests/cli/bad/$1")

run sphere "$IN" "$T/o/out.obj" --report "$T/o/report.json"
expect_rejected "$2"
expect_err "^authalic: error: $IN:"

echo "an earlier result" >"$T/o/out.obj"
cp "$T/o/out.obj" "$T/keep"
run sphere "$IN" "$T/o/out.obj"
expect_status 2
expect_err "$2"
cmp -s "$T/o/out.obj" "$T/keep" || fail "an existing output file was changed by a failed run"
rm "$T/o/out.obj"
expect_no_output
exit 0

# bad_input.sh - one file of the bad-input corpus (tests/cli/bad/) is rejected with exit status 2,
# one error line naming the file and the problem, and no output: neither where none was before,
# nor over an existing file (which keeps its bytes). In the sanitizer build the same run also
# fails on any leak or undefined behaviour (LeakSanitizer makes the exit status non-zero).
# A file whose name starts with "unreadable" is made unreadable first (mode 000); as root, which
# can read anything, the program then runs as the user nobody (setpriv), or the case is skipped.
# sh bad_input.sh PROG SOURCE_DIR SHARED_DIR FILE REGEX [COMMAND (default sphere)]
. "$(dirname "$0")/lib.sh"
CMD=${3:-sphere}
[ -f "$SRC/tests/cli/bad/$1" ] || fail "corpus file $SRC/tests/cli/bad/$1 is missing"
IN=$(stage "$SRC/tests/cli/bad/$1")

case $1 in
unreadable*)
  chmod 000 "$IN" || fail "cannot chmod $IN"
  if [ "$(id -u)" -eq 0 ]; then
    command -v setpriv >/dev/null 2>&1 || skip "running as root without setpriv: cannot make a file unreadable"
    # nobody must reach the input's folder and the output folder, but not the input itself.
    chmod 755 "$T" "$T/in" && chmod 777 "$T/o" || fail "cannot open up the scratch folder"
    printf '#!/bin/sh\nexec setpriv --reuid=65534 --regid=65534 --clear-groups "%s" "$@"\n' "$PROG" >"$T/as-nobody"
    chmod 755 "$T/as-nobody" || fail "cannot create $T/as-nobody"
    PROG=$T/as-nobody
  fi
  ;;
esac

run "$CMD" "$IN" "$T/o/out.obj" --report "$T/o/report.json"
expect_rejected "$2"
expect_err "^authalic: error: $IN:"

echo "an earlier result" >"$T/o/out.obj"
cp "$T/o/out.obj" "$T/keep"
run "$CMD" "$IN" "$T/o/out.obj"
expect_status 2
expect_err "$2"
cmp -s "$T/o/out.obj" "$T/keep" || fail "an existing output file was changed by a failed run"
rm "$T/o/out.obj"
expect_no_output
exit 0

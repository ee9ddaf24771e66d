# lib.sh - helpers shared by the end-to-end tests of the `authalic` program (POSIX sh, sourced).
# Every script is called as: sh SCRIPT.sh PROG SOURCE_DIR SHARED_DIR [ARGS...]; it exits 0 (pass),
# 1 (fail) or 77 (skip). Each run gets a private scratch folder: $T/o for outputs, $T/log for the
# program's stdout and stderr, so "no file was left behind" is simply "$T/o is empty". Inputs are
# copied into $T/in first (`stage`), so a misbehaving program can never damage the source tree.

PROG=$1
SRC=$2
SHARED=$3
shift 3

T=$(mktemp -d "${TMPDIR:-/tmp}/authalic-cli.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
mkdir "$T/o" "$T/log" "$T/in" || exit 1
PY=/usr/bin/python3
# The Python checks' shared helpers (objmesh.py) beside the scripts.
PYTHONPATH="$(cd "$(dirname "$0")" && pwd)${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONPATH

# The test's verdict, with the program's output for the log.
fail() {
  echo "FAIL: $*" >&2
  for f in stdout stderr; do
    if [ -s "$T/log/$f" ]; then
      echo "--- $f of the last run:" >&2
      head -c 4000 "$T/log/$f" >&2
    fi
  done
  exit 1
}

# Copy an input file into the scratch folder and print the copy's path.
stage() {
  cp "$1" "$T/in/" || fail "cannot copy $1"
  echo "$T/in/$(basename "$1")"
}

skip() {
  echo "SKIP: $*" >&2
  exit 77
}

# stage_shared MESH: skip unless ../shared has meshes/MESH and tools/param-eval; then IN is the staged
# copy of the mesh and PE the evaluator.
stage_shared() {
  PE=$SHARED/tools/param-eval
  [ -f "$SHARED/meshes/$1" ] || skip "$SHARED/meshes/$1 is absent"
  [ -x "$PE" ] || skip "$PE is absent"
  IN=$(stage "$SHARED/meshes/$1")
}

# Run the program; $status holds its exit status.
run() {
  echo "+ authalic $*" >&2
  "$PROG" "$@" >"$T/log/stdout" 2>"$T/log/stderr"
  status=$?
}

expect_status() {
  [ "$status" -eq "$1" ] || fail "exit status $status, expected $1"
}

# The stderr of the last run matches the extended regular expression $1 (case-insensitive).
expect_err() {
  grep -Eiq -- "$1" "$T/log/stderr" || fail "stderr does not match /$1/"
}

expect_out() {
  grep -Eiq -- "$1" "$T/log/stdout" || fail "stdout does not match /$1/"
}

# A failed run says so in exactly one line, "authalic: error: ...", and prints nothing on stdout.
expect_one_error_line() {
  n=$(wc -l <"$T/log/stderr")
  [ "$n" -eq 1 ] || fail "stderr has $n lines, expected exactly one error line"
  grep -q '^authalic: error: ' "$T/log/stderr" || fail "the error line does not start with 'authalic: error: '"
  [ ! -s "$T/log/stdout" ] || fail "a failed run printed on stdout"
}

# Nothing at all was created in the output folder (no result, no report, no temporary file).
expect_no_output() {
  left=$(ls -A "$T/o")
  [ -z "$left" ] || fail "files left in the output folder: $left"
}

# The usual end of a run rejected before or during the work: status 2, one error line, no file.
expect_rejected() {
  expect_status 2
  expect_one_error_line
  expect_no_output
  [ -z "$1" ] || expect_err "$1"
}

# The number of `v` lines of an OBJ file.
obj_nv() {
  grep -c '^v ' "$1"
}

# Faces of an OBJ file as plain 1-based index triples (texture/normal indices dropped).
obj_faces() {
  awk '$1 == "f" { for (i = 2; i <= 4; i++) { split($i, c, "/"); printf "%s%s", c[1], (i < 4 ? " " : "\n") } }' "$1"
}

# No face of the OBJ file $1 (f v/vt corners) is turned over in (u, v): a zero or negative signed area
# fails, with the count; $2 names the run in the message.
expect_vt_upright() {
  awk '$1 == "vt" { n++; u[n] = $2; v[n] = $3 }
       $1 == "f" { for (i = 2; i <= 4; i++) { split($i, c, "/"); t[i] = c[2] }
                   if ((u[t[3]] - u[t[2]]) * (v[t[4]] - v[t[2]]) - (u[t[4]] - u[t[2]]) * (v[t[3]] - v[t[2]]) <= 0) bad++ }
       END { if (bad) { print bad " faces turned over in (u, v)"; exit 1 } }' "$1" >"$T/log/flips" 2>&1 \
    || fail "$2$(cat "$T/log/flips")"
}

# Every `v` of an OBJ file lies on the unit sphere to within $2; prints the worst deviation if not.
expect_on_sphere() {
  awk -v tol="$2" '
    $1 == "v" { n++; r = sqrt($2 * $2 + $3 * $3 + $4 * $4); d = r - 1; if (d < 0) d = -d; if (d > worst || d != d) worst = d }
    END { if (n == 0 || !(worst <= tol)) { printf "%d vertices, worst | |p| - 1 | = %.3g\n", n, worst; exit 1 } }
  ' "$1" >"$T/log/sphere" 2>&1 || fail "$1: not on the unit sphere: $(cat "$T/log/sphere")"
}

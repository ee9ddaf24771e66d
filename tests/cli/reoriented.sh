# reoriented.sh - a mesh with two faces reversed against their neighbours maps with exit 0 and one
# warning naming the count, for the sphere (data/ellipsoid.obj), disk (data/disk_bump.obj) and torus
# (data/torus_r3.obj) commands; the output's faces are the faces before they were reversed, and the
# report has no fold and carries the warning.
# sh reoriented.sh PROG SOURCE_DIR SHARED_DIR
. "$(dirname "$0")/lib.sh"
for c in sphere:ellipsoid disk:disk_bump torus:torus_r3; do
  cmd=${c%%:*} name=${c#*:}
  [ -f "$SRC/data/$name.obj" ] || skip "data/$name.obj is missing"
  # Faces 3 and 101 turned over (their last two corners swapped).
  awk '$1 == "f" { n++; if (n == 4 || n == 102) { print "f", $2, $4, $3; next } } { print }' "$SRC/data/$name.obj" \
    >"$T/in/$name.obj" || fail "cannot write $T/in/$name.obj"
  nf=$(obj_faces "$T/in/$name.obj" | wc -l)
  run "$cmd" "$T/in/$name.obj" "$T/o/$name.obj" --quiet --report "$T/o/$name.json"
  expect_status 0
  expect_err "^authalic: warning: $T/in/$name.obj: re-oriented 2 of $nf faces to agree with their neighbours \(first: face 3\)"
  [ "$(grep -c 're-oriented' "$T/log/stderr")" -eq 1 ] || fail "$cmd: the re-orientation is not warned exactly once"
  obj_faces "$SRC/data/$name.obj" >"$T/f.in"
  obj_faces "$T/o/$name.obj" >"$T/f.out"
  cmp -s "$T/f.in" "$T/f.out" || fail "$cmd: the output's faces are not the faces before they were reversed"
  $PY -c '
import json, sys
r = json.load(open(sys.argv[1]))
sys.exit(0 if r["folds"] == 0 and any("re-oriented 2 of" in w for w in r["warnings"]) else "report: folds or warning")
' "$T/o/$name.json" || fail "$cmd: the report lacks the warning or has folds"
done
exit 0

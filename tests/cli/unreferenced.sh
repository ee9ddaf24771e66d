# unreferenced.sh - a mesh with a vertex no face uses maps with exit 0 and a warning, and the
# output keeps that vertex at its index: same vertex count, same faces, every vertex on the sphere.
# sh unreferenced.sh PROG SOURCE_DIR SHARED_DIR
. "$(dirname "$0")/lib.sh"
IN=$(stage "$SRC/tests/cli/unreferenced.obj")
OUT=$T/o/map.obj

run sphere "$IN" "$OUT" --quiet --report "$T/o/r.json"
expect_status 0
# Quiet keeps warnings: exactly the one about vertex 10.
[ "$(wc -l <"$T/log/stderr")" -eq 1 ] || fail "expected one warning line on stderr"
expect_err "^authalic: warning: $IN: .*referenced by no face \(10\)"
[ "$(obj_nv "$OUT")" -eq "$(obj_nv "$IN")" ] || fail "vertex count $(obj_nv "$OUT"), input has $(obj_nv "$IN")"
obj_faces "$IN" >"$T/f.in"
obj_faces "$OUT" >"$T/f.out"
cmp -s "$T/f.in" "$T/f.out" || fail "the output's faces differ from the input's"
expect_on_sphere "$OUT" 1e-12
$PY -c '
import json, sys
r = json.load(open(sys.argv[1]))
sys.exit(0 if r["folds"] == 0 and any("referenced by no face" in w for w in r["warnings"]) else "report: folds or warning")
' "$T/o/r.json" || fail "the report lacks the warning or has folds"
exit 0

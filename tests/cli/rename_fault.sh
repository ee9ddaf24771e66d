# rename_fault.sh - every output of a map that cannot be renamed into place, one at a time (the preload
# library fail_rename.c makes the N-th rename fail): whatever the exit status, no temporary is left in
# the output folder, and a report is never left without its map (the report describes OUT).
# sh rename_fault.sh PROG SOURCE_DIR SHARED_DIR SHIM
. "$(dirname "$0")/lib.sh"
SHIM=$1
[ -f "$SHIM" ] || fail "$SHIM is missing"
IN=$(stage "$SRC/data/ellipsoid.obj")
# The sanitizer build's runtime wants to come first among the preloaded libraries; the shim needs none.
ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
export ASAN_OPTIONS
failed_somewhere=0
for n in 1 2 3 4 5 6 7 8; do
  rm -rf "$T/o" && mkdir "$T/o"
  echo "+ AU_FAIL_RENAME=$n" >&2
  AU_FAIL_RENAME=$n LD_PRELOAD=$SHIM run sphere "$IN" "$T/o/out.obj" --refine-mesh "$T/o/surf.obj" \
    --distortion "$T/o/d.curv" --report "$T/o/rep.json" --quiet
  left=$(ls -A "$T/o" | grep '^\.authalic-' || true)
  [ -z "$left" ] || fail "rename $n failed: temporaries left behind: $left"
  if [ ! -e "$T/o/out.obj" ]; then
    [ "$status" -ne 0 ] || fail "rename $n failed: no map, exit status 0"
    [ ! -e "$T/o/rep.json" ] || fail "rename $n failed: a report without its map"
  fi
  [ "$status" -ne 0 ] && failed_somewhere=1
  if [ "$status" -eq 0 ]; then
    for f in out.obj surf.obj surf.obj.parents.txt d.curv rep.json; do
      [ -s "$T/o/$f" ] || fail "rename $n: exit status 0 without $f"
    done
  fi
done
# The renames counted must reach the outputs: with none failing the run never fails, so at least one of
# the eight must have been the program's.
[ "$failed_somewhere" -eq 1 ] || fail "no injected failure reached the program (is the shim preloaded?)"
exit 0

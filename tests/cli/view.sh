# view.sh - `authalic view` and --html: the page of a map, checked as a file and in headless Chromium.
#   page MESH CMD       map MESH (../shared/meshes, else data/) with CMD --html, then open the page in Chromium
#                       (WebGL through SwiftShader): no JavaScript error, 15% of a 1280x720 screenshot painted
#                       in 50 colours or more, the pixel over the map's most squeezed face in the squeezed
#                       colour (the page's #probe option turns the map to it and prints where it is; every
#                       colour mode is drawn once and the face picked there must be that face); `view`
#                       of the written map makes the same page's data
#   writer              the C writer alone (also under the sanitizers): a page with no URL whose figures are
#                       the report's, --attr, a MAP that is not IN's map refused (exit 2, no file), and a
#                       torus map read back from its OBJ vt
. "$(dirname "$0")/lib.sh"
case=$1
[ -x "$PY" ] || skip "$PY is absent"

# $1: a mesh of ../shared/meshes, $2: its stand-in in data/ when ../shared is absent.
mesh() {
  if [ -f "$SHARED/meshes/$1" ]; then IN=$(stage "$SHARED/meshes/$1"); else IN=$(stage "$SRC/data/$2"); fi
}

case $case in
page)
  CHROME=$(command -v chromium || command -v chromium-browser) || skip "chromium is not installed (scripts/setup-debian.sh)"
  mesh "$2" "$4"
  cmd=$3
  # The default run: it converges in about ten steps (fewer steps would set off the slower retries).
  run "$cmd" "$IN" "$T/o/map.obj" --html "$T/o/map.html" --report "$T/o/r.json" --quiet
  expect_status 0
  $PY "$SRC/tests/cli/viewcheck.py" page "$T/o/map.html" "$T/o/r.json" >&2 || fail "the page"
  run view "$IN" "$T/o/map.obj" "$T/o/view.html" --quiet
  expect_status 0
  $PY "$SRC/tests/cli/viewcheck.py" same "$T/o/map.html" "$T/o/view.html" >&2 || fail "view's page differs from --html's"
  # A private profile, so runs in parallel and a user's own browser do not meet.
  "$CHROME" --headless --no-sandbox --use-gl=swiftshader --enable-unsafe-swiftshader --user-data-dir="$T/profile" \
    --window-size=1280,720 --virtual-time-budget=8000 --enable-logging=stderr --v=0 \
    --screenshot="$T/o/shot.png" "file://$T/o/map.html#probe" >"$T/log/chromium" 2>&1
  if [ ! -s "$T/o/shot.png" ] && grep -Eq "Missing X server|cannot open display|Failed to (launch|initialize)" "$T/log/chromium"; then
    skip "chromium cannot run here: $(grep -Em1 "Missing X server|cannot open display|Failed to" "$T/log/chromium")"
  fi
  [ -s "$T/o/shot.png" ] || { cp "$T/log/chromium" "$T/log/stderr"; fail "chromium made no screenshot"; }
  $PY "$SRC/tests/cli/viewcheck.py" shot "$T/log/chromium" "$T/o/shot.png" >&2 || { cp "$T/log/chromium" "$T/log/stderr"; fail "the page in chromium"; }
  ;;
writer)
  IN=$(stage "$SRC/data/ellipsoid.obj")
  run sphere "$IN" "$T/o/s.obj" --steps 3 --report "$T/o/r.json" --html "$T/o/s.html" --quiet
  expect_status 0
  $PY "$SRC/tests/cli/viewcheck.py" page "$T/o/s.html" "$T/o/r.json" >&2 || fail "the --html page"
  # An attribute: one number per vertex, shown under its file's name.
  nv=$(obj_nv "$IN")
  awk -v n="$nv" 'BEGIN { for (i = 0; i < n; i++) print i }' >"$T/in/index.txt"
  run view "$IN" "$T/o/s.obj" "$T/o/v.html" --attr "$T/in/index.txt" --title "ellipsoid <test>"
  expect_status 0
  expect_err "view: .*v.html"
  grep -q '"attr":{"name":"index.txt"' "$T/o/v.html" || fail "the attribute is not in the page"
  grep -q '"title":"ellipsoid \\u003ctest\\u003e"' "$T/o/v.html" || fail "the title is not escaped"
  $PY "$SRC/tests/cli/viewcheck.py" page "$T/o/v.html" >&2 || fail "the view page"
  rm -f "$T/o/v.html"
  # A map of another mesh, and an attribute of the wrong length: refused, nothing written.
  other=$(stage "$SRC/data/disk_bump.obj")
  mkdir "$T/keep" && mv "$T/o/s.obj" "$T/o/s.html" "$T/o/r.json" "$T/keep/"
  run view "$IN" "$other" "$T/o/v.html"
  expect_rejected "faces are not those of"
  echo "1 2 3" >"$T/in/short.txt"
  run view "$IN" "$T/keep/s.obj" "$T/o/v.html" --attr "$T/in/short.txt"
  expect_rejected "short.txt"
  run view "$IN" "$T/keep/s.obj"
  expect_rejected "expected IN MAP OUT.html"
  # A map by per-corner vt (a torus): read back from the OBJ, tiled by the lattice found in it.
  TR=$(stage "$SRC/data/torus_r3.obj")
  run torus "$TR" "$T/o/t.obj" --html "$T/o/t.html" --quiet
  expect_status 0
  run view "$TR" "$T/o/t.obj" "$T/o/tv.html" --quiet
  expect_status 0
  grep -q '"kind":"torus","lattice":\[\[' "$T/o/tv.html" || fail "the torus map's page is not tiled"
  $PY "$SRC/tests/cli/viewcheck.py" same "$T/o/t.html" "$T/o/tv.html" >&2 || fail "view's torus page differs from --html's"
  ;;
*)
  fail "unknown case $case"
  ;;
esac
exit 0

#!/usr/bin/env bash
# view_size.sh - how big the `authalic view` page of a large map is and how long it takes to make and
# to open: generated closed genus-0 meshes (bench/mkbig.c), mapped with --init-only (the page, not the
# flow, is measured: its size depends only on the counts), then `authalic view` timed, then the page
# opened in headless Chromium (WebGL through SwiftShader, a software renderer: a browser on a GPU
# draws faster). Prints a markdown table.
set -u

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$root/build
sizes="60000 1000000"
out=""

usage() {
  cat <<END
usage: bench/view_size.sh [--build DIR] [--sizes "60000 1000000"] [--out DIR]
For each size S: DIR/big_S.obj (au_mkbig; kept when present), its --init-only sphere map, the page
'authalic view DIR/big_S.obj DIR/big_S.init.obj DIR/big_S.html' (seconds, bytes), and the page in
'chromium --headless --timeout=60000' with a 1280x720 screenshot: the whole run's wall seconds
(Chromium's own start and the screenshot included: compare with the smallest size), and the
milliseconds the page reports from the start of its loading to its first drawing (AUTHALIC_READY on
the console, performance.now(): real time, as no virtual time budget is given). Chromium takes the
screenshot at the page's load event, which a small page's drawing (after an asynchronous import of
three.js) may follow: its time then reads "not drawn".
  --build DIR   build directory holding authalic and au_mkbig (default: build)
  --sizes LIST  face counts (default: "$sizes")
  --out DIR     where meshes, maps, pages and view_size.md go (default: BUILD/view_size)
END
}

while [ $# -gt 0 ]; do
  case $1 in
    -h|--help) usage; exit 0 ;;
    --build|--sizes|--out)
      if [ $# -lt 2 ]; then echo "view_size: $1 needs a value" >&2; exit 2; fi
      case $1 in --build) build=$2 ;; --sizes) sizes=$2 ;; --out) out=$2 ;; esac
      shift 2 ;;
    *) echo "view_size: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$out" ] || out=$build/view_size
prog=$build/authalic
gen=$build/au_mkbig
chrome=$(command -v chromium || command -v chromium-browser) || { echo "view_size: chromium is not installed" >&2; exit 2; }
for p in "$prog" "$gen"; do
  [ -x "$p" ] || { echo "view_size: $p is missing; build it first" >&2; exit 2; }
done
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)

table=$out/view_size.md
{
  echo "| faces | vertices | page MB | view s | chromium wall s | page's own ms | screenshot |"
  echo "|---:|---:|---:|---:|---:|---:|---|"
} >"$table"
for s in $sizes; do
  mesh=$out/big_$s.obj map=$out/big_$s.init.obj page=$out/big_$s.html
  [ -s "$mesh" ] || "$gen" "$s" "$mesh" || { echo "view_size: au_mkbig $s failed" >&2; exit 1; }
  [ -s "$map" ] || "$prog" sphere "$mesh" "$map" --init-only --quiet || { echo "view_size: map of $s failed" >&2; exit 1; }
  t0=$(date +%s.%N)
  "$prog" view "$mesh" "$map" "$page" --quiet || { echo "view_size: view of $s failed" >&2; exit 1; }
  t1=$(date +%s.%N)
  "$chrome" --headless --no-sandbox --use-gl=swiftshader --enable-unsafe-swiftshader --user-data-dir="$out/profile" \
    --window-size=1280,720 --timeout=60000 --enable-logging=stderr --v=0 \
    --screenshot="$out/big_$s.png" "file://$page" >"$out/big_$s.chromium.log" 2>&1
  t2=$(date +%s.%N)
  ms=$(grep -o 'AUTHALIC_READY [0-9]* faces, drawn [0-9]* ms' "$out/big_$s.chromium.log" | awk '{print $5}')
  nf=$(grep -c '^f ' "$mesh")
  nv=$(grep -c '^v ' "$mesh")
  awk -v nf="$nf" -v nv="$nv" -v b="$(stat -c %s "$page")" -v t0="$t0" -v t1="$t1" -v t2="$t2" -v ms="${ms:-not drawn}" \
    -v png="big_$s.png" 'BEGIN { printf "| %d | %d | %.1f | %.2f | %.1f | %s | %s |\n", nf, nv, b / 1e6, t1 - t0, t2 - t1, ms, png }' \
    >>"$table"
done
cat "$table"

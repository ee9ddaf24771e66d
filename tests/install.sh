#!/bin/sh
# install.sh - libauthalic as a user gets it: `cmake --install` into a temporary prefix, then the
# examples built against the installed tree only, through pkg-config and through find_package, in C
# and C++, shared and static; each maps a closed genus-0 mesh with 0 folds and writes the very map
# the `authalic` program writes. Also: only the header is installed, the shared library has its
# SONAME and exports only au_ names, and defines nothing that would change its host process.
# sh install.sh BUILD_DIR SOURCE_DIR SHARED_DIR
set -u
B=$1 SRC=$2 SHARED=$3
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
P=$T/prefix
cmake --install "$B" --prefix "$P" >"$T/install.log" 2>&1 || { cat "$T/install.log"; fail "cmake --install failed"; }
[ "$(cd "$P/include" && ls)" = "authalic.h" ] || fail "installed headers: $(ls "$P/include")"
LIB=$(dirname "$(find "$P" -name 'libauthalic.so.*.*.*' | head -1)")
[ -n "$LIB" ] && [ -f "$LIB/libauthalic.a" ] || fail "no shared and static library under $P"
[ -x "$P/bin/authalic" ] || fail "the program is not installed"
[ -f "$LIB/pkgconfig/authalic.pc" ] && [ -f "$LIB/cmake/authalic/authalicConfig.cmake" ] || fail "no authalic.pc or authalicConfig.cmake"
soname=$(objdump -p "$LIB"/libauthalic.so.*.*.* | awk '/SONAME/ {print $2}')
[ "$soname" = "libauthalic.so.1" ] || fail "SONAME is '$soname'"
others=$(nm -D --defined-only "$LIB/libauthalic.so" | awk '{print $3}' | grep -v '^au_')
[ -z "$others" ] || fail "exported symbols other than au_*: $others"
nm -D --defined-only "$LIB/libauthalic.so" | grep -q ' au_map$' || fail "au_map is not exported"
for s in GOMP_parallel openblas_set_num_threads; do
  nm -D "$LIB/libauthalic.so" | grep -q " $s\$" && fail "the library defines or calls $s"
done

IN=$SHARED/meshes/bunny.obj
[ -f "$IN" ] || IN=$SRC/data/bumpy_star.obj
"$P/bin/authalic" sphere "$IN" "$T/cli.obj" --quiet || fail "the installed program failed"

check_run() { # name, program: maps IN, prints folds=0, writes the program's map byte for byte
  # As the program runs itself (and as authalic.h advises on two cores): one OpenMP and one BLAS thread.
  OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1 LD_LIBRARY_PATH=$LIB "$2" "$IN" "$T/$1.obj" >"$T/$1.out" 2>&1 || { cat "$T/$1.out"; fail "$1 failed"; }
  grep -q ' folds=0 ' "$T/$1.out" || fail "$1: $(cat "$T/$1.out")"
  cmp -s "$T/$1.obj" "$T/cli.obj" || fail "$1 wrote another map than the program"
  echo "$1: $(cat "$T/$1.out")"
}

export PKG_CONFIG_PATH=$LIB/pkgconfig
flags=$(pkg-config --cflags --libs authalic) || fail "pkg-config --cflags --libs authalic"
cc -std=c11 -Wall -Werror "$SRC/examples/map_sphere.c" $flags -o "$T/pc_c" || fail "cc with pkg-config"
c++ -Wall -Werror "$SRC/examples/map_sphere.cpp" $flags -o "$T/pc_cpp" || fail "c++ with pkg-config"
check_run pkgconfig_c "$T/pc_c"
check_run pkgconfig_cpp "$T/pc_cpp"

cmake -S "$SRC/examples" -B "$T/ex" -DCMAKE_PREFIX_PATH="$P" >"$T/ex.log" 2>&1 || { cat "$T/ex.log"; fail "find_package(authalic)"; }
cmake --build "$T/ex" >>"$T/ex.log" 2>&1 || { cat "$T/ex.log"; fail "building the examples with CMake"; }
check_run cmake_c "$T/ex/map_sphere"
check_run cmake_cpp "$T/ex/map_sphere_cpp"
check_run cmake_static "$T/ex/map_sphere_static"
ldd "$T/ex/map_sphere_static" | grep -q libauthalic && fail "the static example loads libauthalic.so"
exit 0

#!/bin/sh
# install.sh - install the authalic Python package for one interpreter, with its own copy of the
# library: PYTHON BUILD_DIR [DEST]. DEST defaults to the interpreter's site directory for local
# installs (/usr/local/lib/python3.X/dist-packages for Debian's /usr/bin/python3). The package goes
# to DEST/authalic: its .py files, libauthalic.so.1 copied from BUILD_DIR, and _config.py naming
# that copy, so `import authalic` works from any directory with no environment variable. Nothing is
# fetched from the network; any older copy of the package in DEST is replaced.
set -eu
PYTHON=$1 BUILD=$2
SRC=$(cd "$(dirname "$0")" && pwd)/authalic
DEST=${3:-$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')}
LIB=$BUILD/libauthalic.so.1
[ -f "$LIB" ] || { echo "install.sh: $LIB is missing: build the library first (make build)" >&2; exit 1; }
"$PYTHON" -c 'import numpy' 2>/dev/null || { echo "install.sh: $PYTHON has no numpy (Debian: python3-numpy)" >&2; exit 1; }
mkdir -p "$DEST"
TMP=$(mktemp -d "$DEST/.authalic-install.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
for f in "$SRC"/*.py; do
  case $(basename "$f") in _config.py) ;; *) cp "$f" "$TMP/" ;; esac
done
cp "$LIB" "$TMP/libauthalic.so.1"  # follows the symlink: the real file under the SONAME
cat >"$TMP/_config.py" <<'PY'
"""_config.py - written by python/install.sh (make python): the library this installed package loads."""
import os

LIBRARY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "libauthalic.so.1")
PY
chmod 644 "$TMP"/*
chmod 755 "$TMP"
rm -rf "$DEST/authalic"
mv "$TMP" "$DEST/authalic"
trap - EXIT
# Compiled once here, so that importing from a read-only location does not try to.
"$PYTHON" -m compileall -q "$DEST/authalic" >/dev/null
echo "installed the authalic package for $PYTHON in $DEST/authalic"

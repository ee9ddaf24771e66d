#!/usr/bin/env bash
# setup-debian.sh - install the Debian 12 packages authalic needs; quick and quiet when all are present.
#
# Run as root on a fresh machine (CI does, through .ci/run). It asks apt only when something is
# missing, so it is cheap to run before every build. As a non-root user it installs nothing: it
# names what is missing and fails, so the build does not stop later with a less clear error.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config  # compilers, make, the build system
  libsuitesparse-dev libopenblas-dev  # CHOLMOD with a fast BLAS
  libopenmesh-dev libgeographiclib-dev libcjson-dev libpng-dev
  python3-numpy  # the shared evaluator (param-eval), the data and bench scripts, the Python package
  python3-pytest python3-tqdm  # the Python package's tests; its progress bar
  libgiftiio-dev libexpat1-dev zlib1g-dev  # GIfTI surfaces (giftiio reads by name; .gii.gz is inflated with zlib first)
  python3-nibabel  # the neuro tests read what we write with nibabel (/usr/bin/python3)
  connectome-workbench  # wb_command: the neuro tests check our spheres with Connectome Workbench
  time  # /usr/bin/time, used by the benchmarks
  strace  # holds a run at its write in the interrupted-write test
  clang libclang-rt-14-dev llvm  # libFuzzer and its runtime (make fuzz); llvm-symbolizer for sanitizer stacks
  snakemake python3-matplotlib  # workflow/: the cohort engine (7.x), previews and cohort.png
  slurmctld slurmd slurm-client munge  # workflow/: the cluster path, tested on a one-node Slurm on localhost
  nodejs  # the view page's build: view/embed.mjs, and npm ci of three.js from view/package-lock.json
  chromium  # the view tests open the page headless (WebGL through SwiftShader)
)
# npm comes with Debian's nodejs as its own package; a Node.js from elsewhere (NodeSource) carries its
# own npm and conflicts with Debian's, so npm is asked for only when there is none.
command -v npm >/dev/null 2>&1 || PACKAGES+=(npm)

if ! command -v dpkg-query >/dev/null 2>&1; then
  echo "setup-debian.sh: not a Debian system (no dpkg-query); install the equivalents of: ${PACKAGES[*]}" >&2
  exit 0
fi

# One dpkg-query call for all packages; unknown ones are simply absent from its output.
installed=" $(dpkg-query -W -f='${Package}=${db:Status-Status} ' "${PACKAGES[@]}" 2>/dev/null || true) "
missing=()
for p in "${PACKAGES[@]}"; do
  [[ "$installed" == *" $p=installed "* ]] || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "setup-debian.sh: missing Debian packages: ${missing[*]}" >&2
  echo "setup-debian.sh: install them as root: apt-get install ${missing[*]}" >&2
  exit 1
fi

echo "setup-debian.sh: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"

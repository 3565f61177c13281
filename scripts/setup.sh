#!/usr/bin/env bash
# Installs the Debian packages nodetrace needs (when missing), then configures
# and builds into build/ (programs in build/bin/).
#   scripts/setup.sh [--sanitize] [--build-dir DIR]
# --help: this comment, before anything else runs.
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then sed -n '2,4s/^# \{0,1\}//p' "$0"; exit 0; fi
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
cmake_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --sanitize) cmake_args+=(-DNODETRACE_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo); shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

# groff-base: the test that the manual pages render without warnings. librandom123-dev:
# Philox, the path tracer's counter-based random numbers (header-only). ccache:
# a rebuild (the sanitizer, cross and fuzz builds of CI, another clone) reuses
# what an earlier build compiled.
# pybind11-dev, python3-dev, python3-numpy: the nodetrace Python module
# (python/), built for /usr/bin/python3; python3-pytest runs its tests,
# python3-matplotlib its example.
packages=(cmake g++ make ccache pkg-config zstd python3-matplotlib libzstd-dev libxxhash-dev libcli11-dev libfmt-dev
          libtinyobjloader-dev nlohmann-json3-dev libpng-dev libgtest-dev libgmock-dev groff-base
          librandom123-dev pybind11-dev python3-dev python3-numpy python3-pytest)
scripts/install-packages.sh "${packages[@]}"

source scripts/ccache-launcher.sh
cmake_args+=("${launcher[@]}")
cmake -S . -B "$build_dir" "${cmake_args[@]}" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"

#!/usr/bin/env bash
# Sets up (packages, configure, build) and runs the whole test suite with CTest.
#   scripts/test.sh            tests that need ../shared skip when it is absent
#   scripts/test.sh --ci       they must run: absent shared data fails (CI)
#   scripts/test.sh --sanitize the same suite built with ASan + UBSan in build-sanitize/
# Before the tests, the real Dinero IV is built from ../shared into build/dinero/
# (scripts/build-dinero.sh) for the tests that compare against it: with --ci a
# failure to build it fails the run; without, those tests skip.
set -euo pipefail
cd "$(dirname "$0")/.."

setup_args=()
ci=0
build_dir=build
while [ $# -gt 0 ]; do
  case "$1" in
    --ci) export NODETRACE_REQUIRE_SHARED=1; ci=1; shift ;;
    --sanitize) setup_args+=(--sanitize); build_dir=build-sanitize; shift ;;
    -h|--help) sed -n '2,8s/^# \{0,1\}//p' scripts/test.sh; exit 0 ;;
    *) echo "test.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

scripts/setup.sh "${setup_args[@]}" --build-dir "$build_dir"
if [ "$ci" = 1 ]; then
  scripts/build-dinero.sh >/dev/null
elif [ -f ../shared/dinero-iv/d4-7.tar.gz ]; then
  scripts/build-dinero.sh >/dev/null || echo "test.sh: Dinero IV not built; the tests that need it skip" >&2
fi
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)"

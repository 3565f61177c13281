#!/usr/bin/env bash
# Builds the real Dinero IV (d4-7) from ../shared/dinero-iv/d4-7.tar.gz into
# build/dinero/dineroIV, for the tests and benchmarks that compare against it.
# It is a test oracle only: nothing of it is compiled into nodetrace.
#   scripts/build-dinero.sh [--out DIR]   (default DIR: build/dinero)
# Prints the program's path. Does nothing when DIR/dineroIV was already built
# from the same archive. Exit 1 when the archive is absent or not the
# expected one.
set -euo pipefail
cd "$(dirname "$0")/.."

out=build/dinero
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    -h|--help) sed -n '2,8s/^# \{0,1\}//p' scripts/build-dinero.sh; exit 0 ;;
    *) echo "build-dinero.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

archive=../shared/dinero-iv/d4-7.tar.gz
expected=7b651823c8feb2ee7617be5591df15f9c99265b880e4a99c98c33f5d8b47a837

if [ ! -f "$archive" ]; then
  echo "build-dinero.sh: $archive not found: the Dinero IV release is part of ../shared" \
       "(see ../shared/README.md); without it the tests that compare against Dinero IV skip" >&2
  exit 1
fi
actual=$(sha256sum "$archive" | cut -d' ' -f1)
if [ "$actual" != "$expected" ]; then
  echo "build-dinero.sh: $archive has sha256 $actual, expected $expected (the published d4-7)" >&2
  exit 1
fi

# The stamp records which archive the program came from, so a rebuilt
# program is never mistaken for the published one and vice versa.
if [ -x "$out/dineroIV" ] && [ "$(cat "$out/.sha256" 2>/dev/null)" = "$expected" ]; then
  echo "$out/dineroIV"
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tar xzf "$archive" -C "$work"
src="$work/d4-7"
# d4-7 is 1990s C: its configure script predates today's compilers' defaults,
# so implicit declarations are warnings, not errors; its output is unchanged.
if ! (cd "$src" && CFLAGS="-O2 -w" ./configure >"$work/configure.log" 2>&1 &&
      make >"$work/make.log" 2>&1); then
  echo "build-dinero.sh: building Dinero IV failed; the end of its log:" >&2
  tail -20 "$work/configure.log" "$work/make.log" >&2 2>/dev/null || true
  exit 1
fi
mkdir -p "$out"
cp "$src/dineroIV" "$out/dineroIV.tmp"
mv "$out/dineroIV.tmp" "$out/dineroIV"
cp "$src/COPYRIGHT" "$out/COPYRIGHT"
echo "$expected" >"$out/.sha256"
echo "$out/dineroIV"

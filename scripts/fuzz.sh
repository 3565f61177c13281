#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with Debian's clang (ASan + UBSan
# + coverage) into build-fuzz/, seeds them from ../shared (traces, scenes,
# Dinero IV command lines) and runs each. Any crash, hang (an input running
# longer than --timeout) or sanitizer report fails the run.
#   scripts/fuzz.sh --ci              every target for a fixed number of runs
#                                     from seed 1 (deterministic, ~1 min each,
#                                     at most 90 s), from the seeds only
#   scripts/fuzz.sh --time 3600       each target for an hour (the longer run)
#   scripts/fuzz.sh --target din ...  only the named targets (repeatable)
# Prints executions and coverage (libFuzzer's cov/ft) per target; corpora grow
# in build-fuzz/corpus/TARGET, findings land in build-fuzz/findings/.
# --help: this comment, before anything else runs.
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then sed -n '2,12s/^# \{0,1\}//p' "$0"; exit 0; fi
set -euo pipefail
cd "$(dirname "$0")/.."

mode=time
seconds=600
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --ci) mode=ci; shift ;;
    --time) seconds="$2"; shift 2 ;;
    --target) targets+=("$2"); shift 2 ;;
    *) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
all_targets=(din xdin binary container aff obj dinero_cli)
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")

# Executions per target in CI: about a minute each on this 2-core machine
# under load (measured: din ~1100/s, xdin ~700/s, binary ~1700/s, container
# ~1300/s, aff ~250/s, obj ~200/s, dinero_cli ~10000/s). -max_total_time caps
# a slower machine at 90 s a target, so the 7 stay within ~10 minutes.
declare -A ci_runs=([din]=60000 [xdin]=40000 [binary]=80000 [container]=60000
                    [aff]=12000 [obj]=10000 [dinero_cli]=500000)

packages=(clang libclang-rt-14-dev cmake make pkg-config zstd libzstd-dev libxxhash-dev libcli11-dev
          libfmt-dev libtinyobjloader-dev nlohmann-json3-dev libpng-dev)
scripts/install-packages.sh "${packages[@]}"

build=build-fuzz
source scripts/ccache-launcher.sh
CC=clang CXX=clang++ cmake -S . -B "$build" -DNODETRACE_FUZZ=ON -DNODETRACE_BUILD_TESTS=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}") >/dev/null

# Seeds, remade every run from ../shared (never committed).
shared=../shared
seeds="$build/seeds"
rm -rf "$seeds"
mkdir -p "$seeds"/{din,xdin,binary,container,aff,obj,dinero_cli}
tracetool() { "$build/bin/tracetool" "$@"; }
cmake --build "$build" -j "$(nproc)" --target tracetool >/dev/null
if [ -d "$shared/dinero-golden" ]; then
  golden="$shared/dinero-golden"
  # The first 200 records (zstd stops on the closed pipe: only head's status counts).
  first_records() { zstd -dc "$1" 2>/dev/null | head -n 200 || [ "${PIPESTATUS[1]}" -eq 0 ]; }
  first_records "$golden/mm32.din.zst" >"$seeds/mm32.din"
  first_records "$golden/kd-bfl-s1.din.zst" >"$seeds/kd.din"
  first_records "$golden/mm32.xdin.zst" >"$seeds/mm32.xdin"
  # din seeds carry a first byte that chooses --tags-are-levels (fuzz_din.cpp).
  { printf '\0'; cat "$seeds/mm32.din"; } >"$seeds/din/mm32"
  { printf '\1'; cat "$seeds/kd.din"; } >"$seeds/din/kd-levels"
  { printf '\0'; cat "$seeds/kd.din"; } >"$seeds/din/kd"
  { printf '\0'; cat "$seeds/mm32.xdin"; } >"$seeds/xdin/mm32"
  tracetool convert "$seeds/mm32.din" "$seeds/binary/mm32.bin" --to binary
  tracetool convert "$seeds/mm32.din" "$seeds/binary/mm32.bin.zst" --to binary --frame-records 50
  tracetool convert "$seeds/kd.din" "$seeds/container/kd.din.zst" --tags-are-levels --frame-records 40
  tracetool convert "$seeds/mm32.xdin" "$seeds/container/mm32.xdin.zst" --frame-records 64
  cp "$seeds/binary/mm32.bin.zst" "$seeds/container/"
  zstd -q -c "$seeds/mm32.din" >"$seeds/container/plain.din.zst"
  tail -n +2 "$golden/MANIFEST.tsv" | cut -f3 | while read -r line; do
    echo "$line" | tr ' ' '\n' >"$seeds/dinero_cli/$(echo "$line" | md5sum | cut -c1-12)"
  done
else
  echo "fuzz.sh: ../shared is absent: the trace targets start from built-in seeds only" >&2
  printf '\0000 100\n1 0x200 7\n' >"$seeds/din/small"
  printf '\0r 100 4\nw 200 8 3\n' >"$seeds/xdin/small"
  printf -- '-l1-dsize\n8k\n-l1-dbsize\n8\n-l1-dassoc\n1\n' >"$seeds/dinero_cli/small"
fi
# A container with a treelet map after its animation frame's marker
# (formats/FORMAT.md 2.2.2): a tiny treelet-layout render, small enough for
# -max_len to hold the whole of it.
cmake --build "$build" -j "$(nproc)" --target tracer >/dev/null
"$build/bin/tracer" render mountain:6 --width 8 --height 6 --layout treelet --threads 1 -q \
  -o "$seeds/container/treelet.din.zst"
if [ -d "$shared/scenes" ]; then
  find "$shared/scenes" -name '*.aff' -size -16k -exec cp {} "$seeds/aff/" \;
fi
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' >"$seeds/aff/triangle.aff"
printf 'mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvt 0 0\nusemtl red\nf 1/1/1 2/1/1 3/1/1\nf 2 4 3\no quad\ng g1\nf -1 -2 -3\n\0newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 20\nd 0.5\nNi 1.5\nillum 2\n' \
  >"$seeds/obj/triangles"

status=0
summary=()
mkdir -p "$build/findings"
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target"
  mkdir -p "$corpus"
  args=(-timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1
        -artifact_prefix="$build/findings/$target-")
  if [ "$mode" = ci ]; then
    # A fresh corpus from the seeds and seed 1: the same executions every run.
    rm -rf "$corpus" && mkdir -p "$corpus"
    args+=(-seed=1 -runs="${ci_runs[$target]}" -max_total_time=90)
  else
    args+=(-max_total_time="$seconds")
  fi
  log="$build/fuzz-$target.log"
  echo "fuzz.sh: $target ..." >&2
  start=$(date +%s)
  if "$build/fuzz/fuzz_$target" "${args[@]}" "$corpus" "$seeds/$target" >"$log" 2>&1; then
    result=ok
  else
    result=FAILED
    status=1
    tail -n 40 "$log" >&2
  fi
  elapsed=$(( $(date +%s) - start ))
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  coverage=$(grep -E '^#[0-9]+' "$log" | tail -n 1 | grep -oE 'cov: [0-9]+ ft: [0-9]+' || true)
  summary+=("$(printf '%-11s %-6s %10s executions %4ss  %s' "$target" "$result" "${executions:-?}" "$elapsed" "$coverage")")
done
printf '%s\n' "${summary[@]}"
exit $status

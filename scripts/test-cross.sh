#!/usr/bin/env bash
# Same bytes on every machine: renders a fixed list of cases with the native
# build and with builds for other machines and compilers, and compares the
# whole files with cmp: traces, PNG images, `tracer info` JSON (its timings
# and peak memory aside), and `cachesim run` CSVs and `tracetool verify` /
# `info` outputs of each machine's programs on the other machine's traces.
# The other builds:
#   arm64     GCC cross-build (crossbuild-essential-arm64), run under qemu-aarch64:
#             GCC where every target has fused multiply-add
#   clang-v3  Clang with -march=x86-64-v3 (FMA and AVX2: what -march=native
#             gives): the Clang build and the x86-64-v3 build in one
#   tunables  the native programs with glibc's FMA, AVX2 and AVX-512 code
#             paths turned off through GLIBC_TUNABLES
# x86-64-v3 programs run on the CPU when it has AVX2 and FMA, else under
# qemu-x86_64 -cpu max. Installs what it needs (Debian packages, the arm64
# architecture), builds the native programs with scripts/setup.sh and the
# others into build-cross/.
#   scripts/test-cross.sh [--keep DIR]   keep every output in DIR (default: a temporary folder, removed)
# Exit: 0 when every file is identical, 1 when any differs or a step fails.
set -euo pipefail
cd "$(dirname "$0")/.."

keep=""
while [ $# -gt 0 ]; do
  case "$1" in
    --keep) keep="$2"; shift 2 ;;
    -h|--help) sed -n '2,19s/^# \{0,1\}//p' scripts/test-cross.sh; exit 0 ;;
    *) echo "test-cross.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
jobs=$(nproc)
started=$SECONDS
stage() { echo "test-cross.sh: $* ($((SECONDS - started)) s)" >&2; }

# --- packages ----------------------------------------------------------------
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo dpkg --add-architecture arm64
  $sudo apt-get update -qq
fi
scripts/install-packages.sh crossbuild-essential-arm64 qemu-user clang \
  libzstd-dev:arm64 libxxhash-dev:arm64 libfmt-dev:arm64 libpng-dev:arm64 libtinyobjloader-dev:arm64

# --- builds ------------------------------------------------------------------
stage "building the native programs"
scripts/setup.sh >/dev/null
source scripts/ccache-launcher.sh
build_variant() {
  local name=$1 targets=$2
  shift 2
  stage "building $name"
  mkdir -p build-cross
  # The build's output only when it fails (GCC's arm64 ABI notes are noise).
  if ! { cmake --no-warn-unused-cli -S . -B "build-cross/$name" -DCMAKE_BUILD_TYPE=Release -DNODETRACE_BUILD_TESTS=OFF \
           "${launcher[@]}" "$@" &&
         cmake --build "build-cross/$name" -j "$jobs" --target $targets; } >"build-cross/$name.log" 2>&1; then
    tail -n 40 "build-cross/$name.log" >&2
    echo "test-cross.sh: the $name build failed (build-cross/$name.log)" >&2
    exit 1
  fi
}
# arm64 reads the others' traces too; the x86-64-v3 build only renders.
build_variant arm64 "tracer tracetool cachesim" -DCMAKE_TOOLCHAIN_FILE=scripts/cross/aarch64-linux-gnu.cmake
build_variant clang-v3 tracer -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS=-march=x86-64-v3

# The arm64 programs must really be arm64 (a toolchain file that fell back
# to the host compiler would compare x86-64 with itself).
file -L build-cross/arm64/bin/tracer | grep -q 'ARM aarch64' ||
  { echo "test-cross.sh: build-cross/arm64/bin/tracer is not an arm64 program" >&2; exit 1; }

v3_runner=()
grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo || v3_runner=(qemu-x86_64 -cpu max)
tunables="glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F"
# The tunable names change between glibc versions: check that these take effect.
loader=$(find /lib64 /lib/x86_64-linux-gnu -maxdepth 1 -name 'ld-linux-x86-64.so.2' 2>/dev/null | head -n 1)
if grep -qw fma /proc/cpuinfo && [ -n "$loader" ] &&
   [ "$("$loader" --list-diagnostics | grep 'cpu_features.*active')" = \
     "$(GLIBC_TUNABLES=$tunables "$loader" --list-diagnostics | grep 'cpu_features.*active')" ]; then
  echo "test-cross.sh: GLIBC_TUNABLES=$tunables does not change glibc's active CPU features here" >&2
  exit 1
fi

root=$PWD
run() {
  local variant=$1 program=$2
  shift 2
  case "$variant" in
    native) "$root"/build/bin/"$program" "$@" ;;
    tunables) GLIBC_TUNABLES=$tunables "$root"/build/bin/"$program" "$@" ;;
    arm64) qemu-aarch64 -L / "$root"/build-cross/arm64/bin/"$program" "$@" ;;
    *) "${v3_runner[@]}" "$root"/build-cross/"$variant"/bin/"$program" "$@" ;;
  esac
}

# --- cases -------------------------------------------------------------------
# Each case: a name and tracer render arguments; @ stands for the case's
# output path without extension.
bart=../shared/scenes/bart
[ -f "$bart/robots/Robot.aff" ] && [ -f "$bart/kitchen/kitchen.aff" ] ||
  { echo "test-cross.sh: the BART scenes are not in $bart" >&2; exit 1; }
small="--width 64 --height 48 --quiet"
cases=()
for scene in $(build/bin/tracer scenes --format json | /usr/bin/python3 -c \
    'import json, sys; print(" ".join(s["name"] for s in json.load(sys.stdin)["scenes"]))'); do
  cases+=("builtin-$scene|$scene $small -o @.din.zst --image @.png")
done
cases+=(
  "robot-0|$bart/robots/Robot.aff --frame 0 --high-size 4k $small -o @.din.zst --image @.png"
  "robot-517|$bart/robots/Robot.aff --frame 517 --width 48 --height 36 --quiet -o @.din.zst --image @.png"
  "kitchen|$bart/kitchen/kitchen.aff --width 48 --height 36 --quiet -o @.din.zst --image @.png"
  "robot-bvh2|$bart/robots/Robot.aff --accel bvh2 --width 48 --height 36 --quiet -o @.xdin.zst"
  "robot-cwbvh8|$bart/robots/Robot.aff --accel cwbvh8 --width 48 --height 36 --quiet -o @.xdin.zst"
  "mountain-bvh4|mountain $small --accel bvh4 -o @.xdin.zst"
  "mountain-bvh8|mountain $small --accel bvh8 -o @.xdin.zst"
  "layouts|sphereflake $small --layout hybrid,veb --high-size 4k -o @-{layout}.din.zst"
  "in-flight|forest $small --rays-in-flight 32 --units 4 -o @.din.zst"
  "row-sampled|mountain --width 96 --height 72 --quiet --sample-rows 1/8 --sample-seed 5 -o @.din.zst"
  "path|sphereflake $small --integrator path --spp 2 -o @.din.zst --image @.png --pfm @.pfm"
  "path-kitchen|$bart/kitchen/kitchen.aff --width 32 --height 24 --quiet --integrator path --spp 2 --rays-in-flight 8 -o @.din.zst --pfm @.pfm --variance-pfm @-variance.pfm"
)
# A field-of-view sweep: 200 angles, among them those where glibc's tanf gives
# another float on arm64 than on x86-64.
for fov in 22.96 13.18 26.30 $(seq -f '%.2f' 0.37 0.89 176.0 | head -n 197); do
  cases+=("fov-$fov|sphereflake:1 --width 16 --height 12 --quiet --fov $fov -o @.din.zst --image @.png")
done

work=${keep:-$(mktemp -d /tmp/nodetrace-cross.XXXXXX)}
[ -n "$keep" ] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"

render_case() {
  local variant=$1 name=${2%%|*} arguments=${2#*|}
  local out="$work/$variant/$name"
  # shellcheck disable=SC2086  # the arguments are words, none with blanks
  run "$variant" tracer render ${arguments//@/$out} >"$out.log" 2>&1 || { echo "$name" >>"$work/$variant.failed"; }
}

render_all() {
  local variant=$1 running=0
  mkdir -p "$work/$variant"
  for entry in "${cases[@]}"; do
    render_case "$variant" "$entry" &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
  done
  wait
  if [ -s "$work/$variant.failed" ]; then
    echo "test-cross.sh: $variant: tracer render failed for: $(tr '\n' ' ' <"$work/$variant.failed")" >&2
    for name in $(head -n 3 "$work/$variant.failed"); do cat "$work/$variant/$name.log" >&2; done
    exit 1
  fi
}

# `tracer info` of every scene of the list, as JSON without its timings.
info_all() {
  local variant=$1 scene
  for scene in sphereflake mountain forest "$bart/robots/Robot.aff" "$bart/kitchen/kitchen.aff"; do
    run "$variant" tracer info "$scene" --format json | /usr/bin/python3 -c '
import json, sys
def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if "seconds" not in k and "peak" not in k}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value
print(json.dumps(strip(json.load(sys.stdin)), indent=1, sort_keys=True))'
  done >"$work/$variant/info.json"
}

# cachesim and tracetool of VARIANT on the traces TRACES_FROM wrote, named
# relative to their folder (the reports print the name).
read_traces() {
  local variant=$1 traces_from=$2 into="$work/$1/read-$2"
  mkdir -p "$into"
  (
    cd "$work/$traces_from"
    run "$variant" cachesim run robot-0.din.zst --size 4k,8k,16k --assoc 1,4 --scheme single,split \
      --format csv >"$into/robot-0.csv" 2>/dev/null
    run "$variant" cachesim run kitchen.din.zst --size 8k --assoc 1,full --format csv >"$into/kitchen.csv"
    run "$variant" tracetool verify robot-bvh2.xdin.zst >"$into/verify.txt"
    run "$variant" tracetool info layouts-veb.din.zst >"$into/info.txt"
  )
}

variants=(native arm64 clang-v3 tunables)
for variant in "${variants[@]}"; do
  stage "rendering ${#cases[@]} cases with $variant"
  render_all "$variant"
  info_all "$variant"
done
stage "reading traces across machines"
read_traces native native
read_traces arm64 native
read_traces native arm64

# --- comparison --------------------------------------------------------------
differ=0
compared=0
compare_dirs() {
  local reference=$1 other=$2 file
  for file in $(cd "$reference" && find . -maxdepth 1 -type f ! -name '*.log' | sort); do
    compared=$((compared + 1))
    if ! cmp -s "$reference/$file" "$other/$file"; then
      differ=$((differ + 1))
      echo "test-cross.sh: differs: $other/${file#./} ($(cmp "$reference/$file" "$other/$file" 2>&1 | head -n 1))" >&2
    fi
  done
}
for variant in "${variants[@]:1}"; do
  (cd "$work/native" && find . -maxdepth 1 -type f ! -name '*.log' | sort) >"$work/native.list"
  (cd "$work/$variant" && find . -maxdepth 1 -type f ! -name '*.log' | sort) >"$work/$variant.list"
  cmp -s "$work/native.list" "$work/$variant.list" ||
    { echo "test-cross.sh: $variant wrote other files than native" >&2; differ=$((differ + 1)); }
  compare_dirs "$work/native" "$work/$variant"
done
compare_dirs "$work/native/read-native" "$work/arm64/read-native"
compare_dirs "$work/native/read-native" "$work/native/read-arm64"

stage "compared $compared files, $differ differ"
if [ "$differ" -ne 0 ]; then
  echo "test-cross.sh: FAIL: $differ of $compared files differ" >&2
  exit 1
fi
echo "test-cross.sh: ${#cases[@]} renders x ${#variants[@]} builds: $compared files identical"

#!/usr/bin/env bash
# Speed of `cachesim run` on a level-tagged din container of >= 50 M records,
# against `zstd -dc` of the same file measured in the same run (medians):
#   - first, one configuration (8k single) against zstd -dc on the default
#     scene's trace and on the BART Kitchen trace (400x300, hybrid layout for a
#     4 KB high cache; rendered from ../shared/scenes when it is there): wall,
#     CPU (user + sys) and peak RSS of both, measured alternately in the same
#     run, and their ratios (goals: CPU at most 1.3 x, wall at most 1.0 x on an
#     idle machine, RSS at most 32 MiB); with Dinero IV (below), the ratio
#     against `zstd -dcq | dineroIV` for the same configuration (goal 10 x in
#     CPU), and `zstd -dcq | cachesim dinero` against `zstd -dcq | dineroIV`
#     with the same options (goal 3 x in CPU)
#   - reading speed on the BART Kitchen trace (issue 25), CPU and wall
#     medians of paired runs and their ratios: `cachesim run` (one
#     configuration) of the container against `zstd -dc` (goal 1.5 x in CPU);
#     `tracetool verify` against `zstd -t` (goal 1.3 x); and, for the same
#     records as another tool writes them (variable-width fields, `0 1a38 7`),
#     `cachesim run` of them compressed by plain `zstd` and of their plain
#     text, both against `zstd -dc` of the plain zstd file (goal 1.5 x)
#   - zstd -dc FILE >/dev/null                      (the reference)
#   - one configuration (8k, block 8, direct mapped, single)
#   - the Table 1 grid (4k,8k,16k x single,split) in one pass; ratio grid / one
#     (goal: at most 1.3)
#   - a 36-configuration sweep (1k..256k x assoc 1,2,4,8, single, LRU; goal: at
#     most 2 x one configuration) and the same with split added (72; goal: 3 x);
#     CPU time (user + sys) beside the wall clock; with Dinero IV,
#     36 Dinero IV runs (one per configuration) against the one pass
#   - peak RSS for 50 M records and for 500 M records (a pipe from a generator)
#   - with Dinero IV, the same configuration by Dinero IV
#
# Dinero IV is $DINEROIV (a program), else dineroIV on PATH, else the one
# scripts/build-dinero.sh builds from ../shared (built when it can be).
#
#   - replacement policies (issue 33) on the BART Kitchen trace: opt for one
#     configuration against LRU (goal 2.5 x in CPU), --curve with opt against
#     --curve with lru (goal 3 x), a grid of 4 policies x 3 sizes x 3 ways
#     (goal 3 x) and the 36 LRU configurations (goal 2 x) against one LRU
#     configuration; peak RSS of each
#   - many ways (issue 34): 8k fully associative (1,024 ways) FIFO, LRU and
#     random against `zstd -dc | cachesim dinero` with the same cache, on
#     sphereflake 320x240 (48.6 M records; goal at most 1 x), and 4 ways
#
#   scripts/bench-cachesim.sh [--build-dir DIR] [--repeat N] [--trace FILE]
#                             [--split-level K|auto] [--no-500m] [--one-only]
#                             [--reading-only] [--policies-only]
#
# --one-only stops after the one-configuration and reading comparisons;
# --reading-only runs the reading comparison alone; --policies-only the
# policies and many-ways comparisons alone.
#
# Without --trace it renders (once) DIR/bench/render75m.din.zst: the default
# built-in scene at 400x300, depth 10, hybrid layout for a 4 KB high cache
# (about 75 M records of a real traversal, with animation-frame markers, so
# the grid's split level is auto). A repeated synthetic trace is no stand-in:
# zstd's window finds the repeats and decompresses it unrealistically fast.
# The load average is printed before and after; figures taken under load are
# marked so.
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
repeat=5
trace=
split_level=auto
big=1
one_only=0
reading_only=0
policies_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --trace) trace=$2; shift 2 ;;
    --split-level) split_level=$2; shift 2 ;;
    --no-500m) big=0; shift ;;
    --one-only) one_only=1; shift ;;
    --reading-only) reading_only=1; shift ;;
    --policies-only) policies_only=1; shift ;;
    -h|--help) sed -n '2,57p' "$0"; exit 0 ;;
    *) echo "bench-cachesim.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

cachesim=$build_dir/bin/cachesim
tracetool=$build_dir/bin/tracetool
tracer=$build_dir/bin/tracer
for program in "$cachesim" "$tracetool" "$tracer"; do
  if [ ! -x "$program" ]; then
    echo "bench-cachesim.sh: $program is not built (cmake --build $build_dir)" >&2
    exit 2
  fi
done
golden=../shared/dinero-golden/kd-bfl-s1.din.zst
dinero=
if [ -n "${DINEROIV:-}" ] && [ -x "$DINEROIV" ]; then
  dinero=$DINEROIV
elif command -v dineroIV >/dev/null; then
  dinero=$(command -v dineroIV)
elif [ -f ../shared/dinero-iv/d4-7.tar.gz ]; then
  dinero=$(scripts/build-dinero.sh) || dinero=
fi
if [ -z "$trace" ] && [ "$reading_only" = 0 ] && [ "$policies_only" = 0 ]; then
  trace=$build_dir/bench/render75m.din.zst
  if [ ! -s "$trace" ]; then
    mkdir -p "$build_dir/bench"
    echo "making $trace (default scene, 400x300, depth 10) ..." >&2
    "$tracer" render --width 400 --height 300 --max-depth 10 --high-size 4k -q -o "$trace"
  fi
fi
[ -n "$trace" ] && records=$("$tracetool" info "$trace" | awk '$1 == "records" && $2 ~ /^[0-9]+$/ { print $2; exit }')

# Seconds taken by a command (wall clock), output discarded.
seconds() {
  local start end
  start=$(date +%s%N)
  "$@" >/dev/null
  end=$(date +%s%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f\n", (b - a) / 1e9 }'
}
# Wall, CPU (user + sys) seconds and peak RSS (KB) of a command, output
# discarded (notes on standard error are not timing output).
wall_cpu_rss() {
  local out
  out=$(mktemp)
  /usr/bin/time -f '%e %U %S %M' -o "$out" "$@" >/dev/null 2>/dev/null
  awk '{ printf "%.3f %.3f %d\n", $1, $2 + $3, $4 }' "$out"
  rm -f "$out"
}
# Wall clock and CPU seconds alone.
wall_and_cpu() { wall_cpu_rss "$@" | cut -d' ' -f1,2; }
median() { sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f\n", a / b }'; }
rate() { awk -v n="$records" -v t="$1" 'BEGIN { printf "%.1f\n", n / t / 1e6 }'; }


# One configuration against zstd -dc (and Dinero IV where it is on PATH) on
# one trace: medians of paired runs, taken alternately.
compare_one_config() {
  local file=$1 name=$2 n
  n=$("$tracetool" info "$file" | awk '$1 == "records" && $2 ~ /^[0-9]+$/ { print $2; exit }')
  local zw=() zc=() zr=() cw=() cc=() cr=() dw=() dc=() ew=() ec=()
  local load0 load1 wall cpu rss
  load0=$(cut -d' ' -f1 /proc/loadavg)
  for _ in $(seq "$repeat"); do
    read -r wall cpu rss < <(wall_cpu_rss zstd -q -dc "$file")
    zw+=("$wall") zc+=("$cpu") zr+=("$rss")
    read -r wall cpu rss < <(wall_cpu_rss "$cachesim" run "$file" --size 8k --block 8 --assoc 1 --scheme single --format csv)
    cw+=("$wall") cc+=("$cpu") cr+=("$rss")
    if [ -n "$dinero" ]; then
      read -r wall cpu rss < <(wall_cpu_rss bash -c "zstd -q -dc '$file' | '$dinero' -informat d -l1-usize 8k \
        -l1-ubsize 8 -l1-uassoc 1")
      dw+=("$wall") dc+=("$cpu")
      read -r wall cpu rss < <(wall_cpu_rss bash -c "zstd -q -dc '$file' | '$cachesim' dinero -informat d \
        -l1-usize 8k -l1-ubsize 8 -l1-uassoc 1")
      ew+=("$wall") ec+=("$cpu")
    fi
  done
  load1=$(cut -d' ' -f1 /proc/loadavg)
  local zwm zcm zrm cwm ccm crm
  zwm=$(printf '%s\n' "${zw[@]}" | median) zcm=$(printf '%s\n' "${zc[@]}" | median)
  zrm=$(printf '%s\n' "${zr[@]}" | median) cwm=$(printf '%s\n' "${cw[@]}" | median)
  ccm=$(printf '%s\n' "${cc[@]}" | median) crm=$(printf '%s\n' "${cr[@]}" | sort -n | tail -1)
  echo "one configuration (8k, block 8, direct mapped, single) on $name: $file ($n records)"
  echo "  cores: $(nproc); load average before $load0, after $load1; medians of $repeat paired runs"
  if awk -v a="$load0" -v b="$load1" -v c="$(nproc)" 'BEGIN { exit !(a > c / 2 || b > c / 2) }'; then
    echo "  NOTE: measured under load from other processes: figures are pessimistic and noisy"
  fi
  printf '  %-26s wall %6s s  cpu %6s s  peak RSS %7s KB\n' "zstd -dc FILE >/dev/null" "$zwm" "$zcm" "$zrm"
  printf '  %-26s wall %6s s  cpu %6s s  peak RSS %7s KB (largest)\n' "cachesim run" "$cwm" "$ccm" "$crm"
  printf '  %-26s wall %6s x  cpu %6s x  (goals: wall 1.0 on an idle machine, cpu 1.3; RSS 32768 KB)\n' \
    "cachesim / zstd -dc" "$(ratio "$cwm" "$zwm")" "$(ratio "$ccm" "$zcm")"
  if [ "${#dw[@]}" -gt 0 ]; then
    local dwm dcm
    dwm=$(printf '%s\n' "${dw[@]}" | median) dcm=$(printf '%s\n' "${dc[@]}" | median)
    printf '  %-26s wall %6s s  cpu %6s s  (cachesim run is %s x faster in wall, %s x in cpu; goal 10 in cpu)\n' \
      "zstd -dc | dineroIV" "$dwm" "$dcm" "$(ratio "$dwm" "$cwm")" "$(ratio "$dcm" "$ccm")"
    local ewm ecm
    ewm=$(printf '%s\n' "${ew[@]}" | median) ecm=$(printf '%s\n' "${ec[@]}" | median)
    printf '  %-26s wall %6s s  cpu %6s s  (dineroIV / cachesim dinero: %s x in wall, %s x in cpu; goal 3 in cpu)\n' \
      "zstd -dc | cachesim dinero" "$ewm" "$ecm" "$(ratio "$dwm" "$ewm")" "$(ratio "$dcm" "$ecm")"
  else
    echo "  no Dinero IV (\$DINEROIV, PATH, or ../shared for scripts/build-dinero.sh): no comparison with it"
  fi
}

# Medians of paired runs, taken in turn, of commands given as "label|command"
# (the first is the reference): CPU (user + sys), wall and the largest peak
# RSS of each, and each one's median ratio to the reference over the rounds.
compare_reading_pairs() {
  local goal=$1; shift
  local dir i load0 load1
  dir=$(mktemp -d)
  load0=$(cut -d' ' -f1 /proc/loadavg)
  for _ in $(seq "$repeat"); do
    for i in $(seq 0 $(($# - 1))); do
      local entry=${*:$((i + 1)):1}
      wall_cpu_rss bash -c "${entry#*|}" >>"$dir/$i"
    done
  done
  load1=$(cut -d' ' -f1 /proc/loadavg)
  echo "  load average before $load0, after $load1; medians of $repeat paired runs; goal $goal x in cpu"
  for i in $(seq 0 $(($# - 1))); do
    local entry=${*:$((i + 1)):1}
    local wm cm rm rw rc
    wm=$(cut -d' ' -f1 "$dir/$i" | median) cm=$(cut -d' ' -f2 "$dir/$i" | median)
    rm=$(cut -d' ' -f3 "$dir/$i" | sort -n | tail -1)
    rw=$(paste -d' ' "$dir/$i" "$dir/0" | awk '{ printf "%.3f\n", $1 / $4 }' | median)
    rc=$(paste -d' ' "$dir/$i" "$dir/0" | awk '{ printf "%.3f\n", $2 / $5 }' | median)
    printf '    %-34s wall %6s s  cpu %6s s  ratio wall %5s x  cpu %5s x  peak RSS %7s KB\n' \
      "${entry%%|*}" "$wm" "$cm" "$rw" "$rc" "$rm"
  done
  rm -rf "$dir"
}

# Issue 33's policies on one trace (BART Kitchen): opt, the curves and a grid
# of policies against one LRU configuration, CPU ratios with peak RSS.
compare_policies() {
  local file=$1 one="--size 8k --block 8 --assoc 4 --scheme single --format csv"
  echo "replacement policies (issue 33) on $file, CPU (user + sys), wall and peak RSS:"
  echo "  opt, one configuration (8k, 4 ways):"
  compare_reading_pairs 2.5 "lru 8k 4-way|'$cachesim' run '$file' $one" \
    "opt 8k 4-way|'$cachesim' run '$file' $one --policy opt"
  echo "  --curve, fully associative, every power-of-two size to 64 MB:"
  compare_reading_pairs 3 "--curve lru|'$cachesim' run '$file' --curve --assoc full --policy lru --format csv" \
    "--curve opt|'$cachesim' run '$file' --curve --assoc full --policy opt --format csv"
  echo "  grids against one LRU configuration (goals: 4 policies x 3 sizes x 3 ways 3 x; 36 LRU 2 x):"
  compare_reading_pairs 3 "lru 8k 4-way|'$cachesim' run '$file' $one" \
    "lru,plru,srrip,drrip x 4k,8k,16k x 1,4,8|'$cachesim' run '$file' --size 4k,8k,16k --assoc 1,4,8 \
      --policy lru,plru,srrip,drrip --format csv" \
    "36 lru (1k..256k x 1,2,4,8)|'$cachesim' run '$file' --size 1k,2k,4k,8k,16k,32k,64k,128k,256k \
      --assoc 1,2,4,8 --format csv"
}

# Issue 34's slow path: sets of many ways (8k fully associative: 1,024 ways)
# against cachesim dinero asked the same question (goal: at most 1 x).
compare_many_ways() {
  local file=$1 policy letter
  echo "many ways (issue 34) on $file: cachesim run against zstd -dc | cachesim dinero, same cache:"
  for policy in fifo lru random; do
    letter=${policy:0:1}
    compare_reading_pairs 1 "cachesim dinero 8k full $policy|zstd -q -dc '$file' | '$cachesim' dinero -informat d \
      -l1-dsize 8k -l1-dbsize 8 -l1-dassoc 1024 -l1-drepl $letter" \
      "cachesim run 8k full $policy|'$cachesim' run '$file' --size 8k --assoc full --policy $policy --format csv" \
      "cachesim run 8k 4-way $policy|'$cachesim' run '$file' --size 8k --assoc 4 --policy $policy --format csv"
  done
}

# Issue 25's reading goals on one trace (a container): the container, its
# verification, and the same records as another tool writes them.
compare_reading() {
  local file=$1 one="--size 8k --block 8 --assoc 1 --scheme single --format csv"
  local variable=${file%.din.zst}.variable.din
  if [ ! -s "$variable.zst" ] || [ ! -s "$variable" ]; then
    echo "making $variable(.zst) (its records with fields unpadded, as other tools write them) ..." >&2
    "$tracetool" cat "$file" |
      awk '{ a = $2; sub(/^0+/, "", a); if (a == "") a = "0"; print $1, a, $3 + 0 }' >"$variable"
    zstd -q -f -T2 "$variable" -o "$variable.zst"
  fi
  echo "reading speed (issue 25) on $file and $variable(.zst), CPU (user + sys) and wall:"
  echo "  the container, one configuration:"
  compare_reading_pairs 1.5 "zstd -dc FILE|zstd -q -dc '$file'" "cachesim run FILE|'$cachesim' run '$file' $one"
  echo "  verification:"
  compare_reading_pairs 1.3 "zstd -t FILE|zstd -q -t '$file'" "tracetool verify FILE|'$tracetool' verify '$file'"
  echo "  another tool's trace, variable-width fields (plain zstd, plain text):"
  compare_reading_pairs 1.5 "zstd -dc VARIABLE.zst|zstd -q -dc '$variable.zst'" \
    "cachesim run VARIABLE.zst|'$cachesim' run '$variable.zst' $one" \
    "cachesim run VARIABLE|'$cachesim' run '$variable' $one"
}

kitchen_scene=../shared/scenes/bart/kitchen/kitchen.aff
only=$((reading_only + policies_only))
[ "$only" -gt 0 ] || compare_one_config "$trace" "the trace"
if [ -r "$kitchen_scene" ]; then
  kitchen=$build_dir/bench/kitchen400.din.zst
  if [ ! -s "$kitchen" ]; then
    mkdir -p "$build_dir/bench"
    echo "making $kitchen (BART Kitchen, 400x300, high cache 4k) ..." >&2
    "$tracer" render "$kitchen_scene" --width 400 --height 300 --high-size 4k -q -o "$kitchen"
  fi
  [ "$only" -gt 0 ] || compare_one_config "$kitchen" "BART Kitchen"
  [ "$policies_only" = 1 ] || compare_reading "$kitchen"
  [ "$reading_only" = 1 ] || compare_policies "$kitchen"
else
  echo "no BART Kitchen scene at $kitchen_scene: the Kitchen comparisons are skipped"
fi
if [ "$reading_only" = 0 ]; then
  sphereflake=$build_dir/bench/sphereflake320.din.zst
  if [ ! -s "$sphereflake" ]; then
    mkdir -p "$build_dir/bench"
    echo "making $sphereflake (sphereflake, 320x240) ..." >&2
    "$tracer" render sphereflake --width 320 --height 240 -q -o "$sphereflake"
  fi
  compare_many_ways "$sphereflake"
fi
[ "$only" -gt 0 ] && exit 0
[ "$one_only" = 1 ] && exit 0

one_config=(run "$trace" --size 8k --block 8 --assoc 1 --scheme single --format csv)
grid=(run "$trace" --size 4k,8k,16k --block 8 --assoc 1 --scheme single,split
  --split-level "$split_level" --format csv)

sweep_sizes=1k,2k,4k,8k,16k,32k,64k,128k,256k
sweep36=(run "$trace" --size "$sweep_sizes" --block 8 --assoc 1,2,4,8 --scheme single
  --policy lru --format csv)
sweep72=(run "$trace" --size "$sweep_sizes" --block 8 --assoc 1,2,4,8 --scheme single,split
  --split-level "$split_level" --policy lru --format csv)

load_before=$(cut -d' ' -f1 /proc/loadavg)
zstd_times=() one_times=() grid_times=() s36_times=() s72_times=()
one_cpus=() grid_cpus=() s36_cpus=() s72_cpus=()
for _ in $(seq "$repeat"); do
  zstd_times+=("$(seconds zstd -q -dc "$trace")")
  read -r wall cpu < <(wall_and_cpu "$cachesim" "${one_config[@]}")
  one_times+=("$wall") one_cpus+=("$cpu")
  read -r wall cpu < <(wall_and_cpu "$cachesim" "${grid[@]}")
  grid_times+=("$wall") grid_cpus+=("$cpu")
  read -r wall cpu < <(wall_and_cpu "$cachesim" "${sweep36[@]}")
  s36_times+=("$wall") s36_cpus+=("$cpu")
  read -r wall cpu < <(wall_and_cpu "$cachesim" "${sweep72[@]}")
  s72_times+=("$wall") s72_cpus+=("$cpu")
done
zstd_median=$(printf '%s\n' "${zstd_times[@]}" | median)
one_median=$(printf '%s\n' "${one_times[@]}" | median)
grid_median=$(printf '%s\n' "${grid_times[@]}" | median)
s36_median=$(printf '%s\n' "${s36_times[@]}" | median)
s72_median=$(printf '%s\n' "${s72_times[@]}" | median)
one_cpu=$(printf '%s\n' "${one_cpus[@]}" | median)
grid_cpu=$(printf '%s\n' "${grid_cpus[@]}" | median)
s36_cpu=$(printf '%s\n' "${s36_cpus[@]}" | median)
s72_cpu=$(printf '%s\n' "${s72_cpus[@]}" | median)
load_after=$(cut -d' ' -f1 /proc/loadavg)

peak_rss_kb() { /usr/bin/time -v "$@" 2>&1 >/dev/null | awk -F': ' '/Maximum resident/ { print $2 }'; }
rss_50m=$(peak_rss_kb "$cachesim" "${grid[@]}")

echo "trace: $trace ($records records)"
echo "cores: $(nproc); load average before $load_before, after $load_after"
if awk -v a="$load_before" -v b="$load_after" -v n="$(nproc)" 'BEGIN { exit !(a > n / 2 || b > n / 2) }'; then
  echo "NOTE: measured under load from other processes: figures are pessimistic and noisy"
fi
echo "medians of $repeat runs (wall clock):"
printf '  %-44s %7s s  %6s M records/s\n' "zstd -dc FILE >/dev/null" "$zstd_median" "$(rate "$zstd_median")"
printf '  %-44s %7s s  %6s M records/s  (%s x zstd -dc)  cpu %s s\n' \
  "one configuration (8k single)" "$one_median" "$(rate "$one_median")" \
  "$(ratio "$one_median" "$zstd_median")" "$one_cpu"
printf '  %-44s %7s s  %6s M records/s  (%s x one configuration; goal 1.3)  cpu %s s (%s x)\n' \
  "Table 1 grid (4k,8k,16k x single,split)" "$grid_median" "$(rate "$grid_median")" \
  "$(ratio "$grid_median" "$one_median")" "$grid_cpu" "$(ratio "$grid_cpu" "$one_cpu")"
printf '  %-44s %7s s  %6s M records/s  (%s x one configuration; goal 2)  cpu %s s (%s x)\n' \
  "36 configurations (1k..256k x assoc 1,2,4,8)" "$s36_median" "$(rate "$s36_median")" \
  "$(ratio "$s36_median" "$one_median")" "$s36_cpu" "$(ratio "$s36_cpu" "$one_cpu")"
printf '  %-44s %7s s  %6s M records/s  (%s x one configuration; goal 3)  cpu %s s (%s x)\n' \
  "72 configurations (the 36, single and split)" "$s72_median" "$(rate "$s72_median")" \
  "$(ratio "$s72_median" "$one_median")" "$s72_cpu" "$(ratio "$s72_cpu" "$one_cpu")"
echo "peak RSS of the grid:"
printf '  %-44s %7s KB\n' "$records records (container)" "$rss_50m"
if [ "$big" = 1 ] && [ -r "$golden" ]; then
  # Through a pipe from a generator (the golden trace repeated): only memory
  # is measured, so 50 M and 500 M records can be compared.
  one=$(mktemp)
  zstd -q -dc "$golden" >"$one"
  for copies in 250 2500; do
    rss=$(/usr/bin/time -v bash -c "for _ in \$(seq $copies); do cat '$one'; done |
      '$cachesim' run - --tags-are-levels --size 4k,8k,16k --scheme single,split --split-level 6 \
      --format csv" 2>&1 >/dev/null | awk -F': ' '/Maximum resident/ { print $2 }')
    printf '  %-44s %7s KB\n' "$((copies * 200000)) records (text pipe)" "$rss"
  done
  rm -f "$one"
fi
if [ -n "$dinero" ]; then
  dinero_times=()
  for _ in $(seq "$repeat"); do
    dinero_times+=("$(seconds bash -c "zstd -q -dc '$trace' | '$dinero' -informat d -l1-usize 8k \
      -l1-ubsize 8 -l1-uassoc 1")")
  done
  dinero_median=$(printf '%s\n' "${dinero_times[@]}" | median)
  printf '  %-44s %7s s  (cachesim one configuration is %s x faster)\n' \
    "zstd -dc | dineroIV (8k single)" "$dinero_median" "$(ratio "$dinero_median" "$one_median")"
  # Dinero IV needs one full run per configuration.
  printf '  %-44s %7s s  (the 36-configuration pass is %s x faster)\n' \
    "36 x (zstd -dc | dineroIV), estimated" "$(awk -v t="$dinero_median" 'BEGIN { printf "%.3f", 36 * t }')" \
    "$(ratio "$(awk -v t="$dinero_median" 'BEGIN { print 36 * t }')" "$s36_median")"
else
  echo "no Dinero IV (\$DINEROIV, PATH, or ../shared for scripts/build-dinero.sh): no comparison with it"
fi

#!/usr/bin/env bash
# Loading and building large scenes (issue 35: 3 M triangles within 6 s wall
# and 250 bytes a triangle): `tracer info` on OBJ terrains of N triangles
# made by scripts/make-large-scene.py (kept in BUILD/bench/ for the next
# run), its wall time, CPU (user + sys) and peak RSS, medians of --runs runs.
# With --reference TRACER (another build's tracer, say of an older commit),
# the two run in turn on each scene and the ratios are printed: the machine's
# drift between runs then falls on both alike.
#   scripts/bench-large-scenes.sh [--build-dir build] [--runs 5]
#                                 [--triangles "250000 1000000 3000000"] [--reference PATH]
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build runs=5 triangles="250000 1000000 3000000" reference=
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --triangles) triangles="$2"; shift 2 ;;
    --reference) reference="$2"; shift 2 ;;
    -h|--help) sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "bench-large-scenes.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
tracer="$build_dir/bin/tracer"
[ -x "$tracer" ] || { echo "bench-large-scenes.sh: $tracer not found; build first (scripts/setup.sh)" >&2; exit 2; }
if [ -n "$reference" ] && [ ! -x "$reference" ]; then
  echo "bench-large-scenes.sh: --reference $reference is not an executable" >&2
  exit 2
fi
case "$runs" in '' | *[!0-9]* | 0) echo "bench-large-scenes.sh: --runs must be a positive integer" >&2; exit 2 ;; esac
[ -x /usr/bin/time ] || { echo "bench-large-scenes.sh: /usr/bin/time is missing (Debian package time)" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$build_dir/bench"

median() { sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# Appends "wall cpu peak_kib" of `tracer info SCENE` to FILE.
timed_info() {
  local file="$1" program="$2" scene="$3"
  /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$program" info --format json "$scene" >/dev/null 2>"$work/stderr" || {
    echo "bench-large-scenes.sh: $program info $scene failed:" >&2
    cat "$work/stderr" >&2
    exit 1
  }
  awk '{printf "%s %.2f %s\n", $1, $2 + $3, $4}' "$work/time" >>"$file"
}
column_median() { awk -v c="$2" '{print $c}' "$1" | median; }

echo "tracer info on large OBJ scenes: medians of $runs runs$([ -n "$reference" ] && echo ", in turn with $reference")"
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo); load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-10s %-8s %8s %8s %10s %9s\n' triangles program "wall s" "CPU s" "peak MiB" "B/tri"
for count in $triangles; do
  scene="$build_dir/bench/large-$count.obj"
  if [ ! -s "$scene" ]; then
    echo "making $scene ..." >&2
    /usr/bin/python3 scripts/make-large-scene.py --triangles "$count" "$scene"
  fi
  : >"$work/ours"
  : >"$work/reference"
  for _ in $(seq "$runs"); do
    timed_info "$work/ours" "$tracer" "$scene"
    [ -z "$reference" ] || timed_info "$work/reference" "$reference" "$scene"
  done
  for side in ours reference; do
    [ -s "$work/$side" ] || continue
    wall=$(column_median "$work/$side" 1) cpu=$(column_median "$work/$side" 2) peak=$(column_median "$work/$side" 3)
    awk -v n="$count" -v s="$side" -v w="$wall" -v c="$cpu" -v p="$peak" \
      'BEGIN {printf "%-10s %-8s %8.2f %8.2f %10.0f %9.0f\n", n, s, w, c, p / 1024, p * 1024 / n}'
    eval "${side}_wall=$wall ${side}_cpu=$cpu"
  done
  if [ -n "$reference" ]; then
    awk -v n="$count" -v ow="$ours_wall" -v rw="$reference_wall" -v oc="$ours_cpu" -v rc="$reference_cpu" \
      'BEGIN {printf "%-10s %-8s %8.2f %8.2f\n", n, "ratio", ow / rw, oc / rc}'
  fi
done

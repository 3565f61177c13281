#!/usr/bin/env bash
# The cost of simulating inside the render (tracer render --simulate): for
# each Table 1 size, CPU (user + sys) and wall of the same render with
# --discard-records (the reference: every record made, none used), with
# --simulate (cachesim run's single and split caches on the records, no
# text; goal: at most 1.3x the reference's CPU), and of the path it replaces
# (-o T.din.zst, then cachesim run T.din.zst). Medians of --runs alternating
# runs; the hybrid layout sized for each size's high cache, as Table 1.
#   scripts/bench-simulate.sh [--build-dir build] [--runs 3] [--width 400 --height 300]
#                             [--scene PATH] [--sizes "4k 8k 16k"] [--threads N]
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build runs=3 width=400 height=300 threads=0 sizes="4k 8k 16k"
scene="$(cd .. && pwd)/shared/scenes/bart/kitchen/kitchen.aff"
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --height) height="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --sizes) sizes="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    -h|--help) sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "bench-simulate.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
tracer="$build_dir/bin/tracer" cachesim="$build_dir/bin/cachesim"
for program in "$tracer" "$cachesim"; do
  [ -x "$program" ] || { echo "bench-simulate.sh: $program not found; build first (scripts/setup.sh)" >&2; exit 2; }
done
[ -f "$scene" ] || { echo "bench-simulate.sh: scene $scene not found" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# Appends "wall cpu" of the command to FILE.
timed() {
  local file="$1"; shift
  /usr/bin/time -f "%e %U %S" -o "$work/time" "$@" > /dev/null 2> "$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
  awk '{print $1, $2 + $3}' "$work/time" >> "$file"
}

echo "in-render simulation, $(basename "$scene") ${width}x${height}, threads ${threads} (0: one per core), medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg) on $(nproc) cores"
printf '%-5s %12s %12s %12s %12s %12s %12s %9s %9s\n' size discard_cpu discard_wall simulate_cpu simulate_wall \
  trace+run_cpu trace+run_wall sim/disc trace/sim
for size in $sizes; do
  half="$(( $(numfmt --from=iec "${size^^}") / 2 ))"
  render=("$tracer" render "$scene" -q --width "$width" --height "$height" --threads "$threads" --high-size "$half")
  options="--size $size --block 8 --assoc 1 --scheme single,split --split-level auto --format csv"
  for ((run = 0; run < runs; run++)); do
    timed "$work/discard-$size" "${render[@]}" --discard-records
    timed "$work/simulate-$size" "${render[@]}" --simulate "$options" --report "$work/report.csv"
    timed "$work/trace-$size" sh -c '"$@" -o "$0/t.din.zst" && '"'$cachesim'"' run "$0/t.din.zst" '"$options"' > "$0/run.csv"' \
      "$work" "${render[@]}"
  done
  if ! cmp -s "$work/report.csv" <(sed "s#$work/t.din.zst#hybrid-$half#" "$work/run.csv"); then
    echo "bench-simulate.sh: the in-render report differs from cachesim run's" >&2
    exit 1
  fi
  dc="$(awk '{print $2}' "$work/discard-$size" | median)" dw="$(awk '{print $1}' "$work/discard-$size" | median)"
  sc="$(awk '{print $2}' "$work/simulate-$size" | median)" sw="$(awk '{print $1}' "$work/simulate-$size" | median)"
  tc="$(awk '{print $2}' "$work/trace-$size" | median)" tw="$(awk '{print $1}' "$work/trace-$size" | median)"
  awk -v z="$size" -v dc="$dc" -v dw="$dw" -v sc="$sc" -v sw="$sw" -v tc="$tc" -v tw="$tw" 'BEGIN {
    printf "%-5s %12.2f %12.2f %12.2f %12.2f %12.2f %12.2f %8.2fx %8.2fx\n", z, dc, dw, sc, sw, tc, tw, sc / dc, tc / sc }'
done
echo "goal: simulate_cpu at most 1.3x discard_cpu (sim/disc); trace/sim: the CPU of writing the trace and running cachesim on it, per the in-render simulation's"

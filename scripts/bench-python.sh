#!/usr/bin/env bash
# The cost of the nodetrace Python module against the programs, on one
# trace of BART Kitchen (hybrid layout for an 8 KB high cache): CPU (user +
# sys) and peak memory (max RSS) of reading the trace into numpy
# (records(), whole) against `cachesim run` decoding it with one
# configuration (goal: at most 1.5x its CPU), of a batched read (batches of
# --batch records: its peak memory), and, when the module has simulate(), of
# simulating --options from Python against cachesim run with the same list
# (goal: at most 1.05x). Medians of --runs alternating runs; each figure is
# a whole process's, the interpreter's start and imports included (printed
# apart as "python start").
#   scripts/bench-python.sh [--build-dir build] [--runs 3] [--width 400 --height 300]
#                           [--scene PATH] [--batch 65536] [--options "--size 4k,8k,16k ..."]
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build runs=3 width=400 height=300 batch=65536
options="--size 4k,8k,16k --block 8 --assoc 1 --scheme single,split --split-level auto"
scene="$(cd .. && pwd)/shared/scenes/bart/kitchen/kitchen.aff"
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --height) height="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --batch) batch="$2"; shift 2 ;;
    --options) options="$2"; shift 2 ;;
    -h|--help) sed -n '2,13s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "bench-python.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
python=/usr/bin/python3
tracer="$build_dir/bin/tracer" cachesim="$build_dir/bin/cachesim"
for program in "$tracer" "$cachesim"; do
  [ -x "$program" ] || { echo "bench-python.sh: $program not found; build first (scripts/setup.sh)" >&2; exit 2; }
done
export PYTHONPATH="$build_dir/python"
"$python" -c "import nodetrace" || { echo "bench-python.sh: the nodetrace module is not in $build_dir/python" >&2; exit 2; }
[ -f "$scene" ] || { echo "bench-python.sh: scene $scene not found" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# Appends "cpu max_rss_mib" of the command to FILE; its standard output to FILE.out.
timed() {
  local file="$1"; shift
  /usr/bin/time -f "%U %S %M" -o "$work/time" "$@" > "$file.out" 2> "$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
  awk '{printf "%.3f %.1f\n", $1 + $2, $3 / 1024}' "$work/time" >> "$file"
}
cpu() { cut -d' ' -f1 "$1" | median; }
rss() { cut -d' ' -f2 "$1" | median; }

trace="$work/kitchen.din.zst"
"$tracer" render "$scene" -q --width "$width" --height "$height" --high-size 4k -o "$trace"
records="$("$python" -c "import nodetrace, sys; print(nodetrace.open(sys.argv[1]).trailer['totals']['records'])" "$trace")"
echo "nodetrace Python module, $(basename "$scene") ${width}x${height} ($records records), medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg) on $(nproc) cores"

simulate=0
"$python" -c "import nodetrace; nodetrace.simulate" 2> /dev/null && simulate=1
for ((run = 0; run < runs; run++)); do
  timed "$work/start" "$python" -c "import nodetrace, numpy"
  timed "$work/run1" "$cachesim" run "$trace" --size 8k --format csv
  timed "$work/read" "$python" -c "import nodetrace, sys; print(len(nodetrace.open(sys.argv[1]).records()))" "$trace"
  timed "$work/batches" "$python" -c "import nodetrace, sys
print(sum(len(b) for b in nodetrace.open(sys.argv[1]).batches(int(sys.argv[2]))))" "$trace" "$batch"
  if [ "$simulate" = 1 ]; then
    timed "$work/run" "$cachesim" run "$trace" $options --format csv
    timed "$work/simulate" "$python" -c "import nodetrace, sys
for row in nodetrace.simulate(sys.argv[1], sys.argv[2]): print(row)" "$trace" "$options"
  fi
done
for file in read batches; do
  [ "$(cat "$work/$file.out")" = "$records" ] || { echo "bench-python.sh: $file read $(cat "$work/$file.out") records, not $records" >&2; exit 1; }
done

ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }
printf '%-34s %9s %12s\n' step cpu_s max_rss_mib
printf '%-34s %9s %12s\n' "python start (import nodetrace)" "$(cpu "$work/start")" "$(rss "$work/start")"
printf '%-34s %9s %12s\n' "cachesim run, one configuration" "$(cpu "$work/run1")" "$(rss "$work/run1")"
printf '%-34s %9s %12s\n' "records() whole" "$(cpu "$work/read")" "$(rss "$work/read")"
printf '%-34s %9s %12s\n' "batches($batch)" "$(cpu "$work/batches")" "$(rss "$work/batches")"
echo "read whole / cachesim run (goal <= 1.5): $(ratio "$(cpu "$work/read")" "$(cpu "$work/run1")")"
echo "read in batches / cachesim run (goal <= 1.5): $(ratio "$(cpu "$work/batches")" "$(cpu "$work/run1")")"
echo "read whole without python start / cachesim run: $(ratio "$(awk -v a="$(cpu "$work/read")" -v b="$(cpu "$work/start")" 'BEGIN {print a - b}')" "$(cpu "$work/run1")")"
if [ "$simulate" = 1 ]; then
  printf '%-34s %9s %12s\n' "cachesim run $options" "$(cpu "$work/run")" "$(rss "$work/run")"
  printf '%-34s %9s %12s\n' "simulate() same list" "$(cpu "$work/simulate")" "$(rss "$work/simulate")"
  echo "simulate / cachesim run (goal <= 1.05): $(ratio "$(cpu "$work/simulate")" "$(cpu "$work/run")")"
  echo "simulate without python start / cachesim run: $(ratio "$(awk -v a="$(cpu "$work/simulate")" -v b="$(cpu "$work/start")" 'BEGIN {print a - b}')" "$(cpu "$work/run")")"
else
  echo "simulate: not in this module (no nodetrace.simulate)"
fi

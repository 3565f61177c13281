#!/usr/bin/env bash
# Tracer speed: rays per second rendering only, the cost of writing the trace
# as the ratio (render + trace) / render only (target: at most 2.0), and
# compressed bytes per record, for each built-in scene and the two BART
# scenes; the kd-tree build on one thread and on every core; the binary BVH
# against the kd-tree (build time, rays per second). Medians of --runs runs;
# each run is one `tracer render`. Then, for the BART scenes, the same ratio
# for the whole command (wall and CPU user + sys of `tracer render ...
# --high-size 4k` with and without -o, runs alternating), with peak RSS;
# writing the trace with 32 rays in flight against 1 (wall and CPU, target at
# most 1.3x CPU) and the peak RSS at 1, 32 and 128; a row-sampled run (1/8)
# against the full run (render + simulate, target at most 0.25x CPU); last,
# primary rays per second against Embree where libembree-dev is installed (a
# benchmark-only reference), and a path tracer's rays kind by kind against
# Embree (rays/s per core of each kind). --path-only: a path-traced frame
# (--spp 4) writing its trace against --discard-records (target at most
# 2.0x CPU), and its rays per CPU second.
#   scripts/bench-tracer.sh [--build-dir build] [--runs 3] [--width 400 --height 300]
#                           [--max-depth 10] [--threads N] [--scenes "a b c"]
#                           [--in-flight-only | --sampled-only | --path-only]
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build runs=3 width=400 height=300 max_depth=10 threads=0 scenes="" in_flight_only=0 sampled_only=0
path_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --path-only) path_only=1; shift ;;
    --in-flight-only) in_flight_only=1; shift ;;
    --sampled-only) sampled_only=1; shift ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --height) height="$2"; shift 2 ;;
    --max-depth) max_depth="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    -h|--help) sed -n '2,22s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "bench-tracer.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
tracer="$build_dir/bin/tracer"
[ -x "$tracer" ] || { echo "bench-tracer.sh: $tracer not found; build first (scripts/setup.sh)" >&2; exit 2; }

shared="$(cd .. && pwd)/shared/scenes/bart"
if [ -z "$scenes" ]; then
  scenes="$("$tracer" scenes | awk 'NR > 1 && NF > 1 && $1 ~ /^[a-z]/ && $2 ~ /^[0-9]+$/ {print $1}' | tr '\n' ' ')"
  for bart in robots/Robot.aff kitchen/kitchen.aff; do
    if [ -f "$shared/$bart" ]; then
      scenes="$scenes $shared/$bart"
    else
      echo "bench-tracer.sh: $shared/$bart absent: skipped" >&2
    fi
  done
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
thread_args=()
[ "$threads" != 0 ] && thread_args=(--threads "$threads")

column() { awk -v c="$1" '{print $c}'; }
median() { sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# Seconds of the render loop from tracer's summary line "render: X s, ...".
render_seconds() { sed -n 's/^  render: \([0-9.]*\) s.*/\1/p' "$1"; }

# Writing the trace with rays in flight: 32 against 1 (alternating runs,
# wall and CPU user + sys of the whole command), and the peak RSS at 1, 32
# and 128 rays in flight, for the BART scenes.
rays_in_flight() {
  echo "rays in flight, ${width}x${height} --high-size 4k -o T.din.zst, medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
  printf '%-12s %8s %9s %8s %9s %10s %9s %8s %9s %10s
' scene wall_1 cpu_1 wall_32 cpu_32 wall_ratio cpu_ratio MiB_1 MiB_32 MiB_128
  local bart scene n
  for bart in robots/Robot.aff kitchen/kitchen.aff; do
    scene="$shared/$bart"
    if [ ! -f "$scene" ]; then
      echo "bench-tracer: $scene absent: skipped" >&2
      continue
    fi
    for n in 1 32 128; do : > "$work/inflight$n.all"; done
    for ((run = 0; run < runs; run++)); do
      for n in 1 32 128; do
        /usr/bin/time -f '%e %U %S %M' -o "$work/t" "$tracer" render "$scene" --width "$width" --height "$height" \
          --max-depth "$max_depth" --high-size 4k --rays-in-flight "$n" "${thread_args[@]}" -q \
          -o "$work/inflight.din.zst" >/dev/null 2>/dev/null
        cat "$work/t" >> "$work/inflight$n.all"
      done
    done
    awk -v n="$(basename "$scene")" \
        -v w1="$(awk '{print $1}' "$work/inflight1.all" | median)" -v c1="$(awk '{print $2 + $3}' "$work/inflight1.all" | median)" \
        -v w32="$(awk '{print $1}' "$work/inflight32.all" | median)" -v c32="$(awk '{print $2 + $3}' "$work/inflight32.all" | median)" \
        -v m1="$(awk '{print $4}' "$work/inflight1.all" | median)" -v m32="$(awk '{print $4}' "$work/inflight32.all" | median)" \
        -v m128="$(awk '{print $4}' "$work/inflight128.all" | median)" 'BEGIN {
      printf "%-12s %8.2f %9.2f %8.2f %9.2f %10.2f %9.2f %8.0f %9.0f %10.0f\n", n, w1, c1, w32, c32, w32 / w1, c32 / c1, m1 / 1024, m32 / 1024, m128 / 1024 }'
  done
  echo "wall/cpu_N: tracer render --rays-in-flight N writing the trace (cpu = user + sys); ratios 32 / 1 (target <= 1.3"
  echo "in CPU time); MiB_N: peak RSS"
}

# A row-sampled run against the full run, for the BART scenes: `tracer render
# --high-size 4k` then `cachesim run --size 4k,8k,16k --scheme single,split`,
# at --sample-rows 1/8 and in full; wall and CPU (user + sys) of the two
# commands together, medians of alternating runs; goal: the sampled run at
# most 0.25 of the full run's CPU (the fixed costs, scene loading and the
# tree build, are what keeps it above 1/8). The sampled run loads its tree
# from a warm tree cache (--tree-cache, as a study's repeated renders do);
# the full run builds it.
sampled_run() {
  local cachesim="$build_dir/bin/cachesim" bart scene kind run
  echo "row-sampled run (1/8) against the full run, ${width}x${height}, medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
  printf '%-12s %9s %9s %12s %12s %10s %9s\n' scene full_wall full_cpu sampled_wall sampled_cpu wall_ratio cpu_ratio
  for bart in robots/Robot.aff kitchen/kitchen.aff; do
    scene="$shared/$bart"
    [ -f "$scene" ] || continue
    : > "$work/full.all"
    : > "$work/sampled.all"
    # Warms the tree cache (not timed).
    "$tracer" render "$scene" --width 16 --height 12 --tree-cache "$work/tree-cache" -q --discard-records \
      >/dev/null 2>/dev/null
    for ((run = 0; run < runs; run++)); do
      for kind in full sampled; do
        local sample_args=()
        [ "$kind" = sampled ] && sample_args=(--sample-rows 1/8 --tree-cache "$work/tree-cache")
        /usr/bin/time -f '%e %U %S' -o "$work/render.t" "$tracer" render "$scene" --width "$width" --height "$height" \
          --max-depth "$max_depth" --high-size 4k "${sample_args[@]}" "${thread_args[@]}" -q -o "$work/sampled.din.zst" \
          >/dev/null 2>/dev/null
        /usr/bin/time -f '%e %U %S' -o "$work/simulate.t" "$cachesim" run "$work/sampled.din.zst" --size 4k,8k,16k \
          --scheme single,split >/dev/null
        cat "$work/render.t" "$work/simulate.t" | awk '{w += $1; c += $2 + $3} END {print w, c}' >> "$work/$kind.all"
      done
    done
    awk -v n="$(basename "$scene")" \
        -v fw="$(awk '{print $1}' "$work/full.all" | median)" -v fc="$(awk '{print $2}' "$work/full.all" | median)" \
        -v sw="$(awk '{print $1}' "$work/sampled.all" | median)" -v sc="$(awk '{print $2}' "$work/sampled.all" | median)" \
        'BEGIN { printf "%-12s %9.2f %9.2f %12.2f %12.2f %10.3f %9.3f\n", n, fw, fc, sw, sc, sw / fw, sc / fc }'
  done
  echo "ratios sampled / full (target: cpu_ratio <= 0.25)"
}

# A path-traced frame of each BART scene (--integrator path --spp 4, default
# bounces) writing its trace against the same render with
# --discard-records (every record made, none written): wall and CPU (user +
# sys) of the whole command, medians of alternating runs; target: at most
# 2.0x the CPU. Then the rays per CPU second (rays of every kind over the
# --discard-records run's user + sys, scene loading and the tree build
# included: a rate per core that a busy machine does not change), the
# rays of each kind, and the render summary's own rays/s per core.
path_tracing() {
  echo "path tracing, ${width}x${height} --spp 4, medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
  printf '%-12s %10s %9s %11s %10s %10s %9s %12s\n' scene discard_wall discard_cpu traced_wall traced_cpu wall_ratio cpu_ratio Mrays_cpu_s
  local bart scene kind run
  for bart in robots/Robot.aff kitchen/kitchen.aff; do
    scene="$shared/$bart"
    [ -f "$scene" ] || continue
    : > "$work/discard.all"
    : > "$work/traced.all"
    for ((run = 0; run < runs; run++)); do
      for kind in discard traced; do
        local out_args=(--discard-records)
        [ "$kind" = traced ] && out_args=(-o "$work/path.din.zst")
        /usr/bin/time -f '%e %U %S' -o "$work/t" "$tracer" render "$scene" --width "$width" --height "$height" \
          --integrator path --spp 4 "${thread_args[@]}" "${out_args[@]}" 2> "$work/$kind.txt"
        echo "$(cat "$work/t") $(sed -n 's/^  rays: .*; total \([0-9]*\)$/\1/p' "$work/$kind.txt")" \
          >> "$work/$kind.all"
      done
    done
    awk -v n="$(basename "$scene")" \
        -v dw="$(column 1 < "$work/discard.all" | median)" -v dc="$(awk '{print $2 + $3}' "$work/discard.all" | median)" \
        -v tw="$(column 1 < "$work/traced.all" | median)" -v tc="$(awk '{print $2 + $3}' "$work/traced.all" | median)" \
        -v rays="$(column 4 < "$work/discard.all" | median)" 'BEGIN {
      printf "%-12s %10.2f %9.2f %11.2f %10.2f %10.2f %9.2f %12.3f\n", n, dw, dc, tw, tc, tw / dw, tc / dc, rays / dc / 1e6 }'
    sed -n 's/^  rays: /  rays of each kind: /p' "$work/discard.txt"
    # The render's own rays/s per core (its summary: each kind's traversal, and
    # all rays over the rendering threads' CPU), from the last --discard-records run.
    sed -n 's/^  rays\/s per core, /  the render'"'"'s rays\/s per core, /p' "$work/discard.txt"
  done
  echo "discard: --discard-records; traced: -o T.din.zst; cpu = user + sys; ratios traced / discard (target: cpu_ratio"
  echo "<= 2.0); Mrays_cpu_s: millions of rays of every kind per CPU second of the --discard-records run"
}

if [ "$path_only" = 1 ]; then
  path_tracing
  exit 0
fi
if [ "$in_flight_only" = 1 ]; then
  rays_in_flight
  exit 0
fi
if [ "$sampled_only" = 1 ]; then
  sampled_run
  exit 0
fi

load="$(cut -d' ' -f1 /proc/loadavg)"
echo "bench-tracer: ${width}x${height}, max depth $max_depth, $runs run(s) each, $(nproc) cores, load average $load"
awk -v load="$load" -v cores="$(nproc)" 'BEGIN { if (load + 0 > cores * 0.5) print "bench-tracer: the machine is busy (load " load " on " cores " cores): absolute figures are low; the ratios are measured under the same load" }'
printf '%-14s %9s %8s %11s %10s %9s %11s %9s %7s %10s %9s\n' scene triangles build_s rays render_s Mrays_s recorded_s traced_s ratio B/record vs_zstd3
for scene in $scenes; do
  name="$(basename "$scene")"
  plain=() recorded=() traced=()
  for ((run = 0; run < runs; run++)); do
    "$tracer" render "$scene" --width "$width" --height "$height" --max-depth "$max_depth" \
      "${thread_args[@]}" 2> "$work/plain.txt"
    plain+=("$(render_seconds "$work/plain.txt")")
    "$tracer" render "$scene" --width "$width" --height "$height" --max-depth "$max_depth" \
      "${thread_args[@]}" --discard-records 2> "$work/recorded.txt"
    recorded+=("$(render_seconds "$work/recorded.txt")")
    "$tracer" render "$scene" --width "$width" --height "$height" --max-depth "$max_depth" \
      "${thread_args[@]}" -o "$work/trace.din.zst" 2> "$work/traced.txt"
    traced+=("$(render_seconds "$work/traced.txt")")
  done
  render_s="$(printf '%s\n' "${plain[@]}" | median)"
  traced_s="$(printf '%s\n' "${traced[@]}" | median)"
  recorded_s="$(printf '%s\n' "${recorded[@]}" | median)"
  triangles="$(sed -n 's/^  kd-tree: \([0-9]*\) triangles.*/\1/p' "$work/plain.txt")"
  build_s="$(sed -n 's/.*built in \([0-9.]*\) s.*/\1/p' "$work/plain.txt")"
  rays="$(sed -n 's/^  rays: .*; total \([0-9]*\)$/\1/p' "$work/plain.txt")"
  records="$(sed -n 's/^  render: .*; \([0-9]*\) records$/\1/p' "$work/traced.txt")"
  bytes="$(stat -c %s "$work/trace.din.zst")"
  zstd3_bytes="$(zstd -dc "$work/trace.din.zst" | zstd -3 -T1 -q -c | wc -c)"
  awk -v n="$name" -v t="$triangles" -v b="$build_s" -v r="$rays" -v p="$render_s" -v q="$traced_s" \
      -v m="$recorded_s" -v rec="$records" -v by="$bytes" -v z3="$zstd3_bytes" 'BEGIN {
    printf "%-14s %9d %8.2f %11d %10.3f %9.3f %11.3f %9.3f %7.2f %10.3f %9.4f\n", n, t, b, r, p, r / p / 1e6, m, q, q / p, by / rec, by / z3 }'
done
echo "render_s: rendering only; recorded_s: also making every record (then discarded); traced_s: also writing"
echo "the trace; ratio = traced_s / render_s (target <= 2.0), render-loop seconds; B/record = compressed"
echo "din bytes per record (tracer's default zstd level, 3); vs_zstd3 = trace bytes / \`zstd -3\` of its text (target <= 1)"

# The kd-tree build (wall and CPU, `tracer info`'s build_seconds and
# build_cpu_seconds) on one thread and on every core, for the forest built-in
# at size 5 (about 250K triangles) and the BART scenes; goal: Kitchen at most
# 0.35 s wall on 2 cores.
build_figure() {  # SCENE THREADS KEY: the median of $runs builds
  for ((run = 0; run < runs; run++)); do
    "$tracer" info "$1" --threads "$2" --format json 2>/dev/null | sed -n "s/.*\"$3\": \([0-9.e+-]*\),*/\1/p"
  done | median
}
cores="$(nproc)"
printf '%-14s %9s %12s %11s %12s %11s %8s\n' scene triangles wall_1thread cpu_1thread "wall_${cores}threads" \
  "cpu_${cores}threads" speedup
build_scenes="forest:5"
for bart in robots/Robot.aff kitchen/kitchen.aff; do [ -f "$shared/$bart" ] && build_scenes="$build_scenes $shared/$bart"; done
for scene in $build_scenes; do
  triangles="$("$tracer" info "$scene" --format json 2>/dev/null | sed -n 's/^    "triangles": \([0-9]*\),*/\1/p')"
  wall1="$(build_figure "$scene" 1 build_seconds)" cpu1="$(build_figure "$scene" 1 build_cpu_seconds)"
  walln="$(build_figure "$scene" "$cores" build_seconds)" cpun="$(build_figure "$scene" "$cores" build_cpu_seconds)"
  awk -v n="$(basename "$scene")" -v t="$triangles" -v a="$wall1" -v b="$cpu1" -v c="$walln" -v d="$cpun" \
    'BEGIN { printf "%-14s %9d %12.3f %11.3f %12.3f %11.3f %8.2f\n", n, t, a, b, c, d, a / c }'
done
echo "kd-tree build: medians of $runs run(s); speedup = wall on 1 thread / wall on $cores (load: $(cut -d' ' -f1-3 /proc/loadavg))"

# The binary BVH against the kd-tree on the BART scenes: build wall time
# (goal: at most 0.3 s for Kitchen's BVH on 2 cores) and rays per second of
# the render loop over the same rays (nothing recorded), with wall and CPU
# (user + sys) of the whole command; the two structures' runs alternate.
for bart in robots/Robot.aff kitchen/kitchen.aff; do
  [ -f "$shared/$bart" ] || continue
  [ -z "${bvh_header:-}" ] && bvh_header=1 && {
    echo "bvh2 against kdtree, ${width}x${height}, max depth $max_depth, medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
    printf '%-12s %-7s %11s %8s %10s %9s %9s %9s\n' scene accel rays build_s render_s Mrays_s wall_s cpu_s
  }
  for accel in kdtree bvh2; do : > "$work/$accel.all"; done
  for ((run = 0; run < runs; run++)); do
    for accel in kdtree bvh2; do
      /usr/bin/time -f '%e %U %S' -o "$work/t" "$tracer" render "$shared/$bart" --accel "$accel" --width "$width" \
        --height "$height" --max-depth "$max_depth" "${thread_args[@]}" 2> "$work/s.txt"
      echo "$(sed -n 's/.*built in \([0-9.]*\) s.*/\1/p' "$work/s.txt") $(render_seconds "$work/s.txt")" \
        "$(sed -n 's/^  rays: .*; total \([0-9]*\)$/\1/p' "$work/s.txt") $(cat "$work/t")" >> "$work/$accel.all"
    done
  done
  for accel in kdtree bvh2; do
    b="$(column 1 < "$work/$accel.all" | median)"
    r="$(column 2 < "$work/$accel.all" | median)"
    n="$(column 3 < "$work/$accel.all" | median)"
    w="$(column 4 < "$work/$accel.all" | median)"
    c="$(awk '{print $5 + $6}' "$work/$accel.all" | median)"
    awk -v s="$(basename "$bart")" -v a="$accel" -v n="$n" -v b="$b" -v r="$r" -v w="$w" -v c="$c" 'BEGIN {
      printf "%-12s %-7s %11d %8.3f %10.3f %9.3f %9.2f %9.2f\n", s, a, n, b, r, n / r / 1e6, w, c }'
  done
done
[ -n "${bvh_header:-}" ] && echo "build_s: the structure's build (wall); render_s: the render loop; goal: bvh2 Mrays_s >= kdtree's"

# The whole command on the BART scenes: what a user waits for and pays.
# /usr/bin/time gives wall, user, sys and peak RSS of each run.
timed_render() {  # OUT_FILE tracer-args...
  local out="$1"; shift
  /usr/bin/time -f '%e %U %S %M' -o "$out" "$tracer" render "$@" -q >/dev/null 2>/dev/null
}
bart_found=0
for bart in robots/Robot.aff kitchen/kitchen.aff; do
  [ -f "$shared/$bart" ] && bart_found=1
done
if [ "$bart_found" = 0 ]; then
  echo "bench-tracer: whole command: no BART scene under $shared: skipped"
  exit 0
fi
echo "whole command, ${width}x${height} --high-size 4k, medians of $runs alternating run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
printf '%-12s %12s %11s %12s %11s %10s %9s %10s %11s\n' scene render_wall render_cpu traced_wall traced_cpu wall_ratio cpu_ratio render_MiB traced_MiB
for bart in robots/Robot.aff kitchen/kitchen.aff; do
  scene="$shared/$bart"
  if [ ! -f "$scene" ]; then
    echo "bench-tracer: $scene absent: skipped" >&2
    continue
  fi
  : > "$work/plain.all"; : > "$work/traced.all"
  for ((run = 0; run < runs; run++)); do
    timed_render "$work/t" "$scene" --width "$width" --height "$height" --max-depth "$max_depth" --high-size 4k \
      "${thread_args[@]}"
    cat "$work/t" >> "$work/plain.all"
    timed_render "$work/t" "$scene" --width "$width" --height "$height" --max-depth "$max_depth" --high-size 4k \
      "${thread_args[@]}" -o "$work/whole.din.zst"
    cat "$work/t" >> "$work/traced.all"
  done
  pw="$(column 1 < "$work/plain.all" | median)"
  pc="$(awk '{print $2 + $3}' "$work/plain.all" | median)"
  pm="$(column 4 < "$work/plain.all" | median)"
  tw="$(column 1 < "$work/traced.all" | median)"
  tc="$(awk '{print $2 + $3}' "$work/traced.all" | median)"
  tm="$(column 4 < "$work/traced.all" | median)"
  awk -v n="$(basename "$scene")" -v pw="$pw" -v pc="$pc" -v tw="$tw" -v tc="$tc" -v pm="$pm" -v tm="$tm" 'BEGIN {
    printf "%-12s %12.2f %11.2f %12.2f %11.2f %10.2f %9.2f %10.0f %11.0f\n", n, pw, pc, tw, tc, tw / pw, tc / pc, pm / 1024, tm / 1024 }'
done
echo "render: tracer render without -o (nothing recorded); traced: with -o T.din.zst; cpu = user + sys;"
echo "ratios traced / render (target <= 2.0 in wall and CPU time)"

rays_in_flight
sampled_run
path_tracing

# Primary rays against Embree's rtcIntersect1 (a benchmark-only reference,
# where libembree-dev is installed): the same rays and triangles, one thread
# each, nothing recorded.
if ! dpkg-query -W -f='${Status}' libembree-dev 2>/dev/null | grep -q "install ok installed"; then
  echo "bench-tracer: Embree reference: libembree-dev is not installed (apt-get install libembree-dev): skipped"
  exit 0
fi
cmake -S . -B "$build_dir" >/dev/null
cmake --build "$build_dir" --target primary_rays_bench >/dev/null
echo "primary rays, ${width}x${height}, kd-tree traversal against Embree, one thread each, medians of $runs run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
for bart in robots/Robot.aff kitchen/kitchen.aff; do
  [ -f "$shared/$bart" ] || continue
  "$build_dir/bin/primary_rays_bench" "$shared/$bart" --width "$width" --height "$height" --runs "$runs"
done
echo "ratio = kd-tree rays/s / Embree rays/s (target >= 0.6); same_first_hit: rays whose first hit is the same triangle"
# A path tracer's rays (--integrator path --spp 1), kind by kind: rays/s per
# core of each ray kind through our kd-tree, and against Embree (target for
# the bounce rays: ratio >= 0.5).
echo "a path tracer's rays (1 spp), ${width}x${height}, by kind, one thread each, medians of $runs run(s); load average $(cut -d' ' -f1 /proc/loadavg)"
for bart in robots/Robot.aff kitchen/kitchen.aff; do
  [ -f "$shared/$bart" ] || continue
  "$build_dir/bin/primary_rays_bench" "$shared/$bart" --width "$width" --height "$height" --runs "$runs" --path 1
done
echo "shadow rays are any-hit queries (rtcOccluded1), the others closest-hit; kdtree_rays_per_s: rays/s per core of each kind"

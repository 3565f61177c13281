#!/usr/bin/env bash
# The path tracer's goals on the Cornell box against Blender Cycles (issue
# 49), with figures, ratios and medians of --runs runs: Sobol against
# independent sampling at 16 spp (goal: RMSE at most 0.6x); our RMSE at equal
# single-thread CPU time against Cycles' (goal: at most 1.2x); the CPU of
# writing the trace against --discard-records (goal: at most 2.0x). Installs
# Debian's blender if missing; needs a build (scripts/setup.sh).
#   scripts/bench-cycles.sh [--build-dir build] [--out out/bench-cycles] [--runs 3] [--realizations 6]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build out=out/bench-cycles runs=3 realizations=6
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --realizations) realizations="$2"; shift 2 ;;
    -h|--help) sed -n '2,8s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "bench-cycles.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ ! -x "$build_dir/bin/tracer" ]; then
  echo "bench-cycles.sh: $build_dir/bin/tracer not found: build first (scripts/setup.sh)" >&2
  exit 2
fi
scripts/install-packages.sh blender
exec /usr/bin/python3 scripts/cycles/bench_cycles.py --build-dir "$build_dir" --out "$out" --runs "$runs" --realizations "$realizations"

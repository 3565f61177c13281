#!/usr/bin/env bash
# Numerical stability at scale (issue 9): runs every case of
# tests/tracer/stability_cases.hpp in its own process (build/tests/stability_table)
# and prints one table: case, triangles, kd-tree build wall and CPU
# (user+sys) seconds, peak memory of the process, rays cast, self-hits,
# escapes from closed meshes, watertight misses on shared edges and vertices,
# NaNs, and build time and memory against the 3-D soup of the same size
# (measured in the same run). Exit 1 when any count that must be zero is not.
#   scripts/stability.sh [--build-dir build] [--triangles 100000] [--pixels 64] [--cases "a b"]
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build triangles=100000 pixels=64 cases=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --triangles) triangles="$2"; shift 2 ;;
    --pixels) pixels="$2"; shift 2 ;;
    --cases) cases="$2"; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "stability.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
table="$build_dir/tests/stability_table"
[ -x "$table" ] || { echo "stability.sh: $table not found; build first (scripts/setup.sh)" >&2; exit 2; }
[ -n "$cases" ] || cases="$("$table" --list | grep -v '^soup-3d$' | tr '\n' ' ')"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
load="$(cut -d' ' -f1 /proc/loadavg)"
echo "stability: $triangles triangles for the sized cases, ${pixels} pixels wide, $(nproc) cores, load average $load"
echo "command: scripts/stability.sh --triangles $triangles --pixels $pixels"

status=0
"$table" soup-3d "$triangles" "$pixels" > "$work/rows.csv" || status=1
for name in $cases; do
  "$table" "$name" "$triangles" "$pixels" >> "$work/rows.csv" || status=1
done
awk -F, 'NR == 1 { soup_s = $3; soup_mb = $5 }
  { rows[NR] = $0 }
  END {
    printf "%-20s %9s %8s %8s %8s %10s %9s %7s %10s %5s %9s %8s\n", "case", "triangles", "build_s", "cpu_s",
           "peak_MB", "rays", "self_hits", "escapes", "wt_misses", "NaNs", "s/soup", "MB/soup"
    for (i = 1; i <= NR; ++i) {
      split(rows[i], f, ",")
      printf "%-20s %9d %8.3f %8.3f %8.1f %10d %9d %7d %10d %5d %9.2f %8.2f\n", f[1], f[2], f[3], f[4], f[5],
             f[6], f[7], f[8], f[9], f[10], (soup_s > 0 ? f[3] / soup_s : 0), (soup_mb > 0 ? f[5] / soup_mb : 0)
    }
  }' "$work/rows.csv"
[ "$status" = 0 ] || echo "stability: some case counted a self-hit, escape, watertight miss or NaN" >&2
exit "$status"

#!/usr/bin/env bash
# Blender Cycles as the image oracle of the path tracer: each scene of
# scripts/cycles/scenes.py (a Lambertian sphere under a white sky, the Cornell
# box lit by its emissive quad, a mirror, a dielectric, an environment map,
# GGX lobes) rendered by `tracer render --integrator path` and by Cycles
# (Debian's blender, headless, installed if missing), every 8x8-pixel block's
# mean held within 3 standard errors (docs/guide/testing.md). Prints a table
# per scene; exits 1 on a disagreement. Needs a build (scripts/setup.sh).
# Blender's output goes to the logs under --out.
#   scripts/test-cycles.sh [--build-dir build] [--out out/test-cycles] [--threads 2] [--scenes sphere,cornell]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build out=out/test-cycles threads=2 scenes=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    -h|--help) sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "test-cycles.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ ! -x "$build_dir/bin/tracer" ]; then
  echo "test-cycles.sh: $build_dir/bin/tracer not found: build first (scripts/setup.sh)" >&2
  exit 2
fi
scripts/install-packages.sh blender
started=$SECONDS
/usr/bin/python3 scripts/cycles/test_cycles.py --build-dir "$build_dir" --out "$out" --threads "$threads" \
  ${scenes:+--scenes "$scenes"}
echo "test-cycles.sh: $((SECONDS - started)) s" >&2

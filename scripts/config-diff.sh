#!/usr/bin/env bash
# The differential test of `cachesim run` over every path, at any scale: N
# random cases (seeds S, S+1, ...), each a trace and a configuration list;
# every row must equal its configuration run alone, the reference model
# (tests/reference) and, where it can say, Dinero IV; OPT, LRU-inclusion,
# table-sum and sampling properties hold (tests/differential/config_cases.hpp).
# Every differing case is kept (trace, arguments, every run's output) in DIR/seed-S/.
# And R render checks: `tracer render --simulate LIST --report` against
# `cachesim run LIST` on the trace it writes.
#   scripts/config-diff.sh [--cases N] [--seed S] [--renders R] [--keep DIR] [--jobs J] [--avoid LETTERS]
#                          [--build-dir B] [--python N]
# Defaults: 1000 cases and 10 renders from seed 1, kept in out/config-diff, 2
# jobs. --avoid leaves out the triggers of open defects (letters in config_cases.hpp).
# --python N: every Nth case's list also through nodetrace.simulate() (the Python module, built in B/python).
# Builds Dinero IV (scripts/build-dinero.sh) and the programs it needs. Exit 1 on any difference.
set -euo pipefail
cd "$(dirname "$0")/.."

cases=1000
seed=1
renders=10
keep=out/config-diff
jobs=2
avoid=
build_dir=build
python_every=
while [ $# -gt 0 ]; do
  case "$1" in
    --cases) cases="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --renders) renders="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --avoid) avoid="$2"; shift 2 ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    --python) python_every="$2"; shift 2 ;;
    -h|--help) sed -n '2,15s/^# \{0,1\}//p' scripts/config-diff.sh; exit 0 ;;
    *) echo "config-diff.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

dinero=$(scripts/build-dinero.sh)
targets=(cachesim tracer config_diff)
python=()
if [ -n "$python_every" ]; then
  targets+=(nodetrace_python)
  python=(--python "$build_dir/python" --python-every "$python_every")
fi
cmake --build "$build_dir" -j "$(nproc)" --target "${targets[@]}" >/dev/null
"$build_dir/tests/config_diff" --dinero "$dinero" --cachesim "$build_dir/bin/cachesim" \
  --tracer "$build_dir/bin/tracer" --cases "$cases" --renders "$renders" --seed "$seed" --keep "$keep" \
  --jobs "$jobs" --avoid "$avoid" "${python[@]}"

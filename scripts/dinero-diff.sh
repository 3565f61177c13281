#!/usr/bin/env bash
# The differential test against the real Dinero IV at any scale: N random
# valid cases (seeds S, S+1, ...) compared byte for byte between dineroIV and
# `cachesim dinero`; every differing case is kept (trace, arguments, both
# outputs and exit statuses) in DIR/seed-NNN/.
#   scripts/dinero-diff.sh [--cases N] [--seed S] [--keep DIR] [--build-dir B]
# Defaults: 1000 cases from seed 1, kept in out/dinero-diff. Builds Dinero IV
# (scripts/build-dinero.sh) and the programs it needs. Exit 1 on any difference.
set -euo pipefail
cd "$(dirname "$0")/.."

cases=1000
seed=1
keep=out/dinero-diff
build_dir=build
while [ $# -gt 0 ]; do
  case "$1" in
    --cases) cases="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    -h|--help) sed -n '2,8s/^# \{0,1\}//p' scripts/dinero-diff.sh; exit 0 ;;
    *) echo "dinero-diff.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

dinero=$(scripts/build-dinero.sh)
cmake --build "$build_dir" -j "$(nproc)" --target cachesim dinero_diff >/dev/null
"$build_dir/tests/dinero_diff" --dinero "$dinero" --cachesim "$build_dir/bin/cachesim" \
  --cases "$cases" --seed "$seed" --keep "$keep"

#!/usr/bin/env bash
# The experiment Makefile's renderer: everything of a group (one scene, one
# set of render options, several layouts) that is not on disk yet, made by
# one `tracer render` (the layouts cost a relocation of the records each, not a
# render). A member is a trace, FILE=LAYOUT, or a simulation of a trace not
# kept, CSV=LAYOUT=OPTIONS: cachesim run's OPTIONS (spaces written as ^) run
# inside the render (--simulate), its CSV report written to CSV, its
# --per-level table to CSV.levels.csv, and the trace's header and totals to
# CSV.trace.json (--trace-info). A lock makes concurrent calls for the same
# group (make -j) wait, so the second finds its files written and renders
# nothing.
#   render-layouts.sh LOCK TRACER SCENE [RENDER-OPTIONS...] -- MEMBER...
# LAYOUT is a name tracer render gives {layout}: dfl, bfl, veb, treelet,
# hybrid-kK or hybrid-SIZE. The traces of a group share their suffix
# (.din.zst, .xdin.zst). Each file is written under a temporary name and renamed.
# --help: this comment, before anything else runs.
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then sed -n '2,16s/^# \{0,1\}//p' "$0"; exit 0; fi
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: render-layouts.sh LOCK TRACER SCENE [RENDER-OPTIONS...] -- MEMBER..." >&2
  exit 2
fi
lock=$1 tracer=$2
shift 2
options=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do options+=("$1"); shift; done
[ $# -gt 0 ] && shift

exec 9>"$lock"
flock 9
tmp=$(mktemp -d "$lock.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

layouts=() split_levels=() high_sizes=()
add_once() {  # VALUE ARRAY: VALUE appended to ARRAY unless it holds it
  local -n array=$2
  local v
  for v in "${array[@]}"; do [ "$v" = "$1" ] && return; done
  array+=("$1")
}
add_layout() {  # NAME: its layout in --layout, --split-level or --high-size, once
  case "$1" in
    dfl|bfl|veb|treelet) add_once "$1" layouts ;;
    hybrid-k*) add_once hybrid layouts; add_once "${1#hybrid-k}" split_levels ;;
    hybrid-*) add_once hybrid layouts; add_once "${1#hybrid-}" high_sizes ;;
    *) return 1 ;;
  esac
}
traces=() trace_names=() runs=() run_names=() simulations=()
IFS=^
for member in "$@"; do
  file=${member%%=*} rest=${member#*=}
  [ -f "$file" ] && continue
  name=${rest%%=*}
  add_layout "$name" || { echo "render-layouts.sh: unknown layout name '$name' (of $file)" >&2; exit 2; }
  if [ "$rest" = "$name" ]; then
    traces+=("$file") trace_names+=("$name")
    continue
  fi
  run=${#runs[@]}
  sim=""
  for word in ${rest#*=}; do  # split at ^ (IFS below): the options' words
    [ "$word" = --per-level ] && word="--per-level $tmp/$run.levels.csv"
    sim+=" $word"
  done
  runs+=("$file") run_names+=("$name")
  simulations+=(--simulate "$name=${sim# } --format csv" --report "$tmp/$run.csv")
done
IFS=$' \t\n'
[ ${#traces[@]} -eq 0 ] && [ ${#runs[@]} -eq 0 ] && exit 0

join() { local IFS=,; echo "$*"; }
args=(--layout "$(join "${layouts[@]}")")
[ ${#split_levels[@]} -gt 0 ] && args+=(--split-level "$(join "${split_levels[@]}")")
[ ${#high_sizes[@]} -gt 0 ] && args+=(--high-size "$(join "${high_sizes[@]}")")
if [ ${#traces[@]} -gt 0 ]; then
  base=${traces[0]##*/}
  args+=(-o "$tmp/{layout}.${base#*.}")
fi
[ ${#runs[@]} -gt 0 ] && args+=("${simulations[@]}" --trace-info "$tmp/{layout}.json")
"$tracer" render "${options[@]}" "${args[@]}"
for i in "${!traces[@]}"; do mv "$tmp/${trace_names[$i]}.${base#*.}" "${traces[$i]}"; done
# A group's runs may belong to several studies, whose folders the leader's
# recipe did not make.
for i in "${!runs[@]}"; do
  file=${runs[$i]}
  mkdir -p "$(dirname "$file")"
  [ -f "$tmp/$i.levels.csv" ] && mv "$tmp/$i.levels.csv" "$file.levels.csv"
  cp "$tmp/${run_names[$i]}.json" "$tmp/$i.trace.json" && mv "$tmp/$i.trace.json" "$file.trace.json"
  mv "$tmp/$i.csv" "$file"
done

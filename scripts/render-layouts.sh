#!/usr/bin/env bash
# The experiment Makefile's renderer: every trace of a group (one scene, one
# set of render options, several layouts) that is not on disk yet, written by
# one `tracer render` (the layouts cost a relocation of the records each, not a
# render). A lock makes concurrent calls for the same group (make -j) wait, so
# the second finds its trace written and renders nothing.
#   render-layouts.sh LOCK TRACER SCENE [RENDER-OPTIONS...] -- FILE=LAYOUT...
# LAYOUT is a name tracer render gives {layout}: dfl, bfl, veb, treelet,
# hybrid-kK or hybrid-SIZE. The traces of a group share their suffix
# (.din.zst, .xdin.zst). Each is written under a temporary name and renamed.
# --help: this comment, before anything else runs.
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0; fi
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: render-layouts.sh LOCK TRACER SCENE [RENDER-OPTIONS...] -- FILE=LAYOUT..." >&2
  exit 2
fi
lock=$1 tracer=$2
shift 2
options=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do options+=("$1"); shift; done
[ $# -gt 0 ] && shift

exec 9>"$lock"
flock 9

layouts=() split_levels=() high_sizes=() files=() names=()
add_layout() {
  local l
  for l in "${layouts[@]}"; do [ "$l" = "$1" ] && return; done
  layouts+=("$1")
}
for member in "$@"; do
  file=${member%=*} name=${member##*=}
  [ -f "$file" ] && continue
  case "$name" in
    dfl|bfl|veb|treelet) add_layout "$name" ;;
    hybrid-k*) add_layout hybrid; split_levels+=("${name#hybrid-k}") ;;
    hybrid-*) add_layout hybrid; high_sizes+=("${name#hybrid-}") ;;
    *) echo "render-layouts.sh: unknown layout name '$name' (of $file)" >&2; exit 2 ;;
  esac
  files+=("$file") names+=("$name")
done
[ ${#files[@]} -eq 0 ] && exit 0

join() { local IFS=,; echo "$*"; }
args=(--layout "$(join "${layouts[@]}")")
[ ${#split_levels[@]} -gt 0 ] && args+=(--split-level "$(join "${split_levels[@]}")")
[ ${#high_sizes[@]} -gt 0 ] && args+=(--high-size "$(join "${high_sizes[@]}")")
base=${files[0]##*/}
suffix=.${base#*.}
tmp=$(mktemp -d "$lock.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
"$tracer" render "${options[@]}" "${args[@]}" -o "$tmp/{layout}$suffix"
for i in "${!files[@]}"; do mv "$tmp/${names[$i]}$suffix" "${files[$i]}"; done

#!/usr/bin/env bash
# Speed of the trace formats (a benchmark, not a test): prints medians of
# several runs and ratios against zstd measured in the same run.
#
#   scripts/bench-formats.sh [--records N] [--runs R] [--build-dir DIR] [--archive-records M]
#
# 1. write: formats_bench generates N level-tagged node fetches into a din
#    container (records formatted, frames compressed on both cores at the
#    default level); target >= 30 M records/s, and a container no larger than
#    `zstd -3` of the same text. Reference: `zstd -3 -T2` of that text.
# 2. read: a full decode of that container into the record model (every
#    record parsed, checksums and hashes checked) against `zstd -dc FILE
#    >/dev/null`; target: no slower.
# 3. verify: `tracetool verify` of that container (every checksum, the index,
#    the record hash, every record parsed) against `zstd -t FILE`, wall and
#    CPU; target: at most 1.0 x in both.
# 4. archive: the archive setting's size, write time and reading speed on
#    M such records (default 2097152: level 17 is slow; section 4 below).
# Wall-clock figures depend on what else runs on the machine: the script
# prints the load average next to them, and CPU seconds (user+sys) too.
set -euo pipefail
cd "$(dirname "$0")/.."

records=50000000
runs=5
build_dir=build-bench
archive_records=2097152
while [ $# -gt 0 ]; do
  case "$1" in
    --records) records="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --build-dir) build_dir="$2"; shift 2 ;;
    --archive-records) archive_records="$2"; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    *) echo "bench-formats.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j2 --target formats_bench tracetool >/dev/null
bench="$build_dir/bin/formats_bench"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
trace="$work/bench.din.zst"

TIMEFORMAT='%R %U %S'
# Runs a command, appends "wall cpu" to the file $1.
timed() {
  local out="$1"; shift
  local times
  times=$( { time "$@" >/dev/null 2>&1; } 2>&1 )
  echo "$times" | awk '{ printf "%s %.3f\n", $1, $2 + $3 }' >>"$out"
}
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
column_median() { awk -v c="$2" '{ print $c }' "$1" | median; }

echo "formats benchmark: $records records, $runs runs, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"

: >"$work/write"
for _ in $(seq "$runs"); do
  rm -f "$trace"
  timed "$work/write" "$bench" generate "$records" "$trace"
done
container_bytes=$(stat -c %s "$trace")
zstd -dc "$trace" >"$work/text"
zstd3_bytes=$(zstd -3 -T1 -q -c "$work/text" | wc -c)
text_bytes=$(stat -c %s "$work/text")
# The reference for the write speed: zstd -3 on both cores compressing the
# same text from a file (no records to make or format).
: >"$work/zstd3"
for _ in $(seq "$runs"); do
  timed "$work/zstd3" zstd -3 -T2 -q -c "$work/text"
done
rm -f "$work/text"

: >"$work/read"
: >"$work/zstd"
for _ in $(seq "$runs"); do
  timed "$work/zstd" zstd -dc "$trace"
  timed "$work/read" "$bench" read "$trace"
done
: >"$work/verify"
: >"$work/zstdt"
for _ in $(seq "$runs"); do
  timed "$work/zstdt" zstd -tq "$trace"
  timed "$work/verify" "$build_dir/bin/tracetool" verify "$trace"
done
"$build_dir/bin/tracetool" verify "$trace" >/dev/null  # it must pass

write_wall=$(column_median "$work/write" 1)
read_wall=$(column_median "$work/read" 1)
zstd_wall=$(column_median "$work/zstd" 1)
awk -v n="$records" -v ww="$write_wall" -v wc="$(column_median "$work/write" 2)" \
    -v rw="$read_wall" -v rc="$(column_median "$work/read" 2)" \
    -v zw="$zstd_wall" -v zc="$(column_median "$work/zstd" 2)" \
    -v z3w="$(column_median "$work/zstd3" 1)" -v z3c="$(column_median "$work/zstd3" 2)" \
    -v cb="$container_bytes" -v zb="$zstd3_bytes" -v tb="$text_bytes" 'BEGIN {
  printf "write  (generate + format + compress, default level): median %.3f s wall, %.3f s cpu = %.1f M records/s (target >= 30)\n", ww, wc, n / ww / 1e6
  printf "zstd3  zstd -3 -T2 of the same text: median %.3f s wall, %.3f s cpu = %.1f M records/s; write wall / zstd wall = %.3f\n", z3w, z3c, n / z3w / 1e6, ww / z3w
  printf "size   container %d bytes vs zstd -3 of the same text %d bytes: ratio %.4f (target <= 1); text %d bytes, %.3f bytes/record\n", cb, zb, cb / zb, tb, cb / n
  printf "read   full decode: median %.3f s wall, %.3f s cpu = %.1f M records/s\n", rw, rc, n / rw / 1e6
  printf "zstd   zstd -dc >/dev/null: median %.3f s wall, %.3f s cpu = %.1f M records/s\n", zw, zc, n / zw / 1e6
  printf "ratio  read wall / zstd -dc wall = %.3f (target <= 1)\n", rw / zw
}'
awk -v vw="$(column_median "$work/verify" 1)" -v vc="$(column_median "$work/verify" 2)" \
    -v tw="$(column_median "$work/zstdt" 1)" -v tc="$(column_median "$work/zstdt" 2)" 'BEGIN {
  printf "verify tracetool verify: median %.3f s wall, %.3f s cpu\n", vw, vc
  printf "zstd   zstd -t: median %.3f s wall, %.3f s cpu\n", tw, tc
  printf "ratio  verify / zstd -t: wall %.3f, cpu %.3f (target <= 1 in both)\n", vw / tw, vc / tc
}'
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"

# 4. archive: `tracetool convert --archive` (level 17, 64 MiB window,
#    long-distance matching, 4194304 records per data frame; target on the
#    BART Kitchen trace: at most 0.16 bytes/record) of a container of M
#    records made as in 1, timed once (it is slow), and `cachesim run`
#    reading it against reading that default container: wall, CPU and peak
#    RSS, medians of the runs. These generated records (random descents)
#    compress far less than a tracer's: the bytes/record are not the target's.
cmake --build "$build_dir" -j2 --target cachesim >/dev/null
records="$archive_records"
trace="$work/archive-source.din.zst"
"$bench" generate "$records" "$trace" 2>/dev/null
container_bytes=$(stat -c %s "$trace")
archive="$work/archive.din.zst"
: >"$work/archive_write"
timed "$work/archive_write" "$build_dir/bin/tracetool" convert --archive "$trace" "$archive"
"$build_dir/bin/tracetool" verify "$archive" >/dev/null
zstd -dc "$archive" | cmp -s - <(zstd -dc "$trace") || { echo "bench-formats.sh: the archive's record text differs" >&2; exit 1; }
archive_bytes=$(stat -c %s "$archive")
# Wall, user + sys and peak RSS (KiB) of one cachesim run, appended to $1.
simulate() {
  /usr/bin/time -f '%e %U %S %M' -o "$work/one" "$build_dir/bin/cachesim" run "$2" --size 8k --scheme single >/dev/null
  awk '{ printf "%s %.3f %s\n", $1, $2 + $3, $4 }' "$work/one" >>"$1"
}
: >"$work/sim_archive"
: >"$work/sim_default"
for _ in $(seq "$runs"); do
  simulate "$work/sim_default" "$trace"
  simulate "$work/sim_archive" "$archive"
done
awk -v n="$records" -v ab="$archive_bytes" -v cb="$container_bytes" \
    -v aw="$(column_median "$work/archive_write" 1)" -v ac="$(column_median "$work/archive_write" 2)" \
    -v sw="$(column_median "$work/sim_archive" 1)" -v sc="$(column_median "$work/sim_archive" 2)" \
    -v sm="$(column_median "$work/sim_archive" 3)" \
    -v dw="$(column_median "$work/sim_default" 1)" -v dc="$(column_median "$work/sim_default" 2)" \
    -v dm="$(column_median "$work/sim_default" 3)" 'BEGIN {
  printf "archive  %d records\n", n
  printf "archive  convert --archive: %.3f s wall, %.3f s cpu (one run); %d bytes = %.4f bytes/record (default container %.4f)\n", aw, ac, ab, ab / n, cb / n
  printf "archive  cachesim run --size 8k --scheme single on it: median %.3f s wall, %.3f s cpu, %.0f MiB peak RSS\n", sw, sc, sm / 1024
  printf "archive  the same on the default container: median %.3f s wall, %.3f s cpu, %.0f MiB peak RSS; cpu ratio archive / default %.3f\n", dw, dc, dm / 1024, sc / dc
}'
echo "load average at the end of the archive section: $(cut -d' ' -f1-3 /proc/loadavg)"

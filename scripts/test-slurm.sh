#!/usr/bin/env bash
# The experiments on a real (one-node) Slurm cluster: installs Debian's
# slurm-wlm and munge when missing, starts munged, slurmctld and slurmd on
# localhost from a generated key and slurm.conf in a temporary folder, runs
# table1 at 64x48 for one scene through `srun` (RUN=...), and checks that its
# CSV and table are byte-identical to the same target run without Slurm.
# Stops the daemons it started, by their process ids. Run as root (CI).
#   scripts/test-slurm.sh [--build-dir DIR]
# Exit: 0 pass, 1 mismatch or failure; skips (exit 0, saying why) only when
# slurmd cannot run here, quoting its error.
# --help: this comment, before anything else runs.
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then sed -n '2,10s/^# \{0,1\}//p' "$0"; exit 0; fi
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    *) echo "test-slurm.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$build_dir/bin/tracer" ] || { echo "test-slurm.sh: $build_dir/bin/tracer not found: build first (scripts/setup.sh)" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "test-slurm.sh: the daemons are started as root; run as root" >&2; exit 1; }

missing=()
for package in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "test-slurm.sh: installing ${missing[*]}" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

work=$(mktemp -d /tmp/nodetrace-slurm.XXXXXX)
chmod 755 "$work"  # munged wants every folder above its socket searchable
pids=()
stop_daemons() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  rm -rf "$work"
}
trap stop_daemons EXIT
show_logs() {
  for log in "$work"/*.log; do echo "--- $log" >&2; tail -n 20 "$log" >&2; done
}

# munge: a generated key and a socket of our own, in the foreground (its pid is ours).
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge.key"
mkdir -m 755 "$work/munge"
munged --foreground --force --key-file="$work/munge.key" --socket="$work/munge/munge.socket" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/seed" \
  > "$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$work/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$work/munge/munge.socket" ] || { echo "test-slurm.sh: munged did not start" >&2; show_logs; exit 1; }

# Ports of our own, so another cluster on this machine is left alone.
port=$((20000 + RANDOM % 20000))
host=$(hostname -s)
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" <<EOF
ClusterName=nodetrace-ci
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=ci Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"

slurmctld -D -i -f "$SLURM_CONF" > "$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" > "$work/slurmd.out" 2>&1 &
slurmd_pid=$!
pids+=($slurmd_pid)

ready=""
for _ in $(seq 60); do
  if ! kill -0 "$slurmd_pid" 2>/dev/null; then
    echo "test-slurm.sh: SKIP: slurmd cannot run here: $(tail -n 3 "$work/slurmd.out" "$work/slurmd.log" 2>/dev/null | tr '\n' ' ')" >&2
    exit 0
  fi
  state=$(sinfo -h -o %T 2>/dev/null || true)
  if [ "$state" = idle ]; then ready=yes; break; fi
  sleep 0.5
done
[ -n "$ready" ] || { echo "test-slurm.sh: the node did not become idle (state '$state')" >&2; show_logs; exit 1; }

experiment=(make --no-print-directory -f scripts/table1.mk table1 "BUILD=$build_dir" SCENES=robot WIDTH=64 HEIGHT=48)
echo "test-slurm.sh: table1 at 64x48 through srun" >&2
"${experiment[@]}" -j2 OUT="$work/slurm" RUN="srun --quiet --ntasks=1 --cpus-per-task=1" > "$work/slurm.txt" 2>&1 ||
  { cat "$work/slurm.txt" >&2; show_logs; exit 1; }
jobs=$(scontrol show jobs -o 2>/dev/null | grep -c "JobState=COMPLETED" || true)
echo "test-slurm.sh: the same locally" >&2
"${experiment[@]}" OUT="$work/local" > "$work/local.txt" 2>&1 || { cat "$work/local.txt" >&2; exit 1; }

# Each render (its simulations run inside it) and each simulation of a kept
# trace is one Slurm job: as many as make announced.
expected=$(grep -c -E '^(render|simulate) ' "$work/slurm.txt" || true)
if [ "$expected" -lt 1 ] || [ "$jobs" -lt "$expected" ]; then
  echo "test-slurm.sh: FAIL: expected $expected completed Slurm jobs (one per render or simulation), found $jobs" >&2
  show_logs; exit 1
fi
for file in table1/table1.csv table1/table1.md; do
  if ! cmp "$work/slurm/$file" "$work/local/$file"; then
    echo "test-slurm.sh: FAIL: $file differs between srun and a local run" >&2
    diff "$work/slurm/$file" "$work/local/$file" >&2 || true
    exit 1
  fi
done
echo "test-slurm.sh: OK: $jobs Slurm jobs; table1.csv and table1.md identical to a local run"

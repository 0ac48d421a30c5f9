#!/usr/bin/env bash
# Runs a small sweep through a real Slurm started here (a single-node cluster: munged, slurmctld
# and slurmd with a slurm.conf in a temporary directory), and checks that its merged table equals
# the same grid run locally. Exits 77 (CTest: skipped) with the reason where the daemons cannot
# start. Stops the daemons it started, by their pid files.
# Usage: slurm_sweep_test.sh SPLAM_BINARY [GRID.yaml]
# With a grid (e.g. experiments/splam.yaml), runs that grid both ways instead of the small one
# and compares the tables without their timing figures; prints both wall times. With
# SPLAM_SLURM_TEST_KEEP=DIR the two sweep directories are moved to DIR/local and DIR/cluster.
set -uo pipefail
splam=$(realpath "$1")
grid=${2:+$(realpath "$2")}
skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAILED: $*"; exit 1; }

for tool in munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" > /dev/null || skip "$tool not installed (scripts/setup.sh installs slurm-wlm and munge)"
done
[[ $(id -u) -eq 0 ]] || skip "starting munged and slurmd needs root"

tmp=$(mktemp -d /tmp/splam_slurm.XXXXXX)
started_munge=0
cleanup() {
  for pid_file in "$tmp/slurmd.pid" "$tmp/slurmctld.pid"; do
    [[ -f $pid_file ]] && kill "$(cat "$pid_file")" 2> /dev/null
  done
  if ((started_munge)) && [[ -f $tmp/munged.pid ]]; then kill "$(cat "$tmp/munged.pid")" 2> /dev/null; fi
  sleep 1
  if [[ -n ${SPLAM_SLURM_TEST_KEEP:-} ]]; then
    mkdir -p "$SPLAM_SLURM_TEST_KEEP"
    mv "$tmp/local" "$tmp/cluster" "$SPLAM_SLURM_TEST_KEEP/" 2> /dev/null
  fi
  rm -rf "$tmp"
}
trap cleanup EXIT

# munge: the key the Debian package made, or one made here; a daemon of our own if none runs.
if ! munge -n 2> /dev/null | unmunge > /dev/null 2>&1; then
  if [[ ! -f /etc/munge/munge.key ]]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    chmod 400 /etc/munge/munge.key
  fi
  mkdir -p /run/munge
  munged --force --pid-file="$tmp/munged.pid" --log-file="$tmp/munged.log" ||
    skip "munged does not start: $(tail -1 "$tmp/munged.log" 2> /dev/null)"
  started_munge=1
  sleep 1
  munge -n | unmunge > /dev/null 2>&1 || skip "munge does not authenticate"
fi

# A port pair nobody listens on.
port=$((20000 + RANDOM % 20000))
host=$(hostname -s)
mkdir -p "$tmp/state" "$tmp/spool"
cat > "$tmp/slurm.conf" << CONF
ClusterName=splamtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=splam Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$tmp/slurm.conf
slurmctld -f "$SLURM_CONF" || skip "slurmctld does not start: $(tail -3 "$tmp/slurmctld.log" 2> /dev/null)"
slurmd -f "$SLURM_CONF" || skip "slurmd does not start: $(tail -3 "$tmp/slurmd.log" 2> /dev/null)"
for _ in $(seq 60); do
  sinfo -h -o %t 2> /dev/null | grep -Eq '^(idle|mix|alloc)' && break
  sleep 0.5
done
sinfo -h -o %t | grep -Eq '^(idle|mix|alloc)' || skip "the node does not come up: $(sinfo 2>&1 | tail -2)"

cd "$tmp" || fail "no $tmp"
if [[ -z $grid ]]; then
  # The grid: two SLAM methods x two odometry noise scales x two route seeds on simulated logs.
  "$splam" simulate --world corridor --seed 1 --out sim1 > /dev/null || fail "simulate"
  "$splam" simulate --world corridor --seed 2 --out sim2 > /dev/null || fail "simulate"
  cat > grid.yaml << GRID
command: slam
options: {max-scans: 200}
axes:
  method: [ekf-lines, graph]
  odometry-noise: [1, 2]
  log: [sim1/log.clf, sim2/log.clf]
replicate: log
figures: [error.estimate.rmse_position_m, error.odometry.rmse_position_m, map.lines, scans]
GRID
  grid=$tmp/grid.yaml
fi
small=$([[ $grid == "$tmp/grid.yaml" ]] && echo 1 || echo 0)

start=$SECONDS
"$splam" sweep "$grid" --out local --jobs "$(nproc)" > local.out || fail "local sweep: $(tail -3 local.out)"
local_s=$((SECONDS - start))
start=$SECONDS
submitted=$("$splam" sweep "$grid" --out cluster --slurm --array-chunk 3) ||
  fail "submit: $submitted"
echo "$submitted"
job=$(grep -o 'submitted job [0-9]*' <<< "$submitted" | grep -o '[0-9]*$')
[[ -n $job ]] || fail "no job id in: $submitted"
while [[ -n $(squeue -h -j "$job" 2> /dev/null) ]]; do
  ((SECONDS - start > (small ? 120 : 7200))) && fail "job $job still queued or running after $((SECONDS - start)) s"
  sleep 0.5
done
slurm_s=$((SECONDS - start))
"$splam" sweep status cluster || fail "not every cell ran through Slurm: $(cat cluster/slurm/*.out)"
"$splam" sweep merge cluster > /dev/null || fail "merge"
total=$(grep -vc '^#' cluster/cells.tsv)
tasks=$(ls cluster/slurm/task-*.out | wc -l)
[[ $tasks -eq $(((total + 2) / 3)) ]] || fail "expected $(((total + 2) / 3)) array tasks ($total cells, 3 per task), got $tasks"
# Timings differ between runs; every other figure must be equal.
timing='(wall|ms_per|time_per|real_time|peak_memory|time_ms)'
diff <(grep -Ev "$timing" local/table.csv) <(grep -Ev "$timing" cluster/table.csv) ||
  fail "the merged tables differ"
[[ $(grep -Evc "$timing" cluster/table.csv) -gt 1 ]] || fail "an empty table"
if ((small)); then
  grep -q '^ekf-lines,1,error.estimate.rmse_position_m,2,' cluster/table.csv ||
    fail "no ekf-lines row over two logs in: $(head -3 cluster/table.csv)"
fi
echo "local sweep: $local_s s wall; through Slurm: $slurm_s s wall"
echo "PASSED: job $job ran $total cells in $tasks array tasks; the merged table equals the local one"

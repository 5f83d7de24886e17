#!/usr/bin/env bash
# compare --plan on a real one-node Slurm cluster: installs Debian's slurm-wlm and munge if missing,
# starts munged, slurmctld and slurmd from a minimal slurm.conf in a temporary folder, submits the
# plan with `sbatch --array`, waits, collects, and checks the tables against a local compare of the
# same plan (every column but the times, which differ from run to run). Stops its daemons at the end.
#
#   scripts/slurm_test.sh [build/eval/slamcmp]
#
# Exit 0 passed, 1 failed, 77 skipped (packages cannot be installed: not root and no sudo, or apt
# fails; ctest reports it as skipped).
set -euo pipefail
cd "$(dirname "$0")/.."
slamcmp=$(realpath "${1:-build/eval/slamcmp}")
[ -x "$slamcmp" ] || { echo "slurm_test: $slamcmp is not built" >&2; exit 1; }
start_time=$(date +%s)

skip() { echo "slurm_test: SKIPPED: $*" >&2; exit 77; }
need=()
for p in slurm-wlm munge; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    sudo -n true 2>/dev/null || skip "installing ${need[*]} needs root or password-less sudo"
    sudo="sudo -n"
  fi
  echo "slurm_test: installing ${need[*]}"
  # No daemon may start at install time (a container has no init; ours run from a temporary folder).
  policy=$(mktemp)
  if ! { $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" \
           > "$policy" 2>&1 || { $sudo apt-get update -qq > /dev/null 2>&1 &&
           $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" \
           > "$policy" 2>&1; }; }; then
    tail -n 5 "$policy" >&2
    rm -f "$policy"
    skip "apt-get cannot install ${need[*]}"
  fi
  rm -f "$policy"
fi
for tool in munged slurmctld slurmd sbatch sinfo; do
  command -v "$tool" > /dev/null || skip "$tool is missing after installing slurm-wlm and munge"
done
[ "$(id -u)" -eq 0 ] || skip "the test cluster's daemons run as root here; run as root (CI does)"

work=$(mktemp -d /tmp/slamcmp-slurm.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
  local status=$?
  # Our daemons only, by the pids they wrote.
  for f in "$work"/slurmd.pid "$work"/slurmctld.pid "$work"/munged.pid; do
    [ -s "$f" ] && kill "$(cat "$f")" 2> /dev/null || true
  done
  sleep 1
  for f in "$work"/slurmd.pid "$work"/slurmctld.pid "$work"/munged.pid; do
    [ -s "$f" ] && kill -9 "$(cat "$f")" 2> /dev/null || true
  done
  if [ $status -ne 0 ] && [ $status -ne 77 ]; then
    for log in "$work"/*.log; do echo "== $log" >&2; tail -n 15 "$log" >&2 || true; done
  fi
  rm -rf "$work"
  exit $status
}
trap cleanup EXIT INT TERM

# munged with its own key and socket.
mkdir -p "$work/munge"
chmod 700 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
       --pid-file="$work/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge/munge.seed"

# A one-node cluster on this machine, on ports of its own.
host=$(hostname -s)
cpus=$(nproc)
port=$((20000 + RANDOM % 20000))
mkdir -p "$work/state" "$work/spool"
cat > "$work/slurm.conf" <<CONF
ClusterName=slamcmptest
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmdParameters=config_overrides
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MailProg=/bin/true
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for i in $(seq 1 60); do
  state=$(sinfo -h -o %T 2> /dev/null | head -n 1 || true)
  [ "$state" = idle ] && break
  sleep 1
done
[ "$state" = idle ] || { echo "slurm_test: the node is not idle after 60 s (state '$state')" >&2; exit 1; }
echo "slurm_test: cluster up ($host, $cpus CPUs) after $(( $(date +%s) - start_time )) s"

# The plan: 2 back-ends x 2 trials on a short rendered tv1 (trial 2 re-rendered with seed 2).
"$slamcmp" synth --preset tv1 --frames 20 --supersample 1 --out "$work/tv1" > /dev/null
plan=(--sequence "$work/tv1" --backends cslam,monoslam --trials 2)
# An array of 3 tasks for the 4 runs: task 1 runs the first line and the last, as a plan larger than
# Slurm's MaxArraySize runs. The plan's folder holds a space and a '%a' (Slurm expands '%' in
# --output: its tasks' logs went to another folder, which did not exist, and no run started).
planned="$work/plan 5%a"
"$slamcmp" compare "${plan[@]}" --plan "$planned" --array-tasks 3 > /dev/null
jobs=$(wc -l < "$planned/jobs.txt")
timeout 600 sbatch --wait --chdir="$work" "$planned/slurm.sbatch" > "$work/sbatch.out" 2>&1 ||
  { cat "$work/sbatch.out" >&2; echo "slurm_test: sbatch --wait failed" >&2; exit 1; }
if [ "$(ls "$planned/logs" | grep -c '^slurm-.*\.out$')" -ne 3 ]; then
  ls -la "$planned/logs" >&2; echo "slurm_test: the 3 tasks' Slurm logs are not in the plan's logs/" >&2; exit 1
fi
"$slamcmp" compare --collect "$planned" > /dev/null
mv "$planned" "$work/plan"

# The same plan compared locally.
"$slamcmp" compare "${plan[@]}" --out "$work/local" > /dev/null

# Every run finished on the cluster, and every column but the times agrees.
if grep -q "## Runs not finished" "$work/plan/report.md"; then
  sed -n '/## Runs not finished/,/## Figures/p' "$work/plan/report.md" >&2
  echo "slurm_test: runs did not finish on the cluster" >&2
  exit 1
fi
untimed() {  # results.csv without the time columns
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) drop[i] = ($i ~ /^(cpu_)?ms_/) }
           { line = ""; for (i = 1; i <= NF; ++i) if (!drop[i]) line = line $i ","; print line }' "$1"
}
if ! diff <(untimed "$work/local/results.csv") <(untimed "$work/plan/results.csv") >&2; then
  echo "slurm_test: the cluster's results differ from a local compare's" >&2
  exit 1
fi
echo "slurm_test: passed: $jobs runs as a Slurm array of 3 tasks, collected; results.csv equal to a local compare's but for the times ($(( $(date +%s) - start_time )) s)"

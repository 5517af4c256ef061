#!/usr/bin/env bash
# Issue 24: `asf experiment --backend slurm` against a one-node Slurm cluster started here
# (Debian slurmctld + slurmd + munge, a generated slurm.conf, ports 16917/16918), torn down
# on every exit path. A 2 policies x 2 seeds sweep through Slurm must give the local
# backend's tables (timing columns aside) and the same run outputs to the byte; a second
# submission must find nothing left to run; --dry-run must write the script only; Ctrl-C
# must cancel the job and still summarize.
# Exit 77 (CTest: skipped) with the reason when Slurm cannot be started here.
#   tests/scripts/slurm_local.sh ASF_BINARY SOURCE_DIR
set -uo pipefail
ASF=$1 SRC=$2
skip() { echo "SKIP: $*"; exit 77; }
[[ $(id -u) == 0 ]] || skip "needs root to run slurmd and munged"
for b in slurmctld slurmd munged sbatch squeue scancel sinfo; do
  command -v "$b" > /dev/null || [[ -x /usr/sbin/$b ]] ||
    skip "$b missing (Debian packages slurmctld slurmd slurm-client munge)"
done
export PATH=$PATH:/usr/sbin
W=$(mktemp -d /tmp/asf-slurm-test.XXXXXX)
cleanup() {
  for p in slurmd slurmctld munged; do
    [[ -f $W/$p.pid ]] && kill "$(cat "$W/$p.pid")" 2> /dev/null
  done
  sleep 1
  for p in slurmd slurmctld munged; do
    [[ -f $W/$p.pid ]] && kill -9 "$(cat "$W/$p.pid")" 2> /dev/null
  done
  rm -rf "$W"
}
trap cleanup EXIT
mkdir -p "$W/state" "$W/spool" "$W/log"
head -c 1024 /dev/urandom > "$W/munge.key" && chmod 600 "$W/munge.key"
munged --force --key-file="$W/munge.key" --socket="$W/munge.sock" --pid-file="$W/munged.pid" \
  --log-file="$W/log/munged.log" --seed-file="$W/munge.seed" || skip "munged did not start"
HOST=$(hostname)
cat > "$W/slurm.conf" << CONF
ClusterName=asftest
SlurmctldHost=$HOST
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$W/munge.sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.log
SlurmctldPort=16917
SlurmdPort=16918
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$HOST CPUs=2 State=UNKNOWN
PartitionName=asf Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$W/slurm.conf
slurmctld -f "$SLURM_CONF" || skip "slurmctld did not start ($(tail -3 "$W/log/slurmctld.log"))"
slurmd -f "$SLURM_CONF" || skip "slurmd did not start ($(tail -3 "$W/log/slurmd.log"))"
for _ in $(seq 40); do
  sinfo -h -o %t 2> /dev/null | grep -q idle && break
  sleep 0.5
done
sinfo -h -o %t 2> /dev/null | grep -q idle || skip "the node never became idle: $(sinfo 2>&1)"

fail() { echo "FAIL: $*"; exit 1; }
cat > "$W/exp.ini" << INI
[experiment]
pipeline     = $SRC/configs/default.ini
policies     = tigre, frontier
replications = 2
first_seed   = 1
overrides    = pipeline.max_steps=300; frontier.robot_radius=0.25
INI
"$ASF" experiment "$W/exp.ini" --backend slurm --dry-run -o "$W/dry" > "$W/dry.log" 2>&1 ||
  fail "dry run: $(cat "$W/dry.log")"
[[ -f $W/dry/slurm/array.sh ]] || fail "dry run wrote no script"
[[ -z $(squeue -h) ]] || fail "dry run submitted something: $(squeue)"
[[ ! -d $W/dry/tigre ]] || fail "dry run ran something"

"$ASF" experiment "$W/exp.ini" --backend slurm --max-parallel 2 --poll 0.5 -o "$W/slurm" \
  > "$W/slurm.log" 2>&1 || fail "slurm backend: $(cat "$W/slurm.log")"
grep -q "submitted as Slurm job" "$W/slurm.log" || fail "no submission: $(cat "$W/slurm.log")"
"$ASF" experiment "$W/exp.ini" -j 2 -o "$W/local" > "$W/local.log" 2>&1 ||
  fail "local backend: $(cat "$W/local.log")"
# Tables without the timing columns (decision time, wall time), and the runs themselves.
cols() { python3 -c "
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
keep = [i for i, c in enumerate(rows[0]) if not c.startswith(('decision_ms', 'wall_time'))]
print('\n'.join(','.join(r[i] for i in keep) for r in rows))" "$1"; }
[[ $(cols "$W/slurm/summary.csv") == $(cols "$W/local/summary.csv") ]] ||
  fail "tables differ: $(diff <(cols "$W/slurm/summary.csv") <(cols "$W/local/summary.csv"))"
for p in tigre frontier; do
  for s in 1 2; do
    cmp -s "$W/slurm/$p/seed_$s/trajectory.csv" "$W/local/$p/seed_$s/trajectory.csv" ||
      fail "$p seed $s: trajectories differ"
    [[ $(cat "$W/slurm/$p/seed_$s/exit_code") == 0 ]] || fail "$p seed $s: exit_code"
  done
done
"$ASF" experiment "$W/exp.ini" --backend slurm -o "$W/slurm" > "$W/again.log" 2>&1 ||
  fail "resubmission: $(cat "$W/again.log")"
grep -q "4 finished earlier, 0 to submit" "$W/again.log" || fail "resubmitted: $(cat "$W/again.log")"
# Ctrl-C: the job is cancelled, what exists is summarized, the command exits 130.
cat > "$W/long.ini" << INI
[experiment]
pipeline     = $SRC/configs/default.ini
policies     = tigre
replications = 1
INI
"$ASF" experiment "$W/long.ini" --backend slurm --poll 0.2 -o "$W/long" > "$W/long.log" 2>&1 &
pid=$!
for _ in $(seq 100); do
  grep -q "1 running" "$W/long.log" && break
  sleep 0.2
done
grep -q "1 running" "$W/long.log" || fail "the long run never ran: $(cat "$W/long.log")"
kill -INT "$pid"
wait "$pid"
rc=$?
[[ $rc == 130 ]] || fail "Ctrl-C: exit status $rc: $(cat "$W/long.log")"
grep -q "interrupted: scancel" "$W/long.log" || fail "no scancel: $(cat "$W/long.log")"
[[ -f $W/long/summary.md ]] || fail "Ctrl-C: no summary"
for _ in $(seq 20); do
  [[ -z $(squeue -h) ]] && break
  sleep 0.5
done
[[ -z $(squeue -h) ]] || fail "the job is still queued after Ctrl-C: $(squeue)"
echo "slurm backend: the sweep through Slurm equals the local one; resubmission skipped"

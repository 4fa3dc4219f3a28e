# sweep-spacing --engine slurm on a real single-node Slurm: munged, slurmctld and slurmd
# (Debian's munge and slurm-wlm) configured in this test's directory, started, and stopped
# at the end.  The job array and the merge job give the local engine's CSV, byte for byte;
# a failed array fails the sweep; --no-wait leaves the CSV in the state directory.
# Skipped (77) where Slurm cannot start, unless TP_REQUIRE_CLUSTER=1 (CI).
for p in munged mungekey slurmctld slurmd sbatch scontrol; do
  command -v $p > /dev/null || skip TP_REQUIRE_CLUSTER "no $p (scripts/setup installs munge and slurm-wlm)"
done
[[ $(id -u) -eq 0 ]] || skip TP_REQUIRE_CLUSTER "slurmd must run as root to start jobs (this is uid $(id -u))"

# Everything lives here; daemons are stopped and their logs shown on failure.
sl=$PWD/slurm
mkdir -p "$sl/state" "$sl/spool" "$sl/log" "$sl/munge"
chmod 755 "$PWD" "$sl" "$sl/munge"
node=$(hostname -s)
# Ports: two free ones above 20000, from this process's id.
port=$((20000 + ($$ % 2000) * 2))
while (echo > /dev/tcp/127.0.0.1/$port) 2> /dev/null || (echo > /dev/tcp/127.0.0.1/$((port + 1))) 2> /dev/null; do
  port=$((port + 2))
done
export SLURM_CONF=$sl/slurm.conf
cat > "$SLURM_CONF" << EOF
ClusterName=tp-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sl/munge/socket
StateSaveLocation=$sl/state
SlurmdSpoolDir=$sl/spool
SlurmctldPidFile=$sl/slurmctld.pid
SlurmdPidFile=$sl/slurmd.pid
SlurmctldLogFile=$sl/log/slurmctld.log
SlurmdLogFile=$sl/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MaxArraySize=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
show_logs() {
  for f in "$sl"/log/*.log; do echo "--- $f" >&2; tail -n 15 "$f" >&2; done
}
stop_slurm() {
  scontrol shutdown > /dev/null 2>&1 || true
  for f in slurmctld slurmd munged; do
    pid=$(cat "$sl/$f.pid" 2> /dev/null || true)
    [[ -n $pid ]] || continue
    for _ in $(seq 100); do kill -0 "$pid" 2> /dev/null || break; [[ $f == munged ]] && kill "$pid" 2> /dev/null; sleep 0.1; done
    kill -9 "$pid" 2> /dev/null || true
  done
}
trap 'stop_slurm; cleanup' EXIT
start_failed() { show_logs; stop_slurm; skip TP_REQUIRE_CLUSTER "$1 did not start (logs above)"; }

mungekey --create --keyfile="$sl/munge/key" > /dev/null 2>&1 || skip TP_REQUIRE_CLUSTER "mungekey could not create a key"
munged --force --key-file="$sl/munge/key" --socket="$sl/munge/socket" --pid-file="$sl/munged.pid" \
  --log-file="$sl/log/munged.log" --seed-file="$sl/munge/seed" || start_failed munged
slurmctld -i || start_failed slurmctld
slurmd -N "$node" || start_failed slurmd
for _ in $(seq 300); do
  [[ $(sinfo -h -n "$node" -o %t 2> /dev/null) == idle ]] && break
  sleep 0.1
done
[[ $(sinfo -h -n "$node" -o %t 2> /dev/null) == idle ]] || start_failed "the node (state '$(sinfo -h -o %t 2>&1)')"
echo "ok: Slurm $(sinfo -V | cut -d' ' -f2) on $node, ports $port and $((port + 1)), $(nproc) CPUs"

sweep=$TP_SOURCE/scripts/sweep-spacing
args=(--electrodes 4,6,8 --pitch 0.6:1.4:0.4 --modes RA,SAI,PC)
"$sweep" "${args[@]}" > local.csv || fail "local engine"
mkdir run && cd run
t0=$(date +%s.%N)
"$sweep" --engine slurm "${args[@]}" > ../slurm.csv 2> ../err.txt || { show_logs; fail "slurm engine: $(cat ../err.txt)"; }
t1=$(date +%s.%N)
cd ..
cmp local.csv slurm.csv || fail "the Slurm engine's CSV differs from local's"
[[ -z $(ls run) ]] || fail "the default state directory was left: $(ls run)"
echo "ok: a job array of 2 tasks (9 arrays, MaxArraySize=2) and a merge job: the local engine's CSV, byte for byte, in $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s"
# More tasks than MaxArraySize allows: refused before anything is made or submitted.
refuses 2 --says "more than the cluster's MaxArraySize" -- "$sweep" --engine slurm --chunk 3 --state "$PWD/toomany" "${args[@]}"
[[ ! -e toomany ]] || fail "a refused sweep made its --state"

# A failed array (a fake optimize-weights that fails 6 electrodes at 1 mm): exit 1, one
# line naming it, no output, the logs kept.
mkdir fake
cat > fake/optimize-weights << EOF
#!/usr/bin/env bash
[[ " \$* " == *" --electrodes 6 --pitch 1 "* ]] && { echo "optimize-weights: injected failure" >&2; exit 1; }
exec "$(dirname "$(command -v optimize-weights)")/optimize-weights" "\$@"
EOF
chmod +x fake/optimize-weights
set +e; TP_BIN=$PWD/fake "$sweep" --engine slurm --state "$PWD/failed" "${args[@]}" > out.csv 2> err.txt; rc=$?; set -e
[[ $rc -eq 1 && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] || { show_logs; fail "a failing array: exit $rc, stderr: $(cat err.txt)"; }
grep -F 'electrodes 6 pitch 1: optimize-weights: injected failure' err.txt > /dev/null || fail "$(cat err.txt)"
ls failed/logs/task-*.out > /dev/null || fail "no task logs kept"
echo "ok: a failed array: $(cat err.txt)"

# --no-wait: the job ids on stderr, nothing on stdout, the CSV in the state directory.
"$sweep" --engine slurm --no-wait --sbatch --time=10 --state "$PWD/later" "${args[@]}" > out.csv 2> err.txt || fail "--no-wait: $(cat err.txt)"
[[ ! -s out.csv ]] && grep -F "the CSV will be $PWD/later/sweep.csv" err.txt > /dev/null || fail "--no-wait: $(cat err.txt)"
array_id=$(sed -n 's/.*submitted job array \([0-9]*\) .*/\1/p' err.txt)
# --sbatch reached Slurm: the array's time limit is 10 minutes.
scontrol show job -o "$array_id" | grep -F 'TimeLimit=00:10:00' > /dev/null || fail "--sbatch --time=10: $(scontrol show job -o "$array_id" | grep -o 'TimeLimit=[^ ]*' | head -1)"
# While its jobs are queued, another run on the same --state is refused.
set +e; "$sweep" --engine slurm --state "$PWD/later" "${args[@]}" > busy.csv 2> busy.err; rc=$?; set -e
[[ $rc -eq 1 && ! -s busy.csv ]] && grep -F "are still queued or running" busy.err > /dev/null || fail "a run on a busy --state: exit $rc, $(cat busy.err)"
for _ in $(seq 600); do [[ -f later/sweep.csv ]] && break; sleep 0.1; done
for _ in $(seq 300); do [[ -z $(squeue -h -o %i) ]] && break; sleep 0.1; done
cmp local.csv later/sweep.csv || { show_logs; fail "--no-wait's CSV differs from local's"; }
echo "ok: --no-wait: $(cat err.txt)"

# The same --state again, in other chunks: a fresh run (the old parts removed), the same
# CSV; another sweep on it is refused.
"$sweep" --engine slurm --chunk 9 --state "$PWD/later" "${args[@]}" > again.csv 2> err.txt || fail "again: $(cat err.txt)"
cmp local.csv again.csv || fail "a second run on the same --state differs"
[[ $(ls later/parts | wc -l) -eq 1 ]] || fail "parts of the earlier run left: $(ls later/parts)"
refuses 2 --says "holds another sweep" -- "$sweep" --engine slurm --state "$PWD/later" --electrodes 4 --pitch 1:1:1

# Interrupted while it waits, by SIGINT to its process group or SIGHUP to the script alone:
# both jobs cancelled, the default state removed, exit 128 + N, nothing of its session left.
for case in "INT 130 interrupted group" "HUP 129 hung_up_(SIGHUP) alone"; do
  read -r sig code word whom <<< "$case"
  word=${word//_/ }
  rm -rf interrupted && mkdir interrupted && cd interrupted
  # (env --default-signal: a background job of a script starts with SIGINT ignored.)
  setsid env --default-signal=INT "$sweep" --engine slurm "${args[@]}" > out.csv 2> err.txt &
  pid=$!
  # Both jobs queued (the array, then the merge job that depends on it): a signal between
  # the two submissions cancels the one there is, and says so.
  for _ in $(seq 200); do [[ -n $(squeue -h -n tp-sweep-merge -o %i 2> /dev/null) ]] && break; sleep 0.05; done
  [[ -n $(squeue -h -n tp-sweep-merge -o %i) ]] || fail "no merge job was queued: $(cat err.txt)"
  if [[ $whom == group ]]; then kill -"$sig" -- -"$pid"; else kill -"$sig" "$pid"; fi
  rc=0; wait "$pid" || rc=$?
  [[ $rc -eq $code && ! -s out.csv ]] && grep -E "^sweep-spacing: ${word//[()]/.}; cancelled jobs [0-9]+ and [0-9]+\$" err.txt > /dev/null \
    || fail "SIG$sig: exit $rc, $(cat err.txt)"
  for _ in $(seq 100); do [[ -z $(squeue -h -o %i) ]] && break; sleep 0.1; done
  [[ -z $(squeue -h -o %i) ]] || fail "SIG$sig: jobs left in the queue: $(squeue)"
  [[ -z $(ps -s "$pid" -o pid=,stat= | awk '$2 !~ /^Z/') ]] || fail "SIG$sig: processes left: $(ps -s "$pid" -o pid=,args=)"
  [[ -z $(ls) || $(ls | sort | tr '\n' ' ') == "err.txt out.csv " ]] || fail "SIG$sig: left behind: $(ls)"
  cd ..
  echo "ok: SIG$sig ($whom) while waiting: $(cat interrupted/err.txt), the queue empty"
done

# sweep-spacing's engines: local and GNU parallel write byte-identical CSV; a failed array
# fails the sweep with one line and no output; an interrupted parallel sweep resumes from
# its --state without recomputing the finished arrays; the Slurm engine's --dry-run prints
# complete batch scripts.  (The Slurm engine itself: sweep.slurm.)
sweep=$TP_SOURCE/scripts/sweep-spacing
command -v parallel > /dev/null || fail "GNU parallel is not installed (scripts/setup installs it)"
args=(--electrodes 4,6,8 --pitch 0.6:1.4:0.4 --modes RA,SAI,PC)

"$sweep" "${args[@]}" > local.csv 2> err.txt || fail "local: $(cat err.txt)"
[[ $(wc -l < local.csv) -eq 28 && ! -s err.txt ]] || fail "local: $(wc -l < local.csv) lines, stderr $(cat err.txt)"
"$sweep" --engine parallel "${args[@]}" > parallel.csv 2> err.txt || fail "parallel: $(cat err.txt)"
cmp local.csv parallel.csv || fail "parallel's CSV differs from local's"
# Across "hosts": GNU parallel's --sshloginfile, here two entries for this machine.
printf '1/:\n2/:\n' > hosts
"$sweep" --engine parallel --sshloginfile hosts "${args[@]}" > hosts.csv 2> err.txt || fail "hosts: $(cat err.txt)"
cmp local.csv hosts.csv || fail "parallel --sshloginfile's CSV differs from local's"
# One job at a time gives the same bytes too.
"$sweep" --jobs 1 "${args[@]}" > one.csv || fail "--jobs 1"
cmp local.csv one.csv || fail "--jobs 1 differs"
echo "ok: local, parallel and parallel --sshloginfile: identical, $(($(wc -l < local.csv) - 1)) rows"

# A fake optimize-weights (TP_BIN) that logs each array it computes, slowly, and fails the
# array "6 1" when FAIL_6_1 is set.
mkdir fake
cat > fake/optimize-weights << EOF
#!/usr/bin/env bash
n= p=
for ((i = 1; i <= \$#; i++)); do
  case \${!i} in --electrodes) j=\$((i + 1)); n=\${!j} ;; --pitch) j=\$((i + 1)); p=\${!j} ;; esac
done
if [[ " \$* " != *" --header-only "* ]]; then
  echo "\$n \$p" >> "$PWD/computed"
  [[ -n \${FAIL_6_1:-} && \$n == 6 && \$p == 1 ]] && { echo "optimize-weights: injected failure" >&2; exit 1; }
  sleep "\${FAKE_SLEEP:-0}"
fi
exec "$(dirname "$(command -v optimize-weights)")/optimize-weights" "\$@"
EOF
chmod +x fake/optimize-weights
export TP_BIN=$PWD/fake

# A failed array: exit 1, one line naming it, nothing on stdout (both engines).
for engine in local parallel; do
  set +e; FAIL_6_1=1 "$sweep" --engine $engine "${args[@]}" > out.csv 2> err.txt; rc=$?; set -e
  [[ $rc -eq 1 && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] || fail "$engine with a failing array: exit $rc, stdout $(wc -c < out.csv) bytes, stderr: $(cat err.txt)"
  grep -F 'electrodes 6 pitch 1: optimize-weights: injected failure' err.txt > /dev/null || fail "$engine: $(cat err.txt)"
done
echo "ok: a failed array fails the sweep: $(cat err.txt)"

# A signal to the script alone (not its process group) stops its workers at once: exit
# 143 or 130, one line, nothing on stdout, no job left running.  (env --default-signal: a
# script's background job starts with SIGINT ignored.)
for case in "local TERM 143 terminated" "parallel TERM 143 terminated" "local INT 130 interrupted"; do
  read -r engine sig code word <<< "$case"
  rm -f computed
  FAKE_SLEEP=30 env --default-signal=INT "$sweep" --engine "$engine" --jobs 2 "${args[@]}" > out.csv 2> err.txt &
  pid=$!
  for _ in $(seq 1200); do [[ $(lines computed) -ge 2 ]] && break; sleep 0.05; done
  [[ $(lines computed) -ge 2 ]] || fail "$engine: no job started: $(cat err.txt)"
  t0=$(date +%s)
  kill -"$sig" "$pid"
  rc=0; wait "$pid" || rc=$?
  [[ $rc -eq $code && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] && grep -Fx "sweep-spacing: $word" err.txt > /dev/null \
    || fail "$engine, SIG$sig: exit $rc, stderr: $(cat err.txt)"
  (($(date +%s) - t0 < 10)) || fail "$engine, SIG$sig: took $(($(date +%s) - t0)) s to stop"
  sleep 0.5
  if pgrep -f "$PWD/fake/optimize-weights" > /dev/null; then fail "$engine, SIG$sig: jobs left running: $(pgrep -af "$PWD/fake/")"; fi
  echo "ok: $engine, SIG$sig to the script alone: exit $rc, $(cat err.txt), no job left"
done

# Interrupt a parallel sweep with a --state, after some arrays, then run the same command.
rm -f computed
FAKE_SLEEP=1.5 setsid "$sweep" --engine parallel --jobs 2 --state st "${args[@]}" > first.csv 2> first.err &
pid=$!
for _ in $(seq 1200); do [[ $(lines st/joblog) -ge 4 ]] && break; sleep 0.05; done
# While it runs, another run on the same --state is refused.
set +e; "$sweep" --engine parallel --jobs 2 --state st "${args[@]}" > second.csv 2> second.err; rc=$?; set -e
[[ $rc -eq 1 && ! -s second.csv ]] && grep -F -- "another sweep-spacing is using" second.err > /dev/null \
  || fail "a second run on a busy --state: exit $rc, $(cat second.err)"
kill -TERM -- -"$pid" 2> /dev/null || fail "the sweep ended before it was interrupted"
rc=0; wait "$pid" 2> /dev/null || rc=$?
[[ $rc -eq 143 ]] && grep -Fx "sweep-spacing: terminated; the same command resumes" first.err > /dev/null \
  || fail "interrupted: exit $rc, stderr: $(cat first.err)"
finished=$(awk -F'\t' 'NR > 1 && $7 == 0 && $8 == 0 { print $1 }' st/joblog | sort -n)
n_finished=$(grep -c . <<< "$finished" || true)
[[ $n_finished -ge 3 && $n_finished -lt 9 ]] || fail "interrupted after $n_finished arrays: $(cat st/joblog)"
[[ ! -s first.csv ]] || fail "an interrupted sweep printed rows"
rm -f computed
"$sweep" --engine parallel --jobs 2 --state st "${args[@]}" > resumed.csv 2> err.txt || fail "resume: $(cat err.txt)"
cmp local.csv resumed.csv || fail "the resumed sweep's CSV differs from local's"
recomputed=0
for s in $finished; do
  job=$(sed -n "${s}p" st/jobs)
  if grep -Fx "$job" computed > /dev/null; then recomputed=$((recomputed + 1)); fi
done
[[ $recomputed -eq 0 ]] || fail "the resumed sweep recomputed $recomputed finished arrays"
[[ $(($(wc -l < computed) + n_finished)) -eq 9 ]] || fail "resumed: computed $(wc -l < computed) + finished $n_finished != 9"
# Once finished, the same command computes nothing and prints the same CSV.
rm -f computed
"$sweep" --engine parallel --state st "${args[@]}" > again.csv || fail "again"
cmp local.csv again.csv && [[ ! -s computed ]] || fail "a finished sweep recomputed $(lines computed) arrays"
echo "ok: interrupted after $n_finished of 9 arrays; the resumed sweep computed the other $((9 - n_finished)), identical CSV"
# A --state that holds another sweep is refused; so is a non-empty directory without one.
refuses 2 --says "holds another sweep" -- "$sweep" --engine parallel --state st --electrodes 4 --pitch 1:1:1
mkdir other && touch other/file
refuses 2 --says "is not empty and holds no sweep" -- "$sweep" --engine parallel --state other "${args[@]}"
unset TP_BIN

# Slurm's --dry-run: the array and merge scripts, complete, and nothing submitted.
"$sweep" --engine slurm --dry-run --chunk 4 --state "$PWD/sl" --sbatch --partition=short "${args[@]}" \
  > dry.txt 2> err.txt || fail "--dry-run: $(cat err.txt)"
[[ ! -e sl && ! -s err.txt ]] || fail "--dry-run created the state or talked: $(cat err.txt)"
for want in '#SBATCH --array=0-2' '#SBATCH --partition=short' "#SBATCH --output=$PWD/sl/logs/task-%a.out" \
            '#SBATCH --job-name=tp-sweep-merge' 'run_one ()' 'merge_rows ()' "cd '$PWD/sl'" ' jobs | while read -r n p'; do
  grep -F -- "$want" dry.txt > /dev/null || fail "--dry-run lacks '$want'"
done
[[ $(grep -c '^#!/bin/bash' dry.txt) -eq 2 ]] || fail "--dry-run: expected two scripts"
bash -n <(sed -n '1,/^$/p' dry.txt) || fail "the array script is not valid bash"
bash -n <(sed -n '/^$/,$p' dry.txt) || fail "the merge script is not valid bash"
echo "ok: --dry-run prints two scripts ($(wc -l < dry.txt) lines)"

# Bad options: exit 2, one line, nothing run.
refuses 2 --says "--engine: expected local, parallel or slurm, not 'cluster'" -- "$sweep" --engine cluster
refuses 2 --says "--state is for --engine parallel and slurm" -- "$sweep" --engine local --state st
refuses 2 --says "--chunk, --sbatch, --dry-run and --no-wait are for --engine slurm" -- "$sweep" --engine local --dry-run
refuses 2 --says "--jobs is for --engine local and parallel" -- "$sweep" --engine slurm --jobs 2
refuses 2 --says "--sshloginfile: cannot read 'no-such-file'" -- "$sweep" --engine parallel --sshloginfile no-such-file
refuses 2 --says "--chunk: expected a positive integer" -- "$sweep" --engine slurm --chunk 0
refuses 2 --says "--sbatch: expected one sbatch option without spaces or quotes, like --partition=short, not 'partition'" -- "$sweep" --engine slurm --sbatch 'partition'
refuses 2 --says "--electrodes: need at least 2, got 1" -- "$sweep" --electrodes 1,4
refuses 2 --says "--pitch: expected MIN:MAX:STEP with 0 < MIN <= MAX" -- "$sweep" --pitch 1:0.5:0.1
refuses 2 --says "at most 100000 pitches" -- "$sweep" --pitch 0.5:1000:0.001
refuses 2 --says "--jobs: needs a value" -- "$sweep" --jobs
refuses 2 --says "--electrodes: a count given twice in '4,6,4'" -- "$sweep" --electrodes 4,6,4
refuses 2 --says "--pitch: STEP too small: two pitches are the same in 10 significant digits" -- "$sweep" --electrodes 4 --pitch 1:1.0000000001:0.00000000001   # pitches the same in 10 digits
refuses 2 --says "--pitch: 150 mm outside [0.01, 100] mm" -- "$sweep" --electrodes 4 --pitch 50:150:50                      # 150 mm: the largest pitch is checked
refuses 2 --says "--header-only: set by sweep-spacing for each job, not an extra option" -- "$sweep" --electrodes 4 --pitch 1:1:1 -- --header-only
refuses 2 --says "--format: set by sweep-spacing for each job, not an extra option" -- "$sweep" --electrodes 4 --pitch 1:1:1 -- --format=json
refuses 2 --says "--version: not an option for each job" -- "$sweep" --electrodes 4 --pitch 1:1:1 -- --version
refuses 2 --says "GNU parallel would rewrite the braces in 'sk{1}.json'" -- "$sweep" --engine parallel --electrodes 4 --pitch 1:1:1 --skin "sk{1}.json"
refuses 2 --says "--state: for Slurm, a path of letters, digits and ._/+=@,:~- only" -- "$sweep" --engine slurm --state "a b" --electrodes 4 --pitch 1:1:1
[[ ! -e "a b" ]] || fail "a refused --state was created"
refuses 2 --says "--chunk, --sbatch, --dry-run and --no-wait are for --engine slurm" -- "$sweep" --engine local --chunk 4
# What GNU parallel, its job log (a line a job) or sbatch cannot carry is refused up front
# (exit 2, one line, nothing created), whichever option or variable it comes in.
refuses 2 --says "--state: a path with a newline" -- "$sweep" --engine parallel --state $'nl\nx' --electrodes 4 --pitch 1:1:1
refuses 2 --says "--state: a path with a newline" -- "$sweep" --engine slurm --state $'nl\nx' --electrodes 4 --pitch 1:1:1
[[ ! -e nl ]] || fail "a refused --state was created"
refuses 2 --says "GNU parallel's job log cannot hold the newline in \$'fingertip\\n'" -- "$sweep" --engine parallel --electrodes 4 --pitch 1:1:1 --skin $'fingertip\n'
refuses 2 --says "GNU parallel's job log cannot hold the newline in \$'1\\n2'" -- "$sweep" --engine parallel --electrodes 4 --pitch 1:1:1 -- --max-current $'1\n2'
refuses 2 --says "unknown option \$'--bo\\ngus'" -- "$sweep" $'--bo\ngus'
printf '1/:\n' > $'hosts\nx'
refuses 2 --says "--sshloginfile: a path with a newline" -- "$sweep" --engine parallel --sshloginfile $'hosts\nx' --electrodes 4 --pitch 1:1:1
mkdir -p $'bin\nx' 'bin{1}'
ln -s "$(command -v optimize-weights)" $'bin\nx/optimize-weights'
ln -s "$(command -v optimize-weights)" 'bin{1}/optimize-weights'
refuses 2 --says "the programs' directory has a newline" -- env TP_BIN=$'bin\nx' "$sweep" --electrodes 4 --pitch 1:1:1
refuses 2 --says "GNU parallel would rewrite the braces in the programs' directory" -- env TP_BIN='bin{1}' "$sweep" --engine parallel --electrodes 4 --pitch 1:1:1
mkdir 'in{1}'
(cd 'in{1}' && refuses 2 --says "GNU parallel would rewrite the braces in this directory's path" -- "$sweep" --engine parallel --state st --electrodes 4 --pitch 1:1:1)
[[ ! -e 'in{1}/st' ]] || fail "a refused --state was created"
# '-' is GNU parallel's name for stdin as --sshloginfile: a file of that name is read as one.
printf '1/:\n' > ./-
"$sweep" --engine parallel --sshloginfile - --electrodes 4 --pitch 1:1:1 --modes SAI < /dev/null > dash.csv 2> err.txt \
  || fail "--sshloginfile -: $(cat err.txt)"
[[ $(wc -l < dash.csv) -eq 2 ]] || fail "--sshloginfile -: $(cat dash.csv)"
refuses 2 --says "1045011 arrays: at most 1000000 in one sweep" -- "$sweep" --electrodes 2,3,4,5,6,7,8,9,10,11,12 --pitch 0.5:10:0.0001

# The progress bar, on a terminal (script(1) gives stderr one).
if command -v script > /dev/null; then
  script -qec "$sweep --electrodes 4,6 --pitch 1:1.4:0.4 --modes SAI > tty.csv" typescript > /dev/null \
    || fail "on a terminal: $(cat typescript)"
  grep -F '[##############################] 4/4 rows' typescript > /dev/null || fail "no progress bar: $(cat -v typescript)"
  [[ $(wc -l < tty.csv) -eq 5 ]] || fail "on a terminal: $(cat tty.csv)"
  echo "ok: a progress bar on a terminal"
fi

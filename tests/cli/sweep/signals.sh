# Every signal that would end sweep-spacing, sent to the script alone (not its process
# group), stops its workers first: exit 128 + N, one line on stderr, nothing on stdout, no
# process of its session left (the script runs in a session of its own, so that whatever
# it started, GNU parallel's jobs in their own process groups included, is found by its
# session id), and with --state the same command then resumes (not refused as in use).
# Both engines that run workers here: local (xargs) and parallel.  (Slurm's wait:
# sweep.slurm.)
sweep=$TP_SOURCE/scripts/sweep-spacing
command -v parallel > /dev/null || fail "GNU parallel is not installed (scripts/setup installs it)"
args=(--electrodes 4 --pitch 1:1.4:0.4 --modes SAI)
"$sweep" "${args[@]}" > local.csv 2> err.txt || fail "local: $(cat err.txt)"
[[ $(wc -l < local.csv) -eq 3 ]] || fail "local: $(cat local.csv)"

# A fake optimize-weights (TP_BIN) that logs each array it starts and sleeps before
# computing it.
mkdir fake
cat > fake/optimize-weights << EOF
#!/usr/bin/env bash
if [[ " \$* " == *" --header-only "* ]]; then
  sleep "\${FAKE_HEADER_SLEEP:-0}"
else
  echo "\$*" >> "$PWD/computed"
  sleep "\${FAKE_SLEEP:-0}"
fi
exec "$(dirname "$(command -v optimize-weights)")/optimize-weights" "\$@"
EOF
chmod +x fake/optimize-weights
export TP_BIN=$PWD/fake

# left SID: the processes of session SID still running (zombies, which only wait for
# init to reap them, aside).
left() { ps -s "$1" -o pid=,stat=,args= 2> /dev/null | awk '$2 !~ /^Z/' || true; }

for engine in local parallel; do
  for sig in HUP INT QUIT USR1 USR2 ALRM PIPE TERM; do
    code=$((128 + $(kill -l $sig)))
    case $sig in INT) word=interrupted ;; TERM) word=terminated ;; HUP) word="hung up (SIGHUP)" ;; *) word="stopped by SIG$sig" ;; esac
    state=() resumes=
    [[ $engine == parallel ]] && state=(--state "st-$sig") resumes="; the same command resumes"
    rm -f computed
    # (env --default-signal: a script's background job starts with SIGINT and SIGQUIT
    # ignored.  setsid execs, as this job leads no process group: the session's id is $!.)
    FAKE_SLEEP=30 setsid env --default-signal=INT,QUIT "$sweep" --engine $engine --jobs 2 "${state[@]}" "${args[@]}" \
      > out.csv 2> err.txt &
    pid=$!
    for _ in $(seq 400); do [[ $(lines computed) -ge 2 ]] && break; sleep 0.05; done
    [[ $(lines computed) -ge 2 ]] || fail "$engine: no job started: $(cat err.txt)"
    [[ $(ps -o sid= -p "$pid" | tr -d ' ') == "$pid" ]] || fail "the sweep is not in a session of its own"
    t0=$(date +%s%N)
    kill -"$sig" "$pid"
    rc=0; wait "$pid" || rc=$?
    ms=$((($(date +%s%N) - t0) / 1000000))
    [[ $rc -eq $code && ! -s out.csv && $(wc -l < err.txt) -eq 1 ]] && grep -Fx "sweep-spacing: $word$resumes" err.txt > /dev/null \
      || fail "$engine, SIG$sig: exit $rc (expected $code), stdout $(wc -c < out.csv) bytes, stderr: $(cat err.txt)"
    ((ms < 10000)) || fail "$engine, SIG$sig: took $ms ms to stop"
    # Everything it started has ended by the time it exits (a moment for the last ones
    # to be reaped).
    for _ in $(seq 40); do [[ -z $(left "$pid") ]] && break; sleep 0.05; done
    [[ -z $(left "$pid") ]] || fail "$engine, SIG$sig: processes left running: $(left "$pid")"
    if [[ $engine == parallel ]]; then
      # The state is free: the same command resumes, and gives the whole sweep.
      FAKE_SLEEP=0 "$sweep" --engine $engine --jobs 2 "${state[@]}" "${args[@]}" > resumed.csv 2> err2.txt \
        || fail "parallel, after SIG$sig: the same command: $(cat err2.txt)"
      cmp -s local.csv resumed.csv || fail "parallel, after SIG$sig: the resumed CSV differs from local's"
    fi
    echo "ok: $engine, SIG$sig: exit $rc in $ms ms, $(cat err.txt), no process left${resumes:+, resumed}"
  done
done

# A signal while the options are checked (optimize-weights --header-only, before any job
# starts) ends it the same way.
rm -f computed
FAKE_HEADER_SLEEP=30 setsid "$sweep" --engine parallel --state st-early "${args[@]}" > out.csv 2> err.txt &
pid=$!
for _ in $(seq 400); do [[ -n $(pgrep -s "$pid" -x sleep) ]] && break; sleep 0.05; done
[[ -n $(pgrep -s "$pid" -x sleep) ]] || fail "the options check did not start: $(cat err.txt)"
kill -USR1 "$pid"
rc=0; wait "$pid" || rc=$?
[[ $rc -eq 138 && ! -s out.csv && ! -e computed && $(wc -l < err.txt) -eq 1 ]] && grep -Fx 'sweep-spacing: stopped by SIGUSR1' err.txt > /dev/null \
  || fail "SIGUSR1 while the options are checked: exit $rc, stderr: $(cat err.txt)"
for _ in $(seq 40); do [[ -z $(left "$pid") ]] && break; sleep 0.05; done
[[ -z $(left "$pid") ]] || fail "SIGUSR1 while the options are checked: processes left running: $(left "$pid")"
echo "ok: SIGUSR1 while the options are checked: $(cat err.txt), no process left"

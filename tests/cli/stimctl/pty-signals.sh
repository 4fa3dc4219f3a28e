# Every catchable terminating signal stops the output first, then stimctl exits 128 + signal
# (SIGINT and SIGTERM as before; also SIGHUP, SIGQUIT, SIGUSR1/2, SIGALRM, SIGVTALRM,
# SIGPROF, SIGXCPU, SIGTSTP and a real-time signal, which once killed it with the output on).
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
for sig in INT TERM HUP QUIT USR1 USR2 ALRM VTALRM PROF XCPU TSTP RTMIN+2; do
  start_emu --record "$sig.jsonl"
  env --default-signal stimctl --port "$PORT" < stim.json 2> "$sig.err" &
  host=$!
  sleep 0.4
  kill -s "$sig" "$host" 2> /dev/null || kill -"$sig" "$host"
  rc=0
  wait "$host" || rc=$?
  at_exit=$(lines "$sig.jsonl")
  sleep 0.4
  later=$(lines "$sig.jsonl")
  stop_emu
  want=$((128 + $(kill -l "$sig")))
  [[ $rc -eq $want ]] || fail "SIG$sig: exit $rc, expected $want: $(cat "$sig.err")"
  [[ $at_exit -gt 20 ]] || fail "SIG$sig: only $at_exit pulses before the signal"
  [[ $at_exit -eq $later ]] || fail "SIG$sig: pulses continued after stimctl exited ($at_exit -> $later)"
  grep -q "output stopped" "$sig.err" || fail "SIG$sig: no summary: $(cat "$sig.err")"
  echo "ok: SIG$sig -> exit $rc after $at_exit pulses; $(head -1 "$sig.err")"
done
# A crash (SIGSEGV, SIGABRT, SIGBUS) cannot run the session's stop: the handler writes a
# prepared stop frame to the port, so the output ends at once instead of at the watchdog
# (300 ms: ~60 pulses at 200 Hz).
for sig in SEGV ABRT BUS; do
  start_emu --record "$sig.jsonl" --watchdog-ms 300
  env --default-signal stimctl --port "$PORT" < stim.json 2> "$sig.err" &
  host=$!
  sleep 0.4
  kill -s "$sig" "$host"
  rc=0
  wait "$host" 2> /dev/null || rc=$?
  at_exit=$(lines "$sig.jsonl")
  sleep 0.4
  later=$(lines "$sig.jsonl")
  stop_emu
  [[ $rc -eq $((128 + $(kill -l "$sig"))) ]] || fail "SIG$sig: exit $rc"
  [[ $((later - at_exit)) -le 4 ]] || fail "SIG$sig: $((later - at_exit)) pulses after the crash: no emergency stop"
  echo "ok: SIG$sig (crash) -> $((later - at_exit)) pulses after it, not the watchdog's ~60"
done
# A signal the parent ignores (nohup's SIGHUP) stays ignored, as in any POSIX program: the
# host lives on, keeps the session alive, and the stimulus runs to its end.
make_stimulus short.json --frequency 200 --duration 1
start_emu --record hup-ignored.jsonl
env --ignore-signal=HUP stimctl --port "$PORT" < short.json 2> hup-ignored.err &
host=$!
sleep 0.3
kill -HUP "$host"
rc=0
wait "$host" || rc=$?
stop_emu
[[ $rc -eq 0 ]] || fail "ignored SIGHUP: exit $rc: $(cat hup-ignored.err)"
[[ $(lines hup-ignored.jsonl) -eq 200 ]] || fail "ignored SIGHUP: $(lines hup-ignored.jsonl) pulses"
echo "ok: SIGHUP ignored by the parent (nohup): the stimulus completed, $(lines hup-ignored.jsonl) pulses"

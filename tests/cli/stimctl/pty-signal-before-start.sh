# A signal that arrives while stimctl is still identifying or configuring the device starts
# nothing: the stop flag is checked before every step that leads to output.  A slow device
# (every reply 100 ms late) makes the configuring phase ~500 ms long; the signal is sent
# once stimctl holds the port (its handlers are installed before it opens it), then 0, 100
# or 200 ms later: during identify, the status query or configure.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 5
# wait_for_port PID: until the process has the emulator's pty open (at most 10 s)
wait_for_port() {
  for _ in $(seq 1000); do
    ls -l /proc/"$1"/fd 2> /dev/null | grep -qF -- "-> $PORT" && return 0
    sleep 0.01
  done
  fail "stimctl never opened $PORT"
}
for sig in INT TERM; do
  for delay in 0 0.1 0.2; do
    start_emu --record "r$sig$delay.jsonl" --reply-delay-ms 100
    env --default-signal stimctl --port "$PORT" < stim.json 2> "e$sig$delay.err" &
    host=$!
    wait_for_port "$host"
    sleep "$delay"
    kill -s "$sig" "$host"
    rc=0
    wait "$host" || rc=$?
    sleep 0.2
    n=$(lines "r$sig$delay.jsonl")
    stop_emu
    want=$((128 + $(kill -l "$sig")))
    [[ $rc -eq $want ]] || fail "SIG$sig after $delay s: exit $rc, expected $want: $(cat "e$sig$delay.err")"
    grep -q "before the output started" "e$sig$delay.err" \
      || fail "SIG$sig after $delay s: the output was started: $(cat "e$sig$delay.err")"
    [[ $n -eq 0 ]] || fail "SIG$sig after $delay s: 'nothing delivered' but $n pulses recorded"
    echo "ok: SIG$sig $delay s after the port was opened: $n pulses; $(head -1 "e$sig$delay.err")"
  done
done

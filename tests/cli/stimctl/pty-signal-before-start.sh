# A signal that arrives while stimctl is still identifying or configuring the device starts
# nothing: the stop flag is checked before every step that leads to output.  A slow device
# (every reply 30 ms late) makes the configuring phase ~150 ms long; SIGINT lands in it.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 5
before=0
for delay in 0.06 0.09 0.12; do
  start_emu --record "r$delay.jsonl" --reply-delay-ms 30
  stimctl --port "$PORT" < stim.json 2> "e$delay.err" &
  host=$!
  sleep "$delay"
  kill -INT "$host"
  rc=0
  wait "$host" || rc=$?
  sleep 0.2
  n=$(lines "r$delay.jsonl")
  stop_emu
  [[ $rc -eq 130 ]] || fail "SIGINT at $delay s: exit $rc, expected 130: $(cat "e$delay.err")"
  if grep -q "before the output started" "e$delay.err"; then
    [[ $n -eq 0 ]] || fail "SIGINT at $delay s: 'nothing delivered' but $n pulses recorded"
    before=$((before + 1))
  else
    grep -q "output stopped" "e$delay.err" || fail "SIGINT at $delay s: $(cat "e$delay.err")"
  fi
  echo "ok: SIGINT at $delay s: $n pulses; $(head -1 "e$delay.err")"
done
[[ $before -ge 1 ]] || fail "no signal landed before the start: the test did not exercise the case"

# The host is killed with SIGKILL mid-stimulus: the device's watchdog (300 ms) stops the
# output on its own.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
start_emu --record rec.jsonl --watchdog-ms 300
make_stimulus stim.json --frequency 200 --duration 60
stimctl --port "$PORT" < stim.json 2> err.txt &
host=$!
sleep 1
kill -KILL "$host"
wait "$host" 2> /dev/null || true
at_kill=$(lines rec.jsonl)
sleep 1
after=$(lines rec.jsonl)
sleep 0.5
final=$(lines rec.jsonl)
stop_emu
[[ $at_kill -gt 100 ]] || fail "only $at_kill pulses before the kill"
[[ $after -eq $final ]] || fail "output still running 1 s after SIGKILL ($after -> $final pulses)"
extra=$((final - at_kill))
# at 200 Hz the watchdog (300 ms) allows at most ~60 more pulses; 80 leaves room for scheduling
[[ $extra -le 80 ]] || fail "$extra pulses after SIGKILL: more than the watchdog allows"
echo "ok: $extra pulses ($((extra * 5)) ms) after SIGKILL, then the watchdog stopped the output"

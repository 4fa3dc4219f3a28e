# The device goes away (line closed) or stalls past its watchdog: stimctl stops with a
# clear message and exit 1; the stalled device's output stops on its own.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
start_emu --record gone.jsonl --disconnect-after 0.5
rc=0
stimctl --port "$PORT" < stim.json 2> gone.err || rc=$?
stop_emu
[[ $rc -eq 1 ]] || fail "disconnect: exit $rc: $(cat gone.err)"
grep -qE "device lost|not responding" gone.err || fail "disconnect message: $(cat gone.err)"
start_emu --record stall.jsonl --stall-after 0.5 --stall-ms 2000 --watchdog-ms 300
rc=0
stimctl --port "$PORT" < stim.json 2> stall.err || rc=$?
n1=$(lines stall.jsonl)
sleep 0.5
n2=$(lines stall.jsonl)
stop_emu
[[ $rc -eq 1 ]] || fail "stall: exit $rc: $(cat stall.err)"
[[ $n1 -eq $n2 ]] || fail "stalled device kept stimulating"
last=$(tail -1 stall.jsonl | jq .t_s)
awk -v t="$last" 'BEGIN { exit !(t < 0.5 + 0.3 + 0.1) }' || fail "output ran until $last s, past the watchdog"
echo "ok: $(cat gone.err); $(cat stall.err); stalled output ended at $last s"

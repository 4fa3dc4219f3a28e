# Live weight frames: applied at the next pulse; end of input stops the output (exit 0);
# a bad frame stops the output and exits 2 without being sent.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
start_emu --record live.jsonl
{ sleep 0.3; echo '{"currents_mA": [0, 0, -0.25, 0.5, -0.25, 0, 0, 0]}'; sleep 0.3; } \
  | stimctl --port "$PORT" --live --stimulus stim.json 2> live.err || fail "live: $(cat live.err)"
at_exit=$(lines live.jsonl)
sleep 0.4
stop_emu
[[ $(lines live.jsonl) -eq $at_exit ]] || fail "pulses after end of input"
jq -se 'map(.currents_mA[3]) | (.[0] > 0.99) and (.[-1] < 0.51) and (.[-1] > 0.49)' live.jsonl > /dev/null \
  || fail "live frame not applied: $(jq -sc 'map(.currents_mA[3]) | [.[0], .[-1]]' live.jsonl)"
grep -q "end of input" live.err || fail "end reason: $(cat live.err)"
start_emu --record bad.jsonl
rc=0
{ sleep 0.2; echo '{"currents_mA": [0, 0, -1, 1.5, -0.4, 0, 0, 0]}'; sleep 5; } \
  | stimctl --port "$PORT" --live --stimulus stim.json 2> bad.err || rc=$?
at_exit=$(lines bad.jsonl)
sleep 0.3
stop_emu
[[ $rc -eq 2 ]] || fail "bad frame: exit $rc: $(cat bad.err)"
[[ $(lines bad.jsonl) -eq $at_exit ]] || fail "pulses after the refusal"
jq -se 'map(.currents_mA[3]) | all(. < 1.01)' bad.jsonl > /dev/null || fail "the bad frame was applied"
echo "ok: $(cat live.err); refusal: $(cat bad.err)"

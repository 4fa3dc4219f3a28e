# The README's main command: the whole pipeline on the in-process emulator.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
optimize-weights --mode SAI 2> /dev/null | make-pulse --amplitude 1.0 --frequency 200 2> /dev/null \
  | stimctl --port emu --duration 1 --record rec.jsonl 2> err.txt || fail "pipeline: $(cat err.txt)"
n=$(lines rec.jsonl)
[[ $n -eq 200 ]] || fail "expected 200 pulses (200 Hz x 1 s), got $n"
grep -q "200 of 200 pulses on 8 channels" err.txt || fail "summary: $(cat err.txt)"
jq -se 'map(.currents_mA | add | fabs) | max <= 1e-9' rec.jsonl > /dev/null || fail "currents do not sum to zero"
echo "ok: $(cat err.txt)"
# A rate whose period is not a whole number of microseconds: rounded to 6667 us.
make-pulse --amplitude 1 --frequency 150 --count 30 < "$TP_INPUTS/sai-weights.json" 2> /dev/null \
  | stimctl --port emu --record r150.jsonl 2> /dev/null || fail "150 Hz"
[[ $(lines r150.jsonl) -eq 30 ]] || fail "150 Hz: $(lines r150.jsonl) pulses"
jq -se 'to_entries | map((.value.t_s - .key * 0.006667) | fabs) | max < 1e-9' r150.jsonl > /dev/null || fail "150 Hz period"

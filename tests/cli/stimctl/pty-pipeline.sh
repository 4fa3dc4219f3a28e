# Through a real pseudo-terminal: recorded currents = weights x amplitude within the DAC
# resolution; pulse count = frequency x duration; zero sum and zero net charge per pulse.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
start_emu --record rec.jsonl
make_stimulus stim.json --frequency 200 --duration 5
stimctl --port "$PORT" --duration 1 < stim.json 2> err.txt || fail "stimctl: $(cat err.txt)"
stop_emu
n=$(lines rec.jsonl)
[[ $n -eq 200 ]] || fail "expected 200 pulses, got $n"
check_record rec.jsonl "$EXPECTED"
# pulse times: every 5 ms from 0
jq -se 'to_entries | map((.value.t_s - .key * 0.005) | fabs) | max < 1e-9' rec.jsonl > /dev/null || fail "pulse times"
# a count-limited stimulus stops by itself: 37 pulses at 100 Hz
start_emu --record rec2.jsonl
make_stimulus stim2.json --frequency 100 --count 37
stimctl --port "$PORT" < stim2.json 2> err2.txt || fail "stimctl: $(cat err2.txt)"
stop_emu
[[ $(lines rec2.jsonl) -eq 37 ]] || fail "expected 37 pulses, got $(lines rec2.jsonl)"
echo "ok: $(cat err.txt)"

# calibrate with answers from a pipe (--responses -): q stops after the first trial (one
# trial delivered, no profile); someone who never feels anything gets no profile and a log
# of every trial, none above the ceiling.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
cal=(calibrate --bank "$BANK" --primaries SAI --trial-duration 0.05 --responses - --port emu --emu-channels 64)
echo q | "${cal[@]}" --log q.csv --record q.jsonl > q.json 2> q.err && fail "q: exit 0"
grep -q "stopped by the user (q) after trial 1" q.err || fail "q: $(cat q.err)"
[[ ! -s q.json ]] || fail "q: a profile was written"
[[ $(lines q.csv) -eq 1 && $(lines q.jsonl) -eq 10 ]] || fail "q: $(lines q.csv) log lines, $(lines q.jsonl) pulses"
echo "ok: q after one trial of 10 pulses: $(cat q.err)"
yes n | head -1000 | "${cal[@]}" --ceiling 0.5 --log none.csv --record none.jsonl > none.json 2> none.err && fail "never felt: exit 0"
grep -q "nothing was felt up to the ceiling" none.err || fail "never felt: $(cat none.err)"
[[ ! -s none.json ]] || fail "never felt: a profile was written"
peak=$(jq -s 'map(.currents_mA | map(fabs) | max) | max' none.jsonl)
last=$(tail -1 none.csv | cut -d, -f7)
awk -v p="$peak" -v l="$last" 'BEGIN { exit !(p <= 0.5 + 0.000977 && l == 0.5) }' || fail "never felt: peak $peak mA, last level $last"
echo "ok: never felt: $(($(lines none.csv) - 1)) trials up to the 0.5 mA ceiling (peak $peak mA)"
# Bad input before anything is sent.
refuses 2 --says "ceiling 2.5 outside" -- calibrate --bank "$BANK" --log x.csv --ceiling 2.5 --responses -
refuses 2 --says "--pixel" -- calibrate --bank "$BANK" --log x.csv --pixel 8,0 --responses -
refuses 2 --says "not a primary" -- calibrate --bank "$BANK" --log x.csv --primaries XY --responses -
refuses 2 --says "--responses" -- calibrate --bank "$BANK" --log x.csv --responses file.txt
refuses 2 --says "--record" -- calibrate --bank "$BANK" --log x.csv --port /dev/ttyS99 --record r.jsonl
refuses 2 --says "give one" -- calibrate --bank "$BANK" --log x.csv --pixel 1,1 --per-pixel --responses -
refuses 2 --says "not a bank" -- calibrate --bank "$TP_INPUTS/sai-weights.json" --log x.csv --responses -
refuses 2 --says "--log" -- calibrate --bank "$BANK" --log /nonexistent/dir/x.csv --responses -
refuses 2 --says "could not find" -- calibrate --bank "$BANK" --log x.csv --pixel 0,0 --primaries PC --responses -
refuses 2 --says "--trial-duration" -- calibrate --bank "$BANK" --log x.csv --trial-duration 20 --responses -
# The bank's own current limit bounds the ceiling (found by the review).
jq '.max_current_mA = 0.5' "$BANK" > low-bank.json
refuses 2 --says "above the bank's current limit" -- calibrate --bank low-bank.json --log x.csv --ceiling 1 --responses -

# The device's measured guards (issue 41, item 4; docs/safety.md, "Measured guards") on
# stim-emu's real pseudo-terminal with a skin, each checked from the device's own record:
#  - a pad lifted at 0.45 s: the pulse at 0.5 s finds it (no current flows) and is the
#    last; stimctl exits 1 naming the channel, the time and "contact";
#  - a series resistance that rises at 0.3 s past the 20 V compliance: the output stops at
#    that first pulse ("compliance"), its voltage on the rail;
#  - a quarter contact at 0.25 s on the pad of 2 mA, 800 us phases on 5 mm^2 (Shannon's k
#    1.71 at full contact, 2.31 on a quarter; a 100 V compliance and Rp 10 kOhm, so that
#    the quarter needs 78 V): the output stops at the first pulse that breaks the density
#    limit ("density"), so the limit is never broken twice;
#  - the lift at 100 pulses a second: the pulse at 0.45 s is the last;
#  - the same skins without the events: every pulse delivered, exit 0.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 10 --duration 1
make-pulse --amplitude 2 --width 800 --balance-width 800 --frequency 10 --duration 1 \
  < "$TP_INPUTS/sai-weights.json" > strong.json 2> /dev/null || fail "make-pulse"
jq -e '.electrode_area_mm2 == 5' strong.json > /dev/null || fail "the stimulus' area is not 5 mm^2"
skin() {  # FILE RP_KOHM EVENTS_JSON
  printf '{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": %s, "cp_nf": 30.0}, "events": %s}\n' "$2" "$3" > "$1"
}
skin lift.json 50 '[{"t_s": 0.45, "channels": [2], "contact": 0.0}]'
skin rs.json 50 '[{"t_s": 0.3, "channels": [3], "rs_kohm": 30.0}]'
skin quarter.json 10 '[{"t_s": 0.25, "channels": [3], "contact": 0.25}]'
skin none.json 10 '[]'
# guarded SKIN STIMULUS COMPLIANCE_V: runs it on a fresh stim-emu, record in SKIN.jsonl,
# stimctl's exit code in $RC and its stderr in SKIN.err.
guarded() {
  local name=${1%.json}
  start_emu --record "$name.jsonl" --skin "$1" --compliance-v "$3"
  RC=0
  stimctl --port "$PORT" < "$2" 2> "$name.err" || RC=$?
  stop_emu
}
last_t() { jq -s 'map(.t_s) | max' "$1"; }

guarded lift.json stim.json 20
[[ $RC == 1 ]] || fail "lifted pad: exit $RC: $(cat lift.err)"
grep -q "channel 2 lost contact at t = 0.5 s (no current flowed); 6 of 10 pulses delivered" lift.err \
  || fail "lifted pad: $(cat lift.err)"
[[ $(last_t lift.jsonl) == 0.5 ]] || fail "lifted pad: pulses after 0.5 s: $(last_t lift.jsonl)"
jq -se '.[-1] | .voltage_V[2] == -20 and .impedance_kohm[2] == null' lift.jsonl > /dev/null \
  || fail "lifted pad: the last record: $(tail -1 lift.jsonl)"

# The same lift at 100 pulses a second: the pulse at 0.45 s is the last (the firmware's
# engine starts no pulse before the last one's readings are guarded).
cp lift.json lift100.json
make_stimulus fast.json --frequency 100 --duration 1
guarded lift100.json fast.json 20
[[ $RC == 1 ]] || fail "lifted pad at 100 Hz: exit $RC: $(cat lift100.err)"
grep -q "channel 2 lost contact at t = 0.45 s (no current flowed); 46 of 100 pulses delivered" lift100.err \
  || fail "lifted pad at 100 Hz: $(cat lift100.err)"
[[ $(last_t lift100.jsonl) == 0.45 ]] || fail "lifted pad at 100 Hz: pulses after 0.45 s: $(last_t lift100.jsonl)"

guarded rs.json stim.json 20
[[ $RC == 1 ]] || fail "compliance: exit $RC: $(cat rs.err)"
grep -q "channel 3 needed more than the 20 V compliance at t = 0.3 s" rs.err || fail "compliance: $(cat rs.err)"
[[ $(last_t rs.jsonl) == 0.3 ]] || fail "compliance: pulses after 0.3 s: $(last_t rs.jsonl)"
jq -se '.[-1].voltage_V[3] == 20' rs.jsonl > /dev/null || fail "compliance: not at the rail: $(tail -1 rs.jsonl)"

guarded quarter.json strong.json 100
[[ $RC == 1 ]] || fail "quarter contact: exit $RC: $(cat quarter.err)"
grep -q "channel 3: charge density above the limit on the contact area left at t = 0.3 s" quarter.err \
  || fail "quarter contact: $(cat quarter.err)"
[[ $(last_t quarter.jsonl) == 0.3 ]] || fail "quarter contact: pulses after 0.3 s: $(last_t quarter.jsonl)"

for s in stim strong; do
  guarded none.json $s.json 100
  [[ $RC == 0 ]] || fail "no event, $s: exit $RC: $(cat none.err)"
  [[ $(jq -s length none.jsonl) == 10 ]] || fail "no event, $s: $(jq -s length none.jsonl) pulses"
done
# The record's impedance plot (scripts/plot-impedance), where gnuplot is: the lifted pad
# open at 0.5 s; a record without measurements refused.
if command -v gnuplot > /dev/null; then
  "$TP_SOURCE/scripts/plot-impedance" lift.jsonl -o lift.png 2> plot.err || fail "plot-impedance: $(cat plot.err)"
  [[ $(head -c 4 lift.png | od -An -c | tr -d ' ') == 211PNG ]] || fail "plot-impedance wrote no PNG"
  grep -q "wrote lift.png (8 pads, 6 pulses)" plot.err || fail "plot-impedance: $(cat plot.err)"
  stimctl --port emu --record plain.jsonl < stim.json 2> /dev/null || fail "stimctl without a skin"
  refuses 2 --says "plain.jsonl has no measurements" -- "$TP_SOURCE/scripts/plot-impedance" plain.jsonl
  refuses 2 --says "--columns 3 does not divide the record's 8 channels" -- "$TP_SOURCE/scripts/plot-impedance" --columns 3 lift.jsonl
fi
echo "ok: $(cat lift.err) | $(cat rs.err) | $(cat quarter.err)"

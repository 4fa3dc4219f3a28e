# stimctl --contact-loss suspend (issue 41, item 4; docs/safety.md, "Measured guards"): a
# finger moving over a display.  Two patterns on separate pads (A on channels 0 and 1, B on
# 4 and 5, 20 Hz each for 1 s); channel 1 lifted from 0.3 s to 0.6 s.  Checked from the
# record, on stim-emu's real pseudo-terminal: B goes on as asked throughout; A's pulse at
# 0.3 s finds the loss, its pulses from 0.35 s to 0.6 s are at the probe's 0.05 mA (the
# one at 0.6 s finds the contact again), and from 0.65 s A is as asked; exit 0, the
# summary counting the 6 probes.  By default (stop) the same skin stops everything at
# A's pulse at 0.3 s.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
stim() {  # FILE CURRENTS
  printf '{"format": "tactile-primaries/stimulus/1", "channels": 8, "currents_mA": %s, "max_current_mA": 2.0, "pulse": {"width_us": 200, "interphase_us": 0, "balance_width_us": 200, "frequency_hz": 20}, "count": 20}\n' "$2" > "$1"
}
stim a.json '[1, -1, 0, 0, 0, 0, 0, 0]'
stim b.json '[0, 0, 0, 0, 1, -1, 0, 0]'
mix-stimuli a.json b.json > mix.json 2> /dev/null || fail "mix-stimuli"
cat > skin.json <<'JSON'
{"format": "tactile-primaries/skin/1",
 "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
 "events": [{"t_s": 0.3, "channels": [1], "contact": 0.0},
            {"t_s": 0.6, "channels": [1], "contact": 1.0}]}
JSON
start_emu --record rec.jsonl --skin skin.json
stimctl --port "$PORT" --contact-loss suspend < mix.json 2> err.txt || fail "suspend: $(cat err.txt)"
sleep 0.2  # the firmware's monitor writes its last lines after the host has finished
stop_emu
grep -q "40 of 40 pulses" err.txt || fail "suspend: $(cat err.txt)"
# Pattern 0 (A): full before the loss is found and after the contact is found again, at the
# probe in between; pattern 1 (B): full throughout.
jq -se '
  (map(select(.pattern == 1)) | length == 20 and all(.[]; .currents_mA[4] == 1.000448)) and
  (map(select(.pattern == 0)) as $a
   | ($a | length) == 20
   and all($a[]; if .t_s <= 0.3 or .t_s > 0.6 then .currents_mA[0] == 1.000448
                 else (.currents_mA[0] | fabs) <= 0.05 and (.currents_mA[0] | fabs) > 0.04 end)
   and ([$a[] | select((.currents_mA[0] | fabs) <= 0.05)] | length) == 6)' rec.jsonl > /dev/null \
  || fail "the record: $(jq -c '[.pattern, .t_s, .currents_mA[0], .currents_mA[4]]' rec.jsonl | tr '\n' ' ')"
grep -q "6 of them at the probe while a pad had no contact" err.txt || fail "the summary: $(cat err.txt)"
# stop (the default): A's pulse at 0.3 s finds the loss, and is the last pulse (B's at
# 0.3005 s is not delivered).
start_emu --record stop.jsonl --skin skin.json
rc=0; stimctl --port "$PORT" < mix.json 2> stop.err || rc=$?
stop_emu
[[ $rc == 1 ]] && grep -q "channel 1 lost contact at t = 0.3 s" stop.err || fail "stop: exit $rc, $(cat stop.err)"
[[ $(jq -s 'map(.t_s) | max' stop.jsonl) == 0.3 ]] || fail "stop: pulses after 0.3 s"
refuses 2 --stdin mix.json --says "--contact-loss suspend: emu (in-process emulator) does not measure its pulses" \
  -- stimctl --port emu --contact-loss suspend
refuses 2 --stdin mix.json --says "--contact-loss: pause is not stop or suspend" -- stimctl --port emu --contact-loss pause
echo "ok: $(tail -1 err.txt)"

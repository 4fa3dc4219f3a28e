# calibrate against a device whose current limit is below the ceiling (stim-emu
# --max-current 0.5): every trial at the ceiling is checked against the device's
# capabilities before the first is sent, and refused naming the ceiling, the device's
# limit and the ceiling to give; nothing is delivered.  At that ceiling, the trials run.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
start_emu --channels "$CHANNELS" --max-current 0.5 --record rec.jsonl --event-log events.txt
cal=(calibrate --bank "$BANK" --trial-duration 0.05 --port "$PORT" --responses -)
refuses 2 --says "--ceiling 1 mA: the device cannot deliver RA at pixel (4, 4) at it" -- "${cal[@]}" --log a.csv
grep -qF "exceeds the limit of 0.5 mA); lower --ceiling to 0.499 mA or less; nothing was sent" err \
  || fail "the device's limit and the ceiling to give: $(cat err)"
# At 0.5 mA itself: the DAC's steps make the device's limit 0.4998 mA.
refuses 2 --says "lower --ceiling to 0.499 mA or less" -- "${cal[@]}" --log b.csv --ceiling 0.5 --primaries SAI
grep -qF "the device's limit of 0.4998 mA" err || fail "the DAC's limit: $(cat err)"
[[ $(lines rec.jsonl) -eq 0 ]] || fail "$(lines rec.jsonl) pulses delivered before the refusal"
grep -q start events.txt && fail "the output was started: $(cat events.txt)"
[[ ! -e a.csv && ! -e b.csv ]] || fail "a refused session left its log: $(ls ./*.csv)"
echo "ok: nothing delivered, no log left"
# The ceiling it names: every trial within the device's limits (a numb observer climbs to it).
yes n | head -1000 | "${cal[@]}" --log c.csv --ceiling 0.499 --primaries SAI > c.json 2> c.err \
  && fail "never felt: exit 0"
grep -qF "SAI at pixel (4, 4): not felt up to the ceiling, 0.499 mA" c.err || fail "at 0.499 mA: $(cat c.err)"
peak=$(jq -s 'map(.currents_mA | map(fabs) | max) | max' rec.jsonl)
awk -v p="$peak" 'BEGIN { exit !(p > 0.49 && p <= 0.4998) }' || fail "peak $peak mA"
echo "ok: at 0.499 mA, $(($(lines c.csv) - 1)) trials, peak $peak mA"
stop_emu
# A device with fewer channels than the bank's pads: no level helps, and it says so.
refuses 2 --says "RA at pixel (4, 4): the device cannot deliver its trials at any level: stimulus has 64 channels; the device has 8" \
  -- calibrate --bank "$BANK" --log d.csv --responses - --port emu --emu-channels 8 --record d.jsonl
[[ $(lines d.jsonl) -eq 0 ]] || fail "8 channels: pulses delivered"

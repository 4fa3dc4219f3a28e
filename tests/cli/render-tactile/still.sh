# A still image through a real line (stim-emu, or the firmware in QEMU with
# TP_DEVICE=firmware), checked from the record: one pure-G pixel gives that pixel's SAI
# pattern only, at the profile's current, at 200 Hz; two pixels of different colours give
# each its pattern at its own rate, and nothing else.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
row=$((ROWS > 2 ? 2 : 1)); pad=$((row * COLUMNS + 3))

# 1. Pure G = 128 at column 3, row 2 (the firmware's 4 x 2 grid: row 1).
mkpng one.png "$COLUMNS" "$ROWS" "3,$row,0,128,0"
render-tactile --bank "$BANK" --profile profile.json --duration 1 one.png > one.json 2> one.err \
  || fail "render-tactile: $(cat one.err)"
jq -e --argjson pad "$pad" '.pixels == [$pad] and .primary == "SAI" and .pulse.frequency_hz == 200
    and ((.pixel_currents_mA[0] - (0.3 + 128 / 255 * 0.6)) | fabs) < 1e-12' one.json > /dev/null \
  || fail "one pixel: $(jq -c '{pixels, primary, pulse, pixel_currents_mA}' one.json)"
start_emu --channels "$CHANNELS" --record rec.jsonl
stimctl --port "$PORT" < one.json 2> err.txt || fail "stimctl: $(cat err.txt)"
sleep 0.2
stop_emu
check_pixels rec.jsonl one.json
jq -se 'length >= 199 and length <= 201 and all(.[]; .pattern == 0)
    and all(.[]; ((.t_s * 1e6 | round) - .slip_us) % 5000 == 0)' rec.jsonl > /dev/null \
  || fail "one pixel: $(lines rec.jsonl) pulses, patterns $(jq -sc 'map(.pattern) | unique' rec.jsonl)"
# Counts of one in the singular (not "1 groups", "1 slots").
grep -qF "render-tactile: 1 lit pattern in 1 group, cycle 500 us of 1 slot, " one.err \
  && grep -qF "SAI 200 Hz (200 requested; 1 group);" one.err || fail "one pixel's summary: $(cat one.err)"
echo "ok: pad $pad's SAI pattern alone, $(lines rec.jsonl) pulses at 200 Hz: $(cat one.err)"

# 2. R = 255 at (0, 0) and G = 200 at (3, row): RA at comfort, SAI at 0.3 + 200/255 x 0.6 mA.
mkpng two.png "$COLUMNS" "$ROWS" "0,0,255,0,0" "3,$row,0,200,0"
render-tactile --bank "$BANK" --profile profile.json --duration 1 two.png > two.json 2> two.err \
  || fail "render-tactile: $(cat two.err)"
jq -e --argjson pad "$pad" '(.patterns | length) == 2
    and .patterns[0].primary == "RA" and .patterns[0].pixels == [0] and .patterns[0].pixel_currents_mA == [1]
    and .patterns[1].primary == "SAI" and .patterns[1].pixels == [$pad]
    and ((.patterns[1].pixel_currents_mA[0] - (0.3 + 200 / 255 * 0.6)) | fabs) < 1e-12
    and (.patterns[0].pulse.frequency_hz | . <= 30 and . > 29.9)
    and (.patterns[1].pulse.frequency_hz | . <= 200 and . > 199)' two.json > /dev/null \
  || fail "two pixels: $(jq -c '[.patterns[] | {pixels, primary, f: .pulse.frequency_hz}]' two.json)"
start_emu --channels "$CHANNELS" --record rec2.jsonl
stimctl --port "$PORT" < two.json 2> err2.txt || fail "stimctl: $(cat err2.txt)"
sleep 0.2
stop_emu
counts=$(jq -c '[.patterns[] | [.count - 1, .count]]' two.json)
check_mix_record rec2.jsonl two.json "$counts"
check_pixels rec2.jsonl two.json
echo "ok: RA and SAI each at its own rate ($counts pulses): $(cat two.err)"

# Bad input: exit 2, one line naming the problem, nothing on stdout, nothing delivered.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
mkpng ok.png 8 8 "3,2,0,255,0"
rt=(render-tactile --bank "$BANK" --profile profile.json)
# Pictures: bytes that do not decode, the wrong size without --resample, nothing lit (also
# as a palette PNG: pnmtopng's choice for few colours).
head -c 40 ok.png > cut.png
refuses 2 --says "cut.png" -- "${rt[@]}" cut.png
mkpng small.png 4 4 "1,1,255,0,0"
refuses 2 --says "4 x 4" -- "${rt[@]}" small.png
mkpng black.png 8 8
refuses 2 --says "no pixel is lit" -- "${rt[@]}" black.png
{ echo P3; echo 8 8; echo 255; for ((k = 0; k < 64; ++k)); do echo "0 0 0"; done; } | pnmtopng > palette.png 2> /dev/null
refuses 2 --says "palette.png: no pixel is lit" -- "${rt[@]}" palette.png
# Profiles: comfort below threshold, above the device's limit, a pixel of another array.
jq '.primaries.SAI.comfort_mA = 0.2' profile.json > low.json
refuses 2 --says "below its threshold" -- render-tactile --bank "$BANK" --profile low.json ok.png
jq '.primaries.SAI.comfort_mA = 2.5' profile.json > high.json
refuses 2 --says "above the current limit" -- render-tactile --bank "$BANK" --profile high.json ok.png
jq '.pixels = [{pad: 64, SAI: {threshold_mA: 0.1, comfort_mA: 0.2}}]' profile.json > other.json
refuses 2 --says "not one of the array's 64 pads" -- render-tactile --bank "$BANK" --profile other.json ok.png
# Banks: a 4 x 4 grid's for this 8 x 8 image; a weights document, not a bank; a pixel lit
# in a primary its pattern could not be found for (the corner's PC).
optimize-weights --bank --mode SAI --grid 4x4 --pitch 2 --pad 1x1 > bank4.json 2> /dev/null || fail "bank 4x4"
refuses 2 --says "8 x 8 pixels for an array of 4 x 4 pads" -- render-tactile --bank bank4.json --profile profile.json ok.png
refuses 2 --says "not a bank" -- render-tactile --bank "$TP_INPUTS/sai-weights.json" --profile profile.json ok.png
mkpng corner.png 8 8 "0,0,0,0,255"
refuses 2 --says "could not find" -- "${rt[@]}" corner.png
mkpng ra.png 8 8 "3,3,255,0,0"
refuses 2 --says "no patterns for" -- render-tactile --bank bank4.json --profile profile.json --resample ra.png
# Options: rates, widths, crosstalk, duration outside their ranges.
refuses 2 --says "--rates: PC 2000 Hz" -- "${rt[@]}" --rates PC:2000 ok.png
refuses 2 --says "not a primary" -- "${rt[@]}" --rates XY:20 ok.png
refuses 2 --says "--width" -- "${rt[@]}" --width 200.5 ok.png
refuses 2 --says "--crosstalk" -- "${rt[@]}" --crosstalk 1.5 ok.png
refuses 2 --says "--duration" -- "${rt[@]}" --duration 0 ok.png
# Never clamped: 1e300 s is not 3600 s, 1e-9 s not one pulse (SAI's period is 5 ms); a
# primary given twice is not the last of them; what a mode has no use for is not ignored.
refuses 2 --says "--duration: 1e+300 s outside (0, 3600] s" -- "${rt[@]}" --duration 1e300 ok.png
refuses 2 --says "--duration: the stimulus's 1e-09 s is shorter than one period of SAI at its planned 200 Hz (0.005 s): give --duration 0.005 or more" \
  -- "${rt[@]}" --duration 1e-9 ok.png
refuses 2 --says "--rates: RA given twice (RA:10,RA:20): give each once" -- "${rt[@]}" --rates RA:10,RA:20 ok.png
refuses 2 --says "--fps: applies to --frames, and to --sequence's frames without --duration" -- "${rt[@]}" --fps 60 ok.png
refuses 2 --says "--fps: applies to --frames" -- "${rt[@]}" --sequence --duration 2 --fps 60 ok.png
# Nothing reaches a device: the pipeline's stimctl gets nothing and sends nothing.
{ render-tactile --bank "$BANK" --profile low.json ok.png 2> /dev/null || true; } \
  | { stimctl --port emu --emu-channels 64 --record none.jsonl 2> /dev/null || true; }
[[ ! -s none.jsonl ]] || fail "a pulse was delivered after a refusal"
echo "ok: nothing delivered"
# Sequences: a frame lighting what the sequence's stimulus has no pattern for, a JSON frame
# of the wrong size or values, --sequence with --frames; a starting amplitude above its
# pattern's (stimctl too).
mkpng g1.png 8 8 "3,2,0,255,0"
render-tactile --bank "$BANK" --profile profile.json --sequence g1.png > seq.json 2> /dev/null || fail "--sequence"
mkpng r1.png 8 8 "3,2,255,0,0"
refuses 2 --says "no pattern for" -- "${rt[@]}" --frames seq.json r1.png
echo '{"rgb": [[0, 0, 0]]}' > short.jsonl
refuses 2 --says "1 pixel for 8 x 8 pads" --stdin short.jsonl -- "${rt[@]}" --frames seq.json -
jq -nc '{rgb: [range(0; 64) | [0, 256, 0]]}' > big.jsonl
refuses 2 --says "0 to 255" --stdin big.jsonl -- "${rt[@]}" --frames seq.json -
refuses 2 --says "give one" -- "${rt[@]}" --sequence --frames seq.json g1.png
jq '.start_amplitudes_mA = [1.5]' seq.json > loud.json
refuses 2 --says "start_amplitudes_mA" --stdin loud.json -- stimctl --port emu --emu-channels 64 --record loud.jsonl
[[ ! -s loud.jsonl ]] || fail "a pulse was delivered"
# A profile calibrated on another array (calibrate writes its size).
jq '.array = {columns: 4, rows: 4}' profile.json > other-array.json
refuses 2 --says "calibrated on an array of" -- render-tactile --bank "$BANK" --profile other-array.json ok.png
# A bank larger than a stimulator (more than 64 pads): render-tactile plans it (--plan)
# but prints no stimulus; calibrate refuses it before writing its log.
optimize-weights --bank --mode SAI --grid 9x8 --pitch 2 --pad 1x1 --neighbourhood 3 > bank72.json 2> /dev/null || fail "bank 9x8"
mkpng nine.png 9 8 "4,4,0,255,0"
refuses 2 --says "72 pads, more than a stimulator drives" -- render-tactile --bank bank72.json --profile profile.json nine.png
render-tactile --bank bank72.json --profile profile.json --plan nine.png > plan72.json 2> /dev/null || fail "--plan on 72 pads"
refuses 2 --says "72 pads" -- calibrate --bank bank72.json --log never.csv --responses -
[[ ! -e never.csv ]] || fail "calibrate wrote its log before refusing"
# Found by the review: a malformed JSON frame is bad input (2), not a failure; a bank's
# "feasible" that is not true or false.
printf '{"rgb": [1,\n' > broken.jsonl
refuses 2 --says "frame 1: malformed JSON" --stdin broken.jsonl -- "${rt[@]}" --sequence -
jq '.pixels[19].patterns.SAI.feasible = "no"' "$BANK" > odd-bank.json
refuses 2 --says "feasible: not true or false" -- render-tactile --bank odd-bank.json --profile profile.json ok.png
# A profile's range with a key it does not know (a misspelt comfort_mA among them), also
# a pixel's.
jq '.primaries.SAI.comfort_ma = 0.5' profile.json > typo.json
refuses 2 --says "profile: primaries.SAI: unknown key 'comfort_ma'" -- render-tactile --bank "$BANK" --profile typo.json ok.png
jq '.pixels = [{pad: 19, SAI: {threshold_mA: 0.1, comfort_mA: 0.2, trails: 4}}]' profile.json > typo2.json
refuses 2 --says "profile: pixels[0].SAI: unknown key 'trails'" -- render-tactile --bank "$BANK" --profile typo2.json ok.png

# A sequence's stimulus (seq.json, pixel (3, 2) SAI at the profile's comfort, 0.9 mA) fits
# only what it was made for: frames under a profile of a higher comfort (they would be
# clipped: 128 and 255 both 0.9 mA), a bank of another grid of as many pads (16 x 4: the
# frames would light other pads), the stimulus's own settings given again.
jq '.primaries.SAI.comfort_mA = 1.5' profile.json > strong.json
refuses 2 --says "--frames seq.json: the profile gives pixel (3, 2)'s SAI up to 1.5 mA, above the 0.9 mA its pattern was made for" \
  -- render-tactile --bank "$BANK" --profile strong.json --frames seq.json g1.png
jq -nc '{rgb: [range(0; 64) | if . == 19 then [0, 128, 0] else [0, 0, 0] end]}' > g128.jsonl
refuses 2 --says "above the 0.9 mA its pattern was made for" --stdin g128.jsonl \
  -- render-tactile --bank "$BANK" --profile strong.json --frames seq.json -
optimize-weights --bank --mode SAI --grid 16x4 --pitch 2 --pad 1x1 --neighbourhood 3 > bank16x4.json 2> /dev/null || fail "bank 16x4"
mkpng g16.png 16 4 "3,1,0,255,0"  # pad 19, as (3, 2) of 8 x 8
refuses 2 --says "--frames seq.json: a sequence made for 8 x 8 pads (columns x rows), not the bank's 16 x 4: give the bank it was made with" \
  -- render-tactile --bank bank16x4.json --profile profile.json --frames seq.json g16.png
jq 'del(.array)' seq.json > bare.json
refuses 2 --says "--frames bare.json: records no array" -- "${rt[@]}" --frames bare.json g1.png
for opt in "--rates SAI:100" "--duration 2" "--crosstalk 0.2" --plan; do
  # shellcheck disable=SC2086  # the option and its value, two words
  refuses 2 --says "${opt%% *}: --frames plays the sequence's stimulus as it was made" -- "${rt[@]}" $opt --frames seq.json g1.png
done
# A weaker profile is fine, and not clipped: 128 and 255 give 0.3 + 128/255 x 0.3 and 0.6 mA.
jq '.primaries.SAI.comfort_mA = 0.6' profile.json > weak.json
mkpng g128.png 8 8 "3,2,0,128,0"
render-tactile --bank "$BANK" --profile weak.json --frames seq.json --fps 1000 g128.png g1.png > weak.jsonl 2> weak.err \
  || fail "--frames under a weaker profile: $(cat weak.err)"
jq -se 'map(.amplitudes[0]) as $a | (($a[0] - (0.3 + 128 / 255 * 0.3)) | fabs) < 1e-12 and $a[1] == 0.6' weak.jsonl > /dev/null \
  || fail "a weaker profile's frames: $(cat weak.jsonl)"
echo "ok: a weaker profile's frames: $(jq -sc 'map(.amplitudes[0])' weak.jsonl)"

# Bad input: exit 2, one line naming the problem, nothing on stdout, nothing delivered.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
mkpng ok.png 8 8 "3,2,0,255,0"
rt=(render-tactile --bank "$BANK" --profile profile.json)
# Pictures: a palette PNG (few colours: pnmtopng's choice), bytes that do not decode, the
# wrong size without --resample, nothing lit.
{ echo P3; echo 8 8; echo 255; for ((k = 0; k < 64; ++k)); do echo "0 0 0"; done; } | pnmtopng > palette.png 2> /dev/null
refuses 2 --says "a palette image" -- "${rt[@]}" palette.png
head -c 40 ok.png > cut.png
refuses 2 --says "cut.png" -- "${rt[@]}" cut.png
mkpng small.png 4 4 "1,1,255,0,0"
refuses 2 --says "4 x 4" -- "${rt[@]}" small.png
mkpng black.png 8 8
refuses 2 --says "no pixel is lit" -- "${rt[@]}" black.png
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
refuses 2 --says "1 pixels for 8 x 8 pads" --stdin short.jsonl -- "${rt[@]}" --frames seq.json -
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

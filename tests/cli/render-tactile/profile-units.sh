# The whole pipeline in the person's units: make-pulse --profile --intensity and
# mix-stimuli --profile --intensities give threshold + v (comfort - threshold) mA for the
# document's mode; refusals name the problem.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
make-pulse --profile profile.json --intensity 0.5 --frequency 200 < "$TP_INPUTS/sai-weights.json" > sai.json 2> err.txt \
  || fail "make-pulse --intensity: $(cat err.txt)"
jq -e '((.amplitude_mA - 0.6) | fabs) < 1e-12 and (((.currents_mA | map(fabs) | max) - 0.6) | fabs) < 1e-12' sai.json > /dev/null \
  || fail "SAI at 0.5: $(jq -c '{amplitude_mA, currents_mA}' sai.json)"
make-pulse --amplitude 0.8 --frequency 30 < "$TP_INPUTS/ra-weights.json" > ra.json 2> /dev/null || fail "make-pulse RA"
mix-stimuli --profile profile.json --intensities 1,0.25 ra.json sai.json > mix.json 2> err.txt \
  || fail "mix-stimuli --intensities: $(cat err.txt)"
jq -e '.patterns[0].amplitude_mA == 1 and ((.patterns[1].amplitude_mA - 0.45) | fabs) < 1e-12
    and ((([.patterns[1].currents_mA[] | fabs] | max) - 0.45) | fabs) < 1e-12' mix.json > /dev/null \
  || fail "mix: $(jq -c '[.patterns[] | .amplitude_mA]' mix.json)"
echo "ok: SAI at 0.5 -> 0.6 mA; the mix's RA at 1 -> 1 mA, SAI at 0.25 -> 0.45 mA"
refuses 2 --says "intensity 1.5 outside (0, 1]" --stdin "$TP_INPUTS/sai-weights.json" -- make-pulse --profile profile.json --intensity 1.5
refuses 2 --says "--intensity: needs --profile" --stdin "$TP_INPUTS/sai-weights.json" -- make-pulse --intensity 0.5
refuses 2 --says "give --amplitude" --stdin "$TP_INPUTS/sai-weights.json" -- make-pulse
jq 'del(.mode)' "$TP_INPUTS/sai-weights.json" > nomode.json
refuses 2 --says "names no mode" --stdin nomode.json -- make-pulse --profile profile.json --intensity 0.5
jq 'del(.primaries.SAI)' profile.json > nosai.json
refuses 2 --says "no range for SAI" --stdin "$TP_INPUTS/sai-weights.json" -- make-pulse --profile nosai.json --intensity 0.5
refuses 2 --says "2 for 1 inputs" -- mix-stimuli --profile profile.json --intensities 0.5,0.5 sai.json
refuses 2 --says "give both" -- mix-stimuli --intensities 0.5 sai.json
# A profile calibrated on another array (calibrate writes its columns and rows) is refused,
# by make-pulse against the weights' array and by mix-stimuli against each input's channels.
jq '.array = {"columns": 8, "rows": 8}' profile.json > grid-profile.json
refuses 2 --says 'calibrated on an array of {"columns":8,"rows":8}, the weights'"'"' array is 8 electrodes' \
  --stdin "$TP_INPUTS/sai-weights.json" -- make-pulse --profile grid-profile.json --intensity 0.5
refuses 2 --says "calibrated on an array of {\"columns\":8,\"rows\":8}, sai.json's is 8 channels" \
  -- mix-stimuli --profile grid-profile.json --intensities 0.5 sai.json
jq '.array = {"columns": 8, "rows": 1}' profile.json > row-profile.json
mix-stimuli --profile row-profile.json --intensities 0.5 sai.json > /dev/null 2> err.txt ||
  fail "a profile of the inputs' 8 channels: $(cat err.txt)"

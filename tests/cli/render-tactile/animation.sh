# The README's animation, run as the README gives it (its code block after "An animation",
# with stimctl's --record added): the rate SAI actually runs at, from the stimulus's
# patterns and from stimctl's record, is the rate the README states.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
cp "$BANK" bank.json
awk '/An animation/ { found = 1 } found && /^```sh/ { code = 1; next } code && /^```/ { exit } code' \
  "$TP_SOURCE/README.md" > example.sh
grep -q -- '--sequence -' example.sh && grep -q 'stimctl .*--live --stimulus bar.json$' example.sh \
  || fail "the README's animation is not where this test looks: $(cat example.sh)"
sed -i 's/--live --stimulus bar.json$/--live --stimulus bar.json --record rec.jsonl/' example.sh
bash -e -o pipefail example.sh 2> example.err || fail "the README's animation: $(cat example.err)"
# Every SAI pattern at one rate, and the record's pulses of each pattern that far apart.
rate=$(jq -e '[.patterns[] | select(.primary == "SAI") | .pulse.frequency_hz] | unique
  | if length == 1 then .[0] else error("rates \(.)") end' bar.json) || fail "bar.json's rates"
jq -se --argjson f "$rate" '
  group_by(.pattern) | map(map(.t_s * 1e6 | round) | [.[1:], .[:-1]] | transpose | map(.[0] - .[1]))
  | flatten | (length > 100) and all(. == (1e6 / $f | round))' rec.jsonl > /dev/null \
  || fail "the record's spacing is not 1 / $rate s: $(jq -sc 'group_by(.pattern) | .[0][:3] | map(.t_s)' rec.jsonl)"
grep -qF "SAI at $rate Hz" "$TP_SOURCE/README.md" || fail "the README does not say SAI runs at $rate Hz"
grep -qF "SAI at $rate Hz" "$TP_SOURCE/docs/rendering.md" || fail "docs/rendering.md does not say SAI runs at $rate Hz"
echo "ok: the README's animation runs SAI at $rate Hz, as it says ($(lines rec.jsonl) pulses): $(grep refresh example.err | head -1)"

# A shaped pulse (issue 40): --phases, the weights document's pulse and --stimulus simulate
# the same phases; a shorthand and its phases give the same thresholds; the thresholds go
# back to make-pulse, which gives multiples for that shape only.
in=$TP_INPUTS/sai-weights.json
shape=500:0.1,200:1,50:0,500:-0.5
fiber-threshold --config "$in" --phases "$shape" > p.json 2> p.txt
grep -q "shaped (500 us at 0.1, 200 us at 1, 50 us at 0, 500 us at -0.5)" p.txt || fail "stderr: $(cat p.txt)"
jq -e '.thresholds.pulse.phases | length == 4' p.json > /dev/null || fail "pulse: $(jq -c .thresholds.pulse p.json)"
make-pulse --amplitude 1 --count 3 --phases "$shape" < "$in" > st.json 2> /dev/null
fiber-threshold --config "$in" --stimulus st.json > s.json 2> /dev/null
cmp <(jq .thresholds p.json) <(jq .thresholds s.json) || fail "--stimulus and --phases differ"
jq --slurpfile s st.json '.pulse = {phases: $s[0].pulse.phases}' "$in" > carried.json
fiber-threshold --config carried.json > c.json 2> /dev/null
cmp <(jq .thresholds p.json) <(jq .thresholds c.json) || fail "the document's pulse differs"
# The prepulse's shape is not the symmetric pulse: the thresholds move.
fiber-threshold --config "$in" > d.json 2> /dev/null
jq -e --slurpfile d d.json '.thresholds.receptors.SAI.threshold_mA != $d[0].thresholds.receptors.SAI.threshold_mA' p.json > /dev/null ||
  fail "the shape changed nothing"
# The shorthand 200 + 100 gap + 800 at -1/4 and its phases: the same numbers.
fiber-threshold --config "$in" --width 200 --interphase 100 --balance-width 800 > w.json 2> /dev/null
fiber-threshold --config "$in" --phases 200:1,100:0,800:-0.25 > q.json 2> /dev/null
cmp <(jq .thresholds.receptors w.json) <(jq .thresholds.receptors q.json) || fail "shorthand and phases differ"
# make-pulse: multiples for the same shape, not for another.
make-pulse --amplitude 1 --count 2 --phases "$shape" < p.json 2> m1.txt > /dev/null
grep -q "make-pulse: 1 mA = .* x [A-Z]* threshold, .*(mrg, shaped (500 us at 0.1" m1.txt || fail "no multiples: $(cat m1.txt)"
make-pulse --amplitude 1 --count 2 < p.json 2> m2.txt > /dev/null
grep -q "not this 200 us biphasic one" m2.txt || fail "another pulse not noticed: $(cat m2.txt)"
refuses 2 --says "--width excludes --phases" -- fiber-threshold --config "$in" --phases "$shape" --width 100
refuses 2 --says "excludes --phases" -- fiber-threshold --config "$in" --phases "$shape" --stimulus st.json
refuses 2 --says "a shaped pulse (phases) has no single width" -- fiber-threshold --config "$in" --phases "$shape" --strength-duration
refuses 2 --says "phase 1: duration 0.5 us outside [1, 10000] us" -- fiber-threshold --config "$in" --phases 0.5:1
echo "ok: shaped pulses"

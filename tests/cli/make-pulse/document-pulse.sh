# A weights document's pulse (issue 40: a designed shape travels in it) is make-pulse's
# default; a pulse flag replaces it, and make-pulse says so on stderr.
jq '.pulse = {phases: [{duration_us: 100, level: 1}, {duration_us: 400, level: -0.25}]}' \
  "$TP_INPUTS/sai-weights.json" > shaped.json
make-pulse --amplitude 1 --count 2 < shaped.json > a.json 2> a.txt
jq -e '.pulse.phases == [{duration_us: 100, level: 1}, {duration_us: 400, level: -0.25}] and
  (.pulse | has("width_us") | not) and .safety.level_unit == 4' a.json > /dev/null ||
  fail "the document's pulse not used: $(jq -c .pulse a.json)"
grep -q "replaced" a.txt && fail "said replaced without a flag: $(cat a.txt)"
make-pulse --amplitude 1 --count 2 --width 150 < shaped.json > b.json 2> b.txt
jq -e '.pulse.width_us == 150 and (.pulse | has("phases") | not)' b.json > /dev/null ||
  fail "--width did not replace it: $(jq -c .pulse b.json)"
grep -q "make-pulse: the document's pulse (shaped (100 us at 1, 400 us at -0.25)) replaced by the flags' (150 us biphasic)" b.txt ||
  fail "no note: $(cat b.txt)"
# A malformed pulse in the document is bad input.
jq '.pulse = {phases: [{duration_us: 100}]}' "$TP_INPUTS/sai-weights.json" > bad.json
refuses 2 --says "weights document: pulse.phases[0]: expected" --stdin bad.json -- make-pulse --amplitude 1
echo "ok: the document's pulse"

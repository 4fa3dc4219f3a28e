# The stimulus's amplitude in units of each threshold: fiber-threshold --stimulus reports it,
# and make-pulse does too for a document that carries thresholds, for the same pulse only.
in=$TP_INPUTS/sai-weights.json
make-pulse --amplitude 1.5 --count 3 < "$in" 2>/dev/null > stim.json
fiber-threshold --config "$in" --stimulus stim.json > t.json 2> err.txt
for r in RA SAI PC; do
  th=$(jq ".thresholds.receptors.$r.threshold_mA" t.json)
  m=$(jq ".threshold_multiples.$r" t.json)
  jq -e -n "($m * $th - 1.5 | fabs) < 1e-12" >/dev/null || fail "$r: multiple $m x $th is not 1.5 mA"
done
grep -q "stimulus 1.5 mA = " err.txt || fail "no multiples on stderr: $(cat err.txt)"
# The thresholds were for the stimulus's own pulse (200 us symmetric): the same as the default.
fiber-threshold --config "$in" > d.json
cmp <(jq .thresholds t.json) <(jq .thresholds d.json) || fail "--stimulus changed the pulse"
echo "ok: multiples"

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

# make-pulse carries the thresholds and says the multiples for the same pulse only; so does
# stimctl before it sends anything.
make-pulse --amplitude 1.5 --count 20 < t.json > s.json 2> mp.txt
grep -q "make-pulse: 1.5 mA = .* x .* threshold" mp.txt || fail "make-pulse: no multiples: $(cat mp.txt)"
jq -e '.thresholds.receptors.SAI.threshold_mA > 0' s.json >/dev/null || fail "thresholds not carried"
make-pulse --amplitude 1.5 --count 2 --width 100 < t.json > /dev/null 2> mp2.txt
grep -q "not this 100 us biphasic one" mp2.txt || fail "make-pulse: other pulse not noticed: $(cat mp2.txt)"
stimctl --port emu --stimulus s.json 2> sc.txt
grep -q "^stimctl: 1.5 mA = " sc.txt || fail "stimctl: no multiples: $(cat sc.txt)"
# Half the weights: the same currents come from twice the amplitude; the multiples hold.
jq '.weights |= map(. / 2)' "$in" > half.json
fiber-threshold --config half.json > th.json 2>/dev/null
make-pulse --amplitude 2 --count 2 < th.json 2> mp3.txt > s3.json
stimctl --port emu --stimulus s3.json 2> sc3.txt
grep -q "^stimctl: 2 mA = " sc3.txt || fail "stimctl: amplitude per unit weight not used: $(cat sc3.txt)"
# Malformed thresholds are bad input, before anything is sent.
jq '.thresholds.receptors.SAI.threshold_mA = -1' s.json > bad.json
rc=0; stimctl --port emu --stimulus bad.json > out.txt 2> err.txt || rc=$?
[[ $rc -eq 2 && ! -s out.txt ]] || fail "stimctl accepted a negative threshold (exit $rc)"
echo "ok: make-pulse and stimctl multiples"

# Malformed carried thresholds: one line, exit 2, nothing on stdout, for make-pulse.
doc=$TP_GOLDEN/fiber-threshold/sai-mrg.json
bad() {
  jq "$1" "$doc" > bad-doc.json
  local rc=0
  make-pulse --amplitude 1 --count 2 < bad-doc.json > out.txt 2> err.txt || rc=$?
  [[ $rc -eq 2 && ! -s out.txt && $(wc -l < err.txt) -eq 1 ]] ||
    fail "make-pulse accepted thresholds edited by '$1' (exit $rc): $(cat err.txt)"
}
bad '.thresholds.receptors = {}'
bad '.thresholds.receptors["S\nA"] = {"threshold_mA": 1}'
bad '.thresholds.receptors.SAI.threshold_mA = 1e-320'
bad '.thresholds.receptors.SAI.threshold_mA = 1000'
bad '.thresholds.peak_weight = 1e-310'
bad '.thresholds.pulse.monophasic = "yes"'
bad '.thresholds.pulse.width_us = "200"'
echo "ok: malformed carried thresholds refused"

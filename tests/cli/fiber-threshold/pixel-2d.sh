# A pixel on a 2-D grid (optimize-weights --at): fiber-threshold takes the fibres through
# the document's focus, and --at the same point gives the same bytes; the SAI pixel's SAI
# fibre passes at the focus's z, and the threshold ratios are the document's receptors'.
optimize-weights --mode SAI --grid 3x3 --pitch 2 --pad 1x1 --at 2,0 > px.json 2> px.err || fail "optimize-weights: $(cat px.err)"
fiber-threshold < px.json > a.json 2> a.err || fail "fiber-threshold: $(cat a.err)"
jq 'del(.focus)' px.json | fiber-threshold --at 2,0 > b.json 2> b.err || fail "fiber-threshold --at: $(cat b.err)"
cmp -s <(jq -S .thresholds a.json) <(jq -S .thresholds b.json) || fail "the focus and --at differ"
jq -e '.thresholds.settings.through_mm == [2, 0]
    and .thresholds.receptors.SAI.z_mm == 0 and .thresholds.receptors.SAI.threshold_mA > 0
    and .thresholds.receptors.RA.threshold_mA > 0 and .thresholds.receptors.PC.threshold_mA > 0
    and (.thresholds.receptors.RA.x_mm | . >= 1 and . <= 3)' a.json > /dev/null \
  || fail "thresholds: $(jq -c .thresholds a.json)"
echo "ok: $(cat a.err)"

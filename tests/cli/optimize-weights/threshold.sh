# --objective threshold: starts from the AF optimum, never returns a worse threshold ratio,
# keeps Sum w = 0 and max |w| = 1, reports both, and is deterministic.
optimize-weights --mode SAI --objective threshold --max-evaluations 12 > a.json 2> err.txt
# The reruns (determinism, a longer search) repeat the same code: the plain build's only.
sanitized=${TP_SANITIZED:-0}
if [[ $sanitized != 1 ]]; then
  optimize-weights --mode SAI --objective threshold --max-evaluations 12 > b.json 2>/dev/null
  cmp a.json b.json || fail "two runs differ"
fi
jq -e '.objective == "threshold" and .threshold_search.evaluations <= 12' a.json >/dev/null ||
  fail "objective or evaluation count: $(jq -c .threshold_search a.json)"
jq -e '.threshold_ratio.SAI <= .af_optimum.threshold_ratio' a.json >/dev/null ||
  fail "worse than the AF optimum: $(jq -c '[.threshold_ratio.SAI, .af_optimum.threshold_ratio]' a.json)"
jq -e '(.weights | add | fabs) < 1e-12 and (.weights | map(fabs) | max) == 1' a.json >/dev/null ||
  fail "weights: $(jq -c .weights a.json)"
# The reported ratio is the one fiber-threshold finds for those weights.
fiber-threshold --config a.json > t.json 2>/dev/null
jq -e --slurpfile t t.json '.threshold_ratio.SAI == $t[0].threshold_ratio.SAI' a.json >/dev/null ||
  fail "fiber-threshold disagrees: $(jq .threshold_ratio.SAI t.json)"
grep -q "threshold ratio .* (AF optimum: " err.txt || fail "stderr: $(cat err.txt)"
echo "ok: $(cat err.txt)"
# More whole searches follow the same path further (the polish on whole searches): never a
# higher ratio, and never more searches than allowed.
if [[ $sanitized != 1 ]]; then
  optimize-weights --mode SAI --objective threshold --max-evaluations 24 > c.json 2>/dev/null
  jq -e --slurpfile a a.json '.threshold_search.evaluations <= 24 and
    .threshold_ratio.SAI <= $a[0].threshold_ratio.SAI' c.json >/dev/null ||
    fail "24 whole searches: $(jq -c '[.threshold_search, .threshold_ratio.SAI]' c.json)"
fi

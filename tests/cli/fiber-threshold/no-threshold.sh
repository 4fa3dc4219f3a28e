# A pattern too weak to fire any fibre below 100 mA: a null threshold with its reason, null
# ratios, exit 0; the search is bounded.
fiber-threshold --weights 0,0,0,0.001,-0.001,0,0,0 > out.json 2> err.txt
for r in RA SAI PC; do
  jq -e ".thresholds.receptors.$r.threshold_mA == null" out.json >/dev/null || fail "$r has a threshold"
  jq -e ".thresholds.receptors.$r.reason == \"does not fire below 100 mA\"" out.json >/dev/null ||
    fail "$r: no reason"
  jq -e ".threshold_ratio.$r == null" out.json >/dev/null || fail "$r: ratio not null"
done
grep -q "RA none" err.txt || fail "stderr does not say so: $(cat err.txt)"
echo "ok: null thresholds with their reason"

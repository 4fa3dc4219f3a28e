# --objective selectivity (docs/fibres.md, "Designed for selectivity"): the weights and the
# pulse's shape, scored on a population; never worse than the AF optimum on it; the design
# is a document fiber-threshold reads back (its pulse), and the held-out index it reports is
# the one fiber-threshold finds on a population of the next seed; deterministic.
# Under the sanitizers the design's search runs in the unit test "a selectivity design below
# every I50's current limit ..." (fibre-tests): this script's five seconds of fibre work
# would take over a minute there (docs/testing.md).
if [[ ${TP_SANITIZED:-0} == 1 ]]; then
  echo "skipped under the sanitizers"
  exit 0
fi
args=(--mode SAI --objective selectivity --electrodes 4 --population 3 --max-evaluations 10)
optimize-weights "${args[@]}" > a.json 2> err.txt
jq -e '.objective == "selectivity" and .selectivity_search.evaluations <= 10 and
  (.pulse.phases | length) >= 2' a.json >/dev/null ||
  fail "objective, evaluations or pulse: $(jq -c '[.objective, .selectivity_search.evaluations, .pulse]' a.json)"
jq -e '.selectivity.index >= .starts[0].design_population.index' a.json >/dev/null ||
  fail "worse than the AF optimum: $(jq -c '[.selectivity.index, .starts[0].design_population.index]' a.json)"
jq -e '(.weights | add | fabs) < 1e-12 and (.weights | map(fabs) | max) == 1' a.json >/dev/null ||
  fail "weights: $(jq -c .weights a.json)"
jq -e '.selectivity.held_out.seed == 2 and .selectivity.held_out.index > 0' a.json >/dev/null ||
  fail "held out: $(jq -c .selectivity.held_out a.json)"
grep -q "SAI selectivity .* (AF optimum: .*; held out: " err.txt || fail "stderr: $(cat err.txt)"
# The held-out population is fiber-threshold's with the next seed, for the document's pulse.
fiber-threshold --config a.json --population 3 --seed 2 --tolerance 0.01 > /dev/null 2> ft.txt
held=$(jq -r '.selectivity.held_out.index' a.json)
grep -q "selectivity $held (" ft.txt || fail "fiber-threshold's held-out index is not $held: $(cat ft.txt)"
echo "ok: $(cat err.txt)"
optimize-weights "${args[@]}" > b.json 2>/dev/null
cmp a.json b.json || fail "two runs differ"
# A pixel of a 2-D grid (--at): the pixel's AF optimum the start, the population over the grid.
optimize-weights --mode SAI --objective selectivity --grid 3x3 --pitch 2 --pad 1x1 --at 0,0 \
  --population 3 --max-evaluations 10 > px.json 2>/dev/null
jq -e '.at_mm == [0, 0] and .selectivity.index >= .starts[0].design_population.index and
  (.starts | length) == 1' px.json >/dev/null ||
  fail "pixel: $(jq -c '[.at_mm, .selectivity.index, .starts[0].design_population.index]' px.json)"

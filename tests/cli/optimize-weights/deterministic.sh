# Same input, byte-identical output (no timings unless --timing).
optimize-weights --mode SAI > a.json 2> /dev/null
optimize-weights --mode SAI > b.json 2> /dev/null
cmp a.json b.json || fail "output differs between runs"
optimize-weights --mode SAI --timing 2> /dev/null | jq -e '.solver.time_s > 0' > /dev/null || fail "--timing"
echo "ok"

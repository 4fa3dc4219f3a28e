# The same input gives byte-identical output, whatever the number of threads: thresholds
# are points of a fixed amplitude lattice, and ties go to the first placement.
in=$TP_INPUTS/sai-optimum.json
fiber-threshold --config "$in" > a.json
fiber-threshold --config "$in" > b.json
cmp a.json b.json || fail "output differs between runs"
fiber-threshold --config "$in" --threads 1 > c.json
cmp a.json c.json || fail "--threads 1 differs from every core"
fiber-threshold --config "$in" --threads 3 > d.json
cmp a.json d.json || fail "--threads 3 differs from every core"
# Doubling every weight halves every threshold exactly (the lattice is in powers of 2).
jq '.weights |= map(. * 2)' "$in" > double.json
fiber-threshold --config double.json > e.json
for r in RA SAI PC; do
  a=$(jq ".thresholds.receptors.$r.threshold_mA" a.json)
  e=$(jq ".thresholds.receptors.$r.threshold_mA" e.json)
  jq -e -n "$a == 2 * $e" >/dev/null || fail "$r: $a is not twice $e"
done
echo "ok: byte-identical across runs and threads; doubling the weights halves the thresholds"
# The same for a pattern whose thresholds fall on other lattice points, and far below 1 mA
# (x 512: the search must not land above the block threshold).
fiber-threshold --config "$TP_INPUTS/sai-weights.json" > f.json 2>/dev/null
fiber-threshold --weights 0,0,-256,512,-256,0,0,0 > g.json 2>/dev/null
for r in RA SAI PC; do
  f=$(jq ".thresholds.receptors.$r.threshold_mA" f.json)
  g=$(jq ".thresholds.receptors.$r.threshold_mA" g.json)
  jq -e -n "$f == 512 * $g" >/dev/null || fail "$r: $f is not 512 x $g"
done
echo "ok: x 512 weights give exactly 1/512 of the thresholds"

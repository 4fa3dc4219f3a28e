# Done-when of the optimize-weights issue: on the paper's array, each mode's weights, fed
# unchanged to af-field --summary, give a ratio within 1 % of the certified global optimum;
# the weights sum to zero and the PC ratio is not below 1 (Sec. 5.3).
for mode in RA SAI PC; do
  optimize-weights --mode "$mode" --certify > "$mode.json" 2> /dev/null
  af-field --config - --summary < "$mode.json" > "$mode-summary.json"
  ratio=$(jq -r ".ratios.$mode" "$mode-summary.json")
  own=$(jq -r '.ratio' "$mode.json")
  cert=$(jq -r '.certified_optimum' "$mode.json")
  sum=$(jq -r '[.weights[]] | add | fabs' "$mode.json")
  peak=$(jq -r '[.weights[] | fabs] | max' "$mode.json")
  awk -v r="$ratio" -v o="$own" -v c="$cert" -v s="$sum" -v p="$peak" -v m="$mode" 'BEGIN {
    bad = 0
    if (!(r <= 1.01 * c)) { print m ": af-field ratio " r " is not within 1% of the certified optimum " c; bad = 1 }
    if (!(r >= 0.999 * c)) { print m ": ratio " r " below the certified optimum " c "?"; bad = 1 }
    if ((r - o) > 1e-9 * o || (o - r) > 1e-9 * o) { print m ": af-field ratio " r " != optimize-weights ratio " o; bad = 1 }
    if (!(s < 1e-12)) { print m ": weights sum to " s; bad = 1 }
    if (p != 1) { print m ": max |w| is " p; bad = 1 }
    if (m == "PC" && !(r >= 1)) { print "PC ratio " r " below 1"; bad = 1 }
    printf "%s: ratio %s, certified optimum %s (%.3f%% above)\n", m, r, c, 100 * (r / c - 1)
    exit bad }' || fail "$mode"
done

# The 3-D models (fibre regions searched inside, not only on their edges): on the paper's
# array every mode's ratio is within 1 % of the certified optimum, which solves the LP at
# every sample of the target's region (its interior too for these models).
for model in rect3d point3d layered; do
  for mode in RA SAI PC; do
    optimize-weights --mode "$mode" --model "$model" --certify > "$model-$mode.json" 2> err.txt \
      || fail "$model $mode: $(cat err.txt)"
    af-field --config - --summary < "$model-$mode.json" > summary.json 2> err.txt \
      || fail "$model $mode af-field: $(cat err.txt)"
    ratio=$(jq -r ".ratios.$mode" summary.json)
    own=$(jq -r '.ratio' "$model-$mode.json")
    cert=$(jq -r '.certified_optimum' "$model-$mode.json")
    awk -v r="$ratio" -v o="$own" -v c="$cert" -v m="$model $mode" 'BEGIN {
      bad = 0
      if (!(r <= 1.01 * c)) { print m ": ratio " r " is not within 1% of the certified optimum " c; bad = 1 }
      if (!(r >= 0.999 * c)) { print m ": ratio " r " below the certified optimum " c "?"; bad = 1 }
      if ((r - o) > 1e-9 * o || (o - r) > 1e-9 * o) { print m ": af-field ratio " r " != optimize-weights ratio " o; bad = 1 }
      printf "%s: ratio %s, certified optimum %s (%.3f%% above)\n", m, r, c, 100 * (r / c - 1)
      exit bad }' || fail "$model $mode"
  done
done

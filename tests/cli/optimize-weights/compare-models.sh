# scripts/compare-models: one table row per model, each ratio the one optimize-weights
# gives for that model alone; a bad model is refused with exit 2.
"$TP_SOURCE/scripts/compare-models" --models line2d,rect3d --electrodes 4 --pitch 1.5 > table.md 2> err.txt \
  || fail "compare-models: $(cat err.txt)"
[[ $(grep -c '^| line2d |\|^| rect3d |' table.md) -eq 8 ]] || fail "expected 2 ratio rows and 6 weight rows: $(cat table.md)"
for model in line2d rect3d; do
  want=$(optimize-weights --mode SAI --model "$model" --electrodes 4 --pitch 1.5 2> /dev/null | jq -r '.ratio')
  got=$(awk -F'|' -v m=" $model " '$2 == m && NF == 9 { gsub(/ /, "", $4); print $4 }' table.md)
  awk -v a="$want" -v b="$got" 'BEGIN { exit !(a - b < 6e-5 && b - a < 6e-5) }' \
    || fail "$model SAI: table $got, optimize-weights $want"
done
# layered:SKIN rows: the layered model on a built-in skin, labelled with it.
"$TP_SOURCE/scripts/compare-models" --models layered:fingertip-dry --electrodes 4 --pitch 1.5 > layered.md 2> err.txt \
  || fail "compare-models layered: $(cat err.txt)"
want=$(optimize-weights --mode PC --model layered --skin fingertip-dry --electrodes 4 --pitch 1.5 2> /dev/null | jq -r '.ratio')
got=$(awk -F'|' '$2 == " layered (fingertip-dry) " && NF == 9 { gsub(/ /, "", $5); print $5 }' layered.md)
awk -v a="$want" -v b="$got" 'BEGIN { exit !(a - b < 6e-5 && b - a < 6e-5) }' \
  || fail "layered PC: table '$got', optimize-weights $want: $(cat layered.md)"
# A pixel on a grid, under the two 3-D half-space models: each row the ratio of
# optimize-weights --at for that model alone.
"$TP_SOURCE/scripts/compare-models" --models point3d,rect3d --grid 3x3 --pitch 2 --pad 1x1 --at 0,0 > grid.md 2> err.txt \
  || fail "compare-models on a grid: $(cat err.txt)"
for model in point3d rect3d; do
  want=$(optimize-weights --mode PC --model "$model" --grid 3x3 --pitch 2 --pad 1x1 --at 0,0 2> /dev/null | jq -r '.ratio')
  got=$(awk -F'|' -v m=" $model " '$2 == m && NF == 9 { gsub(/ /, "", $5); print $5 }' grid.md)
  awk -v a="$want" -v b="$got" 'BEGIN { exit !(a - b < 6e-5 && b - a < 6e-5) }' \
    || fail "$model PC on a grid: table '$got', optimize-weights $want: $(cat grid.md)"
done
set +e; "$TP_SOURCE/scripts/compare-models" --models line2d,nonesuch > out.md 2> err.txt; rc=$?; set -e
[[ $rc -eq 2 && $(wc -l < err.txt) -eq 1 ]] || fail "bad model: exit $rc, $(cat err.txt)"
echo "ok: $(sed -n 3p table.md)"

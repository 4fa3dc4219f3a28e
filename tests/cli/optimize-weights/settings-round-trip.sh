# A document carries exactly the model settings its conductor uses (issue 20, item 9): what
# optimize-weights writes under each model reads back into af-field, and no model key the
# model ignores is written (a layered document has no resistivity_ohm_m: its layers set it).
for model in line2d strip2d point3d rect3d layered; do
  optimize-weights --mode SAI --electrodes 4 --model "$model" > "$model.json" 2> err ||
    fail "$model: $(cat err)"
  af-field --config "$model.json" --summary > /dev/null 2> err || fail "$model: does not read back: $(cat err)"
  keys=$(jq -r '.model | keys_unsorted | join(",")' "$model.json")
  case $model in
    line2d | strip2d) want=conductor,resistivity_ohm_m,lateral_margin_mm ;;
    point3d | rect3d) want=conductor,resistivity_ohm_m,lateral_margin_mm ;;
    layered) want=conductor,lateral_margin_mm,skin ;;
  esac
  [[ $keys == "$want" ]] || fail "$model: model keys $keys, expected $want"
done
# A non-zero plane is written where it applies, and reads back.
optimize-weights --mode SAI --electrodes 4 --model rect3d --z 2 > z.json 2> err || fail "rect3d --z: $(cat err)"
[[ $(jq '.model.plane_z_mm' z.json) == 2 ]] || fail "rect3d --z 2: plane_z_mm not written"
af-field --config z.json --summary > /dev/null 2> err || fail "rect3d --z 2 does not read back: $(cat err)"
echo "ok: every model's document reads back, with only the settings it uses"
# A layered document written before settings were checked carries the default resistivity
# (3 ohm m), which it ignored: it still reads; any other value is refused.
jq '.model.resistivity_ohm_m = 3.0' layered.json > legacy.json
af-field --config legacy.json --summary > /dev/null 2> err || fail "legacy layered document: $(cat err)"
jq '.model.resistivity_ohm_m = 2.0' layered.json > other.json
refuses 2 --says "model.resistivity_ohm_m: applies to the uniform models" -- af-field --config other.json --summary
echo "ok: a legacy layered document (3 ohm m) reads; 2 ohm m is refused"

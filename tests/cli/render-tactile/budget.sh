# An image that asks more than the device delivers (every pad lit in every primary that
# has a pattern): rates lowered and said so, every lit pixel delivered (the record), no
# pulse deferred; patterns fired together share no pad, and their crosstalk, evaluated
# again by af-field, is within the bound.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
# Every pixel at full intensity in each primary its pattern exists for.
px=$(jq -r '.pixels[] | "\(.pad % 8),\(.pad / 8 | floor),"
    + ([.patterns.RA, .patterns.SAI, .patterns.PC] | map(if .feasible == false then 0 else 255 end) | join(","))' "$BANK")
mkpng full.png 8 8 $px
render-tactile --bank "$BANK" --profile profile.json --duration 1 full.png > full.json 2> full.err \
  || fail "render-tactile: $(cat full.err)"
grep -q "rates lowered" full.err || fail "no word of lowered rates: $(cat full.err)"
grep -q "refresh RA .* Hz (30 requested" full.err || fail "no refresh printed: $(cat full.err)"
lit=$(jq '[.pixels[].patterns[] | select(.feasible != false)] | length' "$BANK")
stimctl --port emu --emu-channels 64 --record rec.jsonl < full.json 2> err.txt || fail "stimctl: $(cat err.txt)"
counts=$(jq -c '[.patterns[] | [.count - 1, .count]]' full.json)
check_mix_record rec.jsonl full.json "$counts"
check_pixels rec.jsonl full.json
# Every lit (pixel, primary) in a pattern that was delivered.
delivered=$(jq -s --slurpfile d full.json '[map(.pattern) | unique[] as $i | $d[0].patterns[$i] | .primary as $p | .pixels[] | "\($p) \(.)"] | unique | length' rec.jsonl)
[[ $delivered -eq $lit ]] || fail "$delivered of $lit lit patterns delivered"
[[ $(jq -s 'map(.slip_us) | max' rec.jsonl) -eq 0 ]] || fail "a pulse was deferred"
# Fired together: no shared pad; crosstalk both ways at most 0.1 (af-field, each member's
# weights x its current, at the other's peak; RA vertical, SAI and PC along x).
jq -e --slurpfile b "$BANK" '[.patterns[] | .primary as $p
    | [.pixels[] | $b[0].pixels[.].patterns[$p].weights | map(if . != 0 then 1 else 0 end)] | transpose | map(add) | max]
    | max <= 1' full.json > /dev/null || fail "patterns fired together share a pad"
pairs=0
for primary in RA SAI PC; do
  # The first group of this primary with several members: every ordered pair.
  group=$(jq -c --arg p "$primary" '[.patterns[] | select(.primary == $p and (.pixels | length) > 1)][0]' full.json)
  [[ $group != null ]] || fail "no $primary pixels fired together"
  n=$(jq '.pixels | length' <<< "$group")
  col=$([[ $primary == RA ]] && echo 4 || echo 3)  # af_v or af_h
  for ((a = 0; a < n; ++a)); do for ((t = 0; t < n; ++t)); do
    ((a == t)) && continue
    read -r pa ia pt it < <(jq -r --argjson a $a --argjson t $t '"\(.pixels[$a]) \(.pixel_currents_mA[$a]) \(.pixels[$t]) \(.pixel_currents_mA[$t])"' <<< "$group")
    af() {  # af PIXEL AT_PIXEL: pixel's weights' AF at at-pixel's peak
      jq --argjson s "$1" --arg p "$primary" 'del(.bank, .pixels) + {weights: input.pixels[$s].patterns[$p].weights}' "$BANK" "$BANK" > w.json
      read -r x y z < <(jq -r --argjson t "$2" --arg p "$primary" '.pixels[$t].patterns[$p].peak | "\(.x_mm) \(.y_mm) \(.z_mm)"' "$BANK")
      af-field --config w.json --amplitude 1 --x "$x:$x:1" --y "$y:$y:1" --z "$z" | tail -1 | cut -d, -f"$col"
    }
    c=$(awk -v ia="$ia" -v it="$it" -v x="$(af "$pa" "$pt")" -v own="$(af "$pt" "$pt")" \
      'BEGIN { v = ia * x / (it * own); if (v < 0) v = -v; printf "%.6f", v }')
    awk -v c="$c" 'BEGIN { exit !(c <= 0.1) }' || fail "$primary: pixel $pa onto $pt: crosstalk $c"
    pairs=$((pairs + 1))
  done; done
done
echo "ok: $lit lit patterns, all delivered; $pairs pairs fired together within 0.1 (af-field): $(cat full.err)"
# The figure of what was delivered (scripts/plot-render), where gnuplot is.
if command -v gnuplot > /dev/null; then
  "$TP_SOURCE/scripts/plot-render" full.json rec.jsonl -o fig.png 2> plot.err || fail "plot-render: $(cat plot.err)"
  [[ $(head -c 4 fig.png | od -An -c | tr -d ' ') == 211PNG ]] || fail "plot-render wrote no PNG"
  refuses 2 --says "not render-tactile's" -- "$TP_SOURCE/scripts/plot-render" "$TP_INPUTS/stimulus-ok.json" rec.jsonl
  echo "ok: plot-render: $(cat plot.err)"
fi

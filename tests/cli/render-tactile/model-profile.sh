# Without --profile: each primary's range from the fibre model, a warning on stderr.  A
# pure-G pixel at full intensity gets comfort = 2 x the SAI threshold that fiber-threshold
# finds for the same pattern through its peak (the centre pixel, pad 27); --comfort-factor
# scales it, the current limit caps it; refusals stay one line.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
[[ $COLUMNS == 8 ]] || skip "the 8 x 8 bank's centre pixel"
mkpng g.png 8 8 "3,3,0,255,0"
render-tactile --bank "$BANK" --duration 1 g.png > g.json 2> g.err || fail "render-tactile: $(cat g.err)"
grep -q "^render-tactile: warning: no --profile: .*SAI .* at pad 27; run calibrate" g.err \
  || fail "no warning naming the model's ranges: $(cat g.err)"
# The peer: fiber-threshold on pad 27's SAI pattern, through its peak.
jq '.pixels[27].patterns.SAI as $p | .weights = $p.weights
    | .focus = {x_mm: $p.peak.x_mm, z_mm: $p.peak.z_mm} | del(.pixels, .bank)' "$BANK" > sai27.json
fiber-threshold --config sai27.json > th.json 2> th.err || fail "fiber-threshold: $(cat th.err)"
T=$(jq '.thresholds.receptors.SAI.threshold_mA' th.json)
jq -e --argjson t "$T" '.pixels == [27] and .primary == "SAI"
    and ((.pixel_currents_mA[0] - 2 * $t) | fabs) < 1e-12' g.json > /dev/null \
  || fail "full SAI at pad 27: $(jq -c .pixel_currents_mA g.json) mA, model threshold $T mA"
# Half intensity: T + 128/255 x (2T - T); --comfort-factor 3: 3T.
mkpng h.png 8 8 "3,3,0,128,0"
render-tactile --bank "$BANK" --comfort-factor 3 h.png > h.json 2> h.err || fail "$(cat h.err)"
jq -e --argjson t "$T" '((.pixel_currents_mA[0] - ($t + 128 / 255 * 2 * $t)) | fabs) < 1e-12' h.json > /dev/null \
  || fail "half SAI, factor 3: $(jq -c .pixel_currents_mA h.json) mA, model threshold $T mA"
# PC's comfort at 10 x its threshold would pass the 2 mA limit: held there, and said.
mkpng pc.png 8 8 "3,3,0,0,255"
render-tactile --bank "$BANK" --comfort-factor 10 pc.png > pc.json 2> pc.err || fail "$(cat pc.err)"
grep -q "PC .* to 2 mA (comfort held at the current limit)" pc.err || fail "PC not held: $(cat pc.err)"
jq -e '.pixel_currents_mA == [2]' pc.json > /dev/null || fail "PC: $(jq -c .pixel_currents_mA pc.json)"
# Refusals: one line, no warning before it.
mkpng black.png 8 8
refuses 2 --says "no pixel is lit" -- render-tactile --bank "$BANK" black.png
refuses 2 --says "--comfort-factor: applies without --profile only" -- \
  render-tactile --bank "$BANK" --profile profile.json --comfort-factor 3 g.png
refuses 2 --says "--comfort-factor: 1 outside [1.1, 10]" -- render-tactile --bank "$BANK" --comfort-factor 1 g.png
echo "ok: the model's SAI threshold $T mA, comfort 2 x; $(head -n 1 g.err)"

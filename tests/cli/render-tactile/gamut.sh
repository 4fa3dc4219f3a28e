# The gamut (issue 40, item 4; docs/rendering.md "The gamut"): optimize-weights --bank
# --population N carries each mode's recruitment; render-tactile maps every requested colour
# to the mode intensities nearest it, and says how near.  Checked: the recruitment's
# reference is fiber-threshold's threshold for the same pattern through its peak (the peer);
# the document's intensities predict, with the document's colours, exactly the errors it
# reports, and the count outside is the count of errors above the tolerance; a colour made
# of the modes' own colours is met; a sequence's frames are mapped alike, by --sequence and
# by --frames; a bank without recruitment is said to render as given.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
optimize-weights --bank --grid 4x4 --pitch 2 --pad 1x1 --neighbourhood 3 --population 3 \
  > rb.json 2> rb.err || fail "optimize-weights --population: $(cat rb.err)"
grep -q "^optimize-weights: recruitment, 3 afferents a class about each mode's centre pixel" rb.err \
  || fail "no recruitment line: $(cat rb.err)"
jq -e '.recruitment.population == 3 and ([.recruitment.modes[] | .thresholds_mA[]
       | length == 3 and (map(. // 1e300) | . == sort)] | length == 9 and all)' rb.json > /dev/null \
  || fail "recruitment: $(jq -c .recruitment rb.json)"
# The peer: fiber-threshold on the SAI mode's pattern at its pad, through its peak.
P=$(jq '.recruitment.modes.SAI.pad' rb.json)
jq --argjson k "$P" '.pixels[$k].patterns.SAI as $p | .weights = $p.weights
    | .focus = {x_mm: $p.peak.x_mm, z_mm: $p.peak.z_mm} | del(.pixels, .bank, .recruitment)' rb.json > sai.json
fiber-threshold --config sai.json > th.json 2> th.err || fail "fiber-threshold: $(cat th.err)"
jq -e --slurpfile t th.json '(.recruitment.modes.SAI.reference_mA / $t[0].thresholds.receptors.SAI.threshold_mA - 1
       | fabs) < 0.01' rb.json > /dev/null \
  || fail "SAI reference $(jq .recruitment.modes.SAI.reference_mA rb.json) mA, fiber-threshold's $(jq .thresholds.receptors.SAI.threshold_mA th.json) mA"

# A picture: pure RA, pure SAI, pure PC and grey pixels around the centre (pad 5 = (1, 1)).
mkpng pic.png 4 4 "1,1,255,0,0" "2,1,0,255,0" "1,2,0,0,255" "2,2,128,128,128"
render-tactile --bank rb.json --profile profile.json pic.png > pic.json 2> pic.err \
  || fail "render-tactile: $(cat pic.err)"
grep -q "^render-tactile: gamut: [0-9]* of 4 pixels asked for outside the modes' gamut (error up to" pic.err \
  || fail "no gamut line: $(cat pic.err)"
# Each requested pixel's intensities, from the patterns (none: off), predicted with the
# colours (a mode on: its onset colour, plus its intensity times the way to its full one),
# against the request: the error reported, for every pixel asked for, lit or not.
jq -e '.gamut.colours as $c | .gamut.onset_colours as $o | .gamut as $g
  | [.patterns[] | .primary as $m | range(0; .pixels | length) as $i
     | {pad: .pixels[$i], m: $m, v: .intensities[$i]}] as $lit
  | {"5": [1,0,0], "6": [0,1,0], "9": [0,0,1], "10": [128/255,128/255,128/255]} as $ask
  | all($ask | to_entries[]; (.key | tonumber) as $pad | .value as $r
        | ([$lit[] | select(.pad == $pad) | {(.m): .v}] | add // {}) as $v
        | ([range(0;3) | . as $k
            | (["RA","SAI","PC"] | map(($v[.] // 0) as $x
                | if $x > 0 then $o[.][$k] + $x * ($c[.][$k] - $o[.][$k]) else 0 end) | add)
              - $r[$k]] | map(. * .) | add | sqrt) as $e
        | (($e - $g.error[$pad]) | fabs) < 1e-9)
    and $g.requested == 4 and $g.outside == ($g.error | map(select(. > $g.tolerance)) | length)' pic.json > /dev/null \
  || fail "the intensities do not give the errors reported: $(jq -c '.gamut' pic.json)"
# The SAI mode's own colour at 60 % of the way from its onset is inside: met within the
# tolerance.
C=$(jq -r '.gamut as $g | [range(0;3) | $g.onset_colours.SAI[.] + 0.6 * ($g.colours.SAI[.] - $g.onset_colours.SAI[.])]
           | map(. * 255 | round) | join(",")' pic.json)
mkpng in.png 4 4 "1,1,$C"
render-tactile --bank rb.json --profile profile.json in.png > in.json 2> in.err || fail "$(cat in.err)"
jq -e '.gamut.outside == 0 and .gamut.error[5] < .gamut.tolerance' in.json > /dev/null \
  || fail "SAI's own colour ($C) outside: $(jq -c '.gamut | del(.error)' in.json)"
# What was delivered beside the gamut's error (scripts/plot-render's fifth panel).
if command -v gnuplot > /dev/null; then
  stimctl --port emu --emu-channels 16 --record rec.jsonl < pic.json 2> st.err || fail "stimctl: $(cat st.err)"
  "$TP_SOURCE/scripts/plot-render" pic.json rec.jsonl -o fig.png 2> plot.err || fail "plot-render: $(cat plot.err)"
  [[ $(pngtopnm fig.png | head -c 32 | sed -n 2p) == "1750 400" ]] \
    || fail "plot-render: not five panels of 350 x 400: $(pngtopnm fig.png | head -c 32 | sed -n 2p)"
fi
# A sequence's frames are mapped as a still's image: its stimulus starts from frame 1's
# mapped intensities, the amplitudes --frames plays for that frame (a PNG, and the same
# frame as a JSON line on stdin), and stderr tells the mapping over the frames.
render-tactile --bank rb.json --profile profile.json --sequence pic.png in.png > seq.json 2> seq.err \
  || fail "--sequence: $(cat seq.err)"
grep -q "^render-tactile: gamut: [0-9]* of 5 pixels asked for outside the modes' gamut (.*) over 2 frames; mapped in [0-9.]* ms$" seq.err \
  || fail "no sequence gamut line: $(cat seq.err)"
jq -e '.gamut.frames == 2 and .gamut.requested == 5 and (.gamut.error | length) == 16' seq.json > /dev/null \
  || fail "the sequence's gamut: $(jq -c '.gamut | del(.error)' seq.json)"
render-tactile --bank rb.json --profile profile.json --frames seq.json pic.png > f.jsonl 2> f.err \
  || fail "--frames: $(cat f.err)"
grep -q "^render-tactile: gamut: .* over 1 frame$" f.err || fail "no --frames gamut line: $(cat f.err)"
jq -nc '{rgb: [range(16) | if . == 5 then [255,0,0] elif . == 6 then [0,255,0] elif . == 9 then [0,0,255]
                           elif . == 10 then [128,128,128] else [0,0,0] end]}' > line.jsonl
render-tactile --bank rb.json --profile profile.json --frames seq.json - < line.jsonl > l.jsonl 2> l.err \
  || fail "--frames -: $(cat l.err)"
for played in f.jsonl l.jsonl; do
  jq -se --slurpfile s seq.json 'length == 1 and (.[0].amplitudes | length) == ($s[0].start_amplitudes_mA | length)
      and ([.[0].amplitudes, $s[0].start_amplitudes_mA] | transpose | all(((.[0] - .[1]) | fabs) < 1e-9))
      and ($s[0].start_amplitudes_mA | any(. > 0))' "$played" > /dev/null \
    || fail "$played: $(cat "$played") against the sequence's start $(jq -c .start_amplitudes_mA seq.json)"
done
# A recruitment without modes lights nothing: refused, naming why (not "all black").
jq '.recruitment.modes = {}' rb.json > none.json
refuses 2 --says "pic.png: 4 pixels ask for colour, and the nearest the modes come to each is nothing (RA: the bank's recruitment has no RA mode; SAI: the bank's recruitment has no SAI mode; PC: the bank's recruitment has no PC mode)" \
  -- render-tactile --bank none.json --profile profile.json pic.png
# Another pulse than the recruitment's is said.
render-tactile --bank rb.json --profile profile.json --width 100 pic.png > w.json 2> w.err || fail "$(cat w.err)"
grep -q "^render-tactile: note: the bank's recruitment was sampled with a 200 us biphasic pulse, not this render's 100 us biphasic pulse: the gamut's colours are that pulse's" w.err \
  || fail "no pulse note: $(cat w.err)"
# Without recruitment in the bank: rendered as given, and said.
mkpng g.png "$COLUMNS" "$ROWS" "1,1,0,255,0"
render-tactile --bank "$BANK" --profile profile.json g.png > g.json 2> g.err || fail "$(cat g.err)"
grep -q "^render-tactile: note: the bank carries no recruitment (optimize-weights --bank --population N)" g.err \
  || fail "no note: $(cat g.err)"
jq -e 'has("gamut") | not' g.json > /dev/null || fail "a gamut without recruitment"
echo "ok: $(grep gamut: pic.err)"

# A 30 fps sequence of 60 frames, a bar of SAI moving across the 8 x 8 array: its stimulus
# (every pixel the frames light; a column's pixels lit alike fire together where they share
# no pad, in 32 patterns of two; starting from the first frame), then the frames played
# live through stimctl.  From the record: frames applied in order, each
# column's first pulse within one frame period (plus one pulse period, the record's
# sampling) of its frame's time; the last frame's intensities at the end; 60 frames.
source "$TP_SOURCE/tests/cli/render-tactile/common.sh"
frames=()
for ((k = 0; k < 60; ++k)); do
  c=$((k * 8 / 60)) px=()
  for ((r = 0; r < 8; ++r)); do px+=("$c,$r,0,255,0"); done
  f=$(printf 'bar-%02d.png' "$k")
  mkpng "$f" 8 8 "${px[@]}"
  frames+=("$f")
done
render-tactile --bank "$BANK" --profile profile.json --sequence "${frames[@]}" > bar.json 2> seq.err \
  || fail "--sequence: $(cat seq.err)"
jq -e '(.patterns | length) == 32 and all(.patterns[]; .primary == "SAI" and (.pixels | length) == 2
      and (.pixels | map(. % 8) | unique | length) == 1)
    and ([.patterns[].pixels[]] | sort) == [range(0; 64)]
    and (.start_amplitudes_mA | length) == 32
    and ([range(0; 32) as $i | select(.start_amplitudes_mA[$i] > 0) | .patterns[$i].pixels[0] % 8] | unique) == [0]
    and ([.start_amplitudes_mA[] | select(. > 0)] | unique) == [0.9]
    and .array.grid == {columns: 8, rows: 8, pitch_mm: 2, row_pitch_mm: 2}' bar.json > /dev/null \
  || fail "the sequence's stimulus: $(jq -c '{n: (.patterns | length), s: .start_amplitudes_mA, a: .array}' bar.json)"
# Each pattern at full intensity: its pixels' currents times their weights, nothing else.
jq 'del(.start_amplitudes_mA) | .patterns |= map(.count = 1)' bar.json \
  | stimctl --port emu --emu-channels 64 --record full.jsonl 2> /dev/null || fail "bar.json at full intensity"
[[ $(lines full.jsonl) -eq 32 ]] || fail "full intensity: $(lines full.jsonl) pulses, expected 32"
check_pixels full.jsonl bar.json
period=$(jq '.patterns[0].pulse.frequency_hz | 1 / .' bar.json)
echo "ok: 32 patterns of a column's two pixels, one pulse every $period s: $(tail -1 seq.err)"

render-tactile --bank "$BANK" --profile profile.json --frames bar.json --fps 30 "${frames[@]}" 2> play.err \
  | stimctl --port emu --emu-channels 64 --live --stimulus bar.json --record rec.jsonl 2> live.err \
  || fail "live: $(cat play.err live.err)"
grep -q "60 live frames" live.err || fail "frames: $(cat live.err)"
# Column c lights from frame ceil(7.5 c), at ceil(7.5 c) / 30 s after the first frame.
jq -se --slurpfile d bar.json --argjson T "$period" '
  ($d[0].patterns | map(.pixels[0] % 8)) as $col
  | map(select(.currents_mA | map(fabs) | max > 0) | {t: .t_s, c: $col[.pattern]})
  | group_by(.c) | map({c: .[0].c, first: (map(.t) | min), last: (map(.t) | max)}) as $s
  | if ($s | map(.c)) != [range(0; 8)] then error("columns lit: \($s | map(.c))") else . end
  | [$s[] | .first - ((.c * 7.5 | ceil) / 30)] as $lag
  | ($lag[1:] | min) as $offset
  | ([$lag[] | . - $offset] | max) as $late
  | if $late > 1 / 30 + $T then error("a column lit \($late) s after its frame (offsets \($lag))") else . end
  | if [range(1; 8) as $c | $s[$c].first > $s[$c - 1].first] | all | not then error("out of order") else . end
  | if [range(1; 8) as $c | $s[$c - 1].last <= $s[$c].first + 1 / 30 + $T] | all | not
    then error("a column still lit after the next one: \($s)") else . end
  | true' rec.jsonl > /dev/null 2> order.err || fail "record: $(cat order.err)"
# The last frame: each pattern's last pulse at 0.9 mA on its pad if in column 7, else dark.
jq -se --slurpfile d bar.json '
  group_by(.pattern) | map(.[-1]) | map(. as $r | $d[0].patterns[$r.pattern].pixels[0] as $pad
    | ($r.currents_mA | map(fabs) | max) as $peak
    | if $pad % 8 == 7 then (($r.currents_mA[$pad] - 0.9) | fabs) <= 0.000978 else $peak == 0 end)
  | all' rec.jsonl > /dev/null || fail "the last frame's intensities are not the record's last pulses"
echo "ok: $(cat play.err); $(cat live.err)"

# A measured profile's comfort has every digit (calibrate's 0.9094947017729282 mA): a frame
# at full intensity asks exactly its pattern's amplitude, and the device takes it.  (Frames
# written with 10 digits asked 2.7e-11 more, and stimctl refused the first.)
jq '.primaries.SAI.comfort_mA = 0.9094947017729282' profile.json > digits.json
render-tactile --bank "$BANK" --profile digits.json --sequence "${frames[@]:0:3}" > bar9.json 2> /dev/null \
  || fail "sequence with a measured profile"
render-tactile --bank "$BANK" --profile digits.json --frames bar9.json --fps 30 "${frames[@]:0:3}" 2> play9.err \
  | stimctl --port emu --emu-channels 64 --live --stimulus bar9.json 2> live9.err \
  || fail "live with a measured profile: $(cat play9.err live9.err)"
grep -q "3 live frames" live9.err || fail "frames: $(cat live9.err)"
echo "ok: full intensity with a measured comfort: $(cat live9.err)"

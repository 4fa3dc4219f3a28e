# 256 patterns, the most a device holds, uploaded and played in turn (issue 22), through a
# real line (stim-emu, or the firmware in QEMU with TP_DEVICE=firmware): mix-stimuli of 256
# stimuli, pattern i at phase i ms, one pulse each (50 + 50 us, every 256 ms), its own
# currents: channel i mod 8 at +a_i, the next at -a_i, a_i = 0.1 + 0.006 i mA.  The record
# must hold each pattern once, in order, 1 ms apart, with its own currents within one DAC
# step (0.977 uA).
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make-pulse --amplitude 1 --frequency 3.90625 --width 50 --balance-width 50 --count 1 \
  < "$TP_INPUTS/ra-weights.json" > base.json 2> /dev/null || fail "make-pulse"
jq -c 'range(0; 256) as $i | (0.1 + 0.006 * $i) as $a
  | .currents_mA = [range(0; 8) | if . == ($i % 8) then $a elif . == (($i + 1) % 8) then -$a else 0 end]
  | .amplitude_mA = $a' base.json | split -l 1 -d -a 3 - part.
[[ $(ls part.* | wc -l) -eq 256 ]] || fail "not 256 parts"
phases=$(seq -s, 0 1000 255000)
mix-stimuli --phase "$phases" part.* > mix.json 2> mix.err || fail "mix-stimuli: $(cat mix.err)"
echo "ok: $(cat mix.err)"
start_emu --record rec.jsonl
stimctl --port "$PORT" < mix.json 2> err.txt || fail "stimctl: $(cat err.txt)"
sleep 0.2
stop_emu
[[ $(lines rec.jsonl) -eq 256 ]] || fail "$(lines rec.jsonl) pulses recorded, expected 256"
jq -se '
  (map(.pattern) == [range(0; 256)] or error("not in turn: \(map(.pattern))")),
  (map(.t_s * 1e6 | round) == [range(0; 256) | . * 1000] or error("not 1 ms apart")),
  (map(. as $r | ($r.pattern) as $i | (0.1 + 0.006 * $i) as $a
       | [range(0; 8) | ($r.currents_mA[.] - (if . == ($i % 8) then $a elif . == (($i + 1) % 8) then -$a else 0 end)) | fabs] | max)
   | max | (. <= 0.000978 or error("a current \(.) mA off its pattern"))),
  (map(.slip_us) | max == 0 or error("deferred"))
  | true' rec.jsonl > /dev/null 2> check.err || fail "record: $(cat check.err)"
echo "ok: 256 patterns in turn, each its own currents within one DAC step: $(cat err.txt)"

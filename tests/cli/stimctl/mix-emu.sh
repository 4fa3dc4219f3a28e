# The README's mix on the in-process emulator: RA at 30 Hz and SAI at 200 Hz for 2 s, the
# schedule checked from the record alone; then both patterns due at once (phases 0, 0),
# which the device defers within its bound.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_mix mix.json
stimctl --port emu --duration 2 --record rec.jsonl < mix.json 2> err.txt || fail "stimctl: $(cat err.txt)"
check_mix_record rec.jsonl mix.json '[[59, 61], [399, 401]]'
grep -q "460 of 460 pulses on 8 channels of 2 patterns" err.txt || fail "summary: $(cat err.txt)"
grep -q "^mix-stimuli: 2 patterns on 8 channels" mix.err || fail "mix-stimuli's line: $(cat mix.err)"
# A mix of one input is one pattern, said so.
mix-stimuli ra.json > one.json 2> one.err || fail "mix-stimuli of one: $(cat one.err)"
grep -q "^mix-stimuli: 1 pattern on 8 channels" one.err || fail "mix-stimuli of one: $(cat one.err)"
echo "ok: $(cat err.txt)"
make_mix mix0.json --phase 0,0
stimctl --port emu --duration 2 --record rec0.jsonl < mix0.json 2> err0.txt || fail "stimctl: $(cat err0.txt)"
check_mix_record rec0.jsonl mix0.json '[[59, 61], [399, 401]]'
deferred=$(jq -s 'map(select(.slip_us > 0)) | length' rec0.jsonl)
[[ $deferred -ge 1 ]] || fail "phases 0, 0: no pulse was deferred"
slip=$(jq -s 'map(.slip_us) | max' rec0.jsonl)
[[ $slip -eq 500 ]] || fail "phases 0, 0: the largest slip is $slip us, expected 500 (RA's 400 us and the gap)"
echo "ok: phases 0, 0: $deferred SAI pulses deferred, at most $slip us"
# What no single pattern's check sees: two patterns within the RMS limit alone, above it
# on one electrode together.  Refused before anything is sent.
make-pulse --amplitude 2 --frequency 100 --width 800 --count 100 < "$TP_INPUTS/sai-weights.json" > heavy.json 2> /dev/null \
  || fail "heavy pattern refused alone"
refuses 2 --says "RMS current" -- mix-stimuli heavy.json heavy.json
jq '{format: "tactile-primaries/stimulus/2", gap_us: 100, patterns: [del(.format), (del(.format) | .phase_us = 5000)]}' \
  heavy.json > two.json 2> /dev/null || fail "jq"
refuses 2 --says "RMS current" --stdin two.json -- stimctl --port emu --record none.jsonl
[[ ! -s none.jsonl ]] || fail "a pulse was delivered"
echo "ok: two patterns over the RMS limit together refused by mix-stimuli and by stimctl"
# One pattern with a phase: sent as a table of one, its first pulse at the phase.
mix-stimuli --phase 5000 ra.json > late.json 2> /dev/null || fail "mix-stimuli --phase, one input"
stimctl --port emu --record late.jsonl < late.json 2> late.err || fail "stimctl: $(cat late.err)"
[[ $(head -1 late.jsonl | jq .t_s) == 0.005 && $(lines late.jsonl) -eq 60 ]] \
  || fail "one pattern at phase 5 ms: first at $(head -1 late.jsonl | jq .t_s) s, $(lines late.jsonl) pulses"
echo "ok: one pattern at phase 5 ms: 60 pulses from 0.005 s"
# That table's gap is checked as any table's: outside 100 to 1000 us, or not whole, exit 2.
jq '.gap_us = 5000' late.json > gap-far.json
refuses 2 --says "gap_us: 5000 us" --stdin gap-far.json -- stimctl --port emu
jq '.gap_us = 100.7' late.json > gap-frac.json
refuses 2 --says "gap_us: 100.7 us" --stdin gap-frac.json -- stimctl --port emu

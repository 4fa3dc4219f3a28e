# mix-stimuli's refusals: one line on stderr, exit 2, nothing on stdout.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
W=$TP_INPUTS/sai-weights.json
make-pulse --amplitude 0.2 --frequency 1000 --width 300 --count 10 < "$W" > fast.json 2> /dev/null || fail "fast"
make-pulse --amplitude 0.2 --frequency 30 --count 10 < "$W" > slow.json 2> /dev/null || fail "slow"
jq '.currents_mA = .currents_mA[0:4] | .channels = 4 | .currents_mA[3] = 0.1' slow.json > four.json
refuses 2 --says "cannot fit their periods" -- mix-stimuli fast.json fast.json
refuses 2 --says "channels, pattern 0 has 8" -- mix-stimuli slow.json four.json
refuses 2 --says "--phase: 1 phases for 2 patterns" -- mix-stimuli slow.json slow.json --phase 0
refuses 2 --says "phase 40000 us outside" -- mix-stimuli slow.json slow.json --phase 0,40000
refuses 2 --says "gap_us: 50 us" -- mix-stimuli slow.json slow.json --gap 50
refuses 2 --says "more than once" --stdin slow.json -- mix-stimuli - -
refuses 2 --says "malformed" -- mix-stimuli slow.json "$TP_INPUTS/malformed.json"
mix-stimuli slow.json slow.json > m.json 2> /dev/null || fail "a mix"
refuses 2 --says "already a mix" -- mix-stimuli m.json slow.json
# Twelve patterns whose deferrals cannot be bounded within 1 ms (coprime rates, phases 0).
files=()
for k in $(seq 12); do
  make-pulse --amplitude 0.05 --frequency $((37 + 2 * k)) --width 100 --count 10 < "$W" > p$k.json 2> /dev/null || fail "p$k"
  files+=(p$k.json)
done
refuses 2 --says "deferred by more than 1000 us" -- mix-stimuli "${files[@]}" --phase "$(printf '0,%.0s' $(seq 11))0"
# 257 patterns: more than a device holds.
refuses 2 --says "257 inputs, more than a device holds" -- mix-stimuli $(for _ in $(seq 257); do echo slow.json; done)
echo "ok: mix-stimuli's refusals"

# No delivered current exceeds the stimulus's max_current_mA: the host quantises toward
# zero where the nearest DAC code would cross the limit (keeping the codes' sum at zero),
# for the stimulus and for every live frame, and the reported peak is what was delivered.
# The balancing phase is never above the main phase.  Through a real pty, against
# stim-emu and, with TP_DEVICE=firmware, the firmware.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
# check_peak REC LIMIT: every phase's current within LIMIT mA (main phase, and the
# balancing phase's current from its charge: main x width + balance x balance width).
check_peak() {
  jq -se --argjson lim "$2" '
    (map(.currents_mA | map(fabs) | max) | max) as $peak
    | if $peak <= $lim and $peak > 0 then true else error("peak \($peak) mA, limit \($lim) mA") end
    ' "$1" > /dev/null || fail "$1: $(jq -se 'map(.currents_mA | map(fabs) | max) | max' "$1") mA delivered, limit $2 mA"
}
reported_peak() { sed -n 's/.*peak \([0-9.]*\) mA.*/\1/p' "$1"; }

# 1. The pipeline: SAI weights for 0.5 mA, a 0.5 mA pulse.  The nearest code of
# 0.5 mA (977 nA a step) is 512, 0.500224 mA; delivered must be 511, 0.499247 mA.
optimize-weights --mode SAI --max-current 0.5 > w.json 2> /dev/null || fail "optimize-weights"
make-pulse --amplitude 0.5 --duration 0.02 < w.json > a.json 2> /dev/null || fail "make-pulse"
jq -e '.max_current_mA == 0.5' a.json > /dev/null || fail "stimulus limit: $(jq .max_current_mA a.json)"
start_emu --record a.jsonl
stimctl --port "$PORT" < a.json 2> a.err || fail "a: $(cat a.err)"
sleep 0.2
stop_emu
[[ $(lines a.jsonl) -gt 0 ]] || fail "a: nothing delivered"
check_peak a.jsonl 0.5
awk -v p="$(reported_peak a.err)" 'BEGIN { exit !(p > 0.499 && p <= 0.5) }' || fail "a: reported $(tail -1 a.err)"
echo "ok: SAI at its 0.5 mA limit: delivered $(jq -s 'map(.currents_mA | map(fabs) | max) | max' a.jsonl) mA, reported $(reported_peak a.err) mA"

# 2. Live frames at the limit: each quantised within it.  (The stimulus says 0.5 mA.)
start_emu --record b.jsonl
{ sleep 0.1
  for k in 1 2 3; do echo '{"currents_mA": [0, 0, -0.25, 0.5, -0.25, 0, 0, 0]}'; sleep 0.05; done
  echo '{"currents_mA": [0.5, -0.5, 0, 0, 0, 0, 0, 0]}'; sleep 0.1; } \
  | stimctl --port "$PORT" --live --stimulus a.json 2> b.err || fail "b: $(cat b.err)"
sleep 0.2
stop_emu
grep -q "4 live frames" b.err || fail "b: $(cat b.err)"
check_peak b.jsonl 0.5
awk -v p="$(reported_peak b.err)" 'BEGIN { exit !(p > 0.499 && p <= 0.5) }' || fail "b: reported $(tail -1 b.err)"
# A live frame above the limit: refused (exit 2), nothing of it delivered.
start_emu --record c.jsonl
rc=0
{ sleep 0.1; echo '{"currents_mA": [0.6, -0.6, 0, 0, 0, 0, 0, 0]}'; sleep 0.2; } \
  | stimctl --port "$PORT" --live --stimulus a.json 2> c.err || rc=$?
sleep 0.1
stop_emu
[[ $rc -eq 2 ]] || fail "c: exit $rc: $(cat c.err)"
grep -q "input line 1: .*exceeds the limit of 0.5 mA" c.err || fail "c: $(cat c.err)"
check_peak c.jsonl 0.5
echo "ok: live frames at 0.5 mA delivered within it ($(reported_peak b.err) mA); 0.6 mA refused: $(head -1 c.err)"

# 3. A coarse DAC (stim-emu only: the firmware's DACs have 12, 14 or 16 bits): 6 bits,
# 64516 nA a code.  0.49 mA is 7.6 codes; the nearest, 8, would be 0.516 mA.
if [[ ${TP_DEVICE:-} != firmware ]]; then
  jq '.max_current_mA = 0.5 | .currents_mA = [0.49, -0.49, 0, 0, 0, 0, 0, 0]' a.json > d.json
  start_emu --record d.jsonl --dac-bits 6
  stimctl --port "$PORT" < d.json 2> d.err || fail "d: $(cat d.err)"
  sleep 0.2
  stop_emu
  check_peak d.jsonl 0.5
  jq -se 'map(.currents_mA[0:2] == [0.451612, -0.451612]) | all' d.jsonl > /dev/null \
    || fail "d: $(head -1 d.jsonl)"
  [[ $(reported_peak d.err) == 0.451612 ]] || fail "d: reported $(tail -1 d.err)"
  echo "ok: 6-bit DAC: 0.49 mA under a 0.5 mA limit delivered as 0.451612 mA (not 0.516128)"
fi

# 4. The paper's 2 mA: the device's largest code (2047 x 977 nA = 1.999919 mA) lies a hair
# below it; the current is delivered at that code, not refused.
make-pulse --amplitude 2 --duration 0.02 < "$TP_INPUTS/sai-weights.json" > e.json 2> /dev/null || fail "make-pulse 2 mA"
start_emu --record e.jsonl
stimctl --port "$PORT" < e.json 2> e.err || fail "e: 2 mA refused: $(cat e.err)"
sleep 0.2
stop_emu
check_peak e.jsonl 2
[[ $(reported_peak e.err) == 1.999919 ]] || fail "e: reported $(tail -1 e.err)"
echo "ok: 2 mA delivered at the largest code, $(reported_peak e.err) mA"

# 5. A limit under one DAC step: every current rounds to 0 codes; refused, nothing sent
# (stim-emu only, for its 6-bit DAC: one step is 0.0645 mA).
if [[ ${TP_DEVICE:-} != firmware ]]; then
  jq '.max_current_mA = 0.05 | .currents_mA = [0.04, -0.04, 0, 0, 0, 0, 0, 0]' a.json > f.json
  start_emu --record f.jsonl --dac-bits 6
  refuses 2 --stdin f.json --says "rounds to 0 DAC codes" -- stimctl --port "$PORT"
  sleep 0.1
  stop_emu
  [[ $(lines f.jsonl) -eq 0 ]] || fail "f: delivered $(lines f.jsonl) pulses"
  echo "ok: currents under one DAC step refused, nothing delivered"
fi

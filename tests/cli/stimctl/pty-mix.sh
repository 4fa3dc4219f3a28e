# A mix through a real line (stim-emu, or the firmware in QEMU with TP_DEVICE=firmware):
# the README's RA 30 Hz + SAI 200 Hz for 2 s, checked from the record; live amplitude
# frames fading RA out while SAI holds, and refused ones (above a pattern's amplitude, the
# wrong count, malformed) changing nothing; SIGKILL of stimctl mid-mix (the device's
# watchdog stops every pattern); and, as raw frames, a table over the RMS bound refused by
# the device itself.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_mix mix.json

# 1. The mix, 2 s.
start_emu --record rec.jsonl
stimctl --port "$PORT" --duration 2 < mix.json 2> err.txt || fail "stimctl: $(cat err.txt)"
sleep 0.2
stop_emu
check_mix_record rec.jsonl mix.json '[[59, 61], [399, 401]]'
echo "ok: $(cat err.txt)"
if [[ ${TP_DEVICE:-} == firmware ]]; then
  # The firmware's monitor measured each start: per pattern, periods within one tick (1 us).
  # QEMU without -icount runs the board's clock on the host's, so a host that preempts QEMU
  # while the engine waits for an edge makes that edge late (2 us seen once in CI, on one
  # period of 458): at least 99% of periods within a tick, and none off by more than the
  # 500 us that pty-rates allows an edge.
  errors=$(jq -sc 'group_by(.pattern) | map(. as $g | (1e6 / (if .[0].pattern == 0 then 30 else 200 end) | round) as $T
      | [range(1; length) as $k | (($g[$k].start_us - $g[$k].slip_us) - ($g[$k - 1].start_us - $g[$k - 1].slip_us) - $T) | fabs])
      | add | {n: length, off: map(select(. > 1)), worst: max}' rec.jsonl)
  jq -e '(.off | length) * 100 <= .n and .worst <= 500' <<< "$errors" > /dev/null \
    || fail "measured periods off by more than a tick: $errors"
  worst=$(jq .worst <<< "$errors")
  echo "ok: measured periods within a tick of 33333 and 5000 us but $(jq '.off | length' <<< "$errors") of $(jq .n <<< "$errors") (worst $worst us)"
fi

# 2. Live: RA at full amplitude, then 0.4 mA, then 0; SAI held at 1.2 mA throughout.
start_emu --record live.jsonl
{ sleep 0.8; echo '{"amplitudes": [0.4, 1.2]}'; sleep 0.5; echo '{"amplitudes": [0, 1.2]}'; sleep 0.5; } \
  | stimctl --port "$PORT" --live --stimulus mix.json 2> live.err || fail "live: $(cat live.err)"
sleep 0.2
stop_emu
grep -q "2 live frames" live.err || fail "live: $(cat live.err)"
# RA's currents in the order delivered, not at fixed times (the device's clock starts when
# stimctl has started it, later than the frames' producer, by however long that took): a
# run of 0.8 mA, then of 0.4 mA, then of 0, each of at least 3 pulses, nothing else.
runs=$(jq -sc 'map(select(.pattern == 0) | .currents_mA[6]
                   | if . > 0.799 and . < 0.801 then 8 elif . > 0.399 and . < 0.401 then 4
                     elif . == 0 then 0 else . end)
               | reduce .[] as $x ([]; if length > 0 and .[-1][0] == $x then .[-1][1] += 1 else . + [[$x, 1]] end)' live.jsonl)
[[ $(jq -c 'map(.[0])' <<< "$runs") == '[8,4,0]' && $(jq 'map(.[1] >= 3) | all' <<< "$runs") == true ]] \
  || fail "RA's fade, as [value x 10, pulses] runs: $runs"
[[ $(jq -s 'map(select(.pattern == 1) | .currents_mA[3] > 1.199 and .currents_mA[3] < 1.201) | all' live.jsonl) == true ]] \
  || fail "SAI did not hold"
echo "ok: RA faded 0.8 -> 0.4 -> 0 mA while SAI held 1.2 mA (runs: $runs)"
# Each refused frame: stimctl exits 2 naming the problem; RA ran before it at 0.8 mA and
# nothing ran on after it.
for case in '{"amplitudes": [0.81, 1.2]}|outside \[0, 0.8\] mA' '{"amplitudes": [0.5]}|1 amplitudes for 2 patterns' \
            '{"amplitudes": [0.5, 1.2|malformed JSON' '{"currents_mA": [0, 0, 0, 0, 0, 0, 0, 0]}|a mix takes'; do
  bad=${case%|*} says=${case##*|}
  start_emu --record bad.jsonl
  rc=0
  { sleep 0.8; echo "$bad"; sleep 1; } | stimctl --port "$PORT" --live --stimulus mix.json 2> bad.err || rc=$?
  sleep 0.1
  stop_emu
  [[ $rc -eq 2 ]] || fail "'$bad': exit $rc: $(cat bad.err)"
  grep -q "$says" bad.err || fail "'$bad': $(cat bad.err)"
  [[ $(jq -s 'map(select(.pattern == 0)) | length' bad.jsonl) -ge 3 ]] || fail "'$bad': RA did not run before it"
  [[ $(jq -s 'map(select(.pattern == 0) | .currents_mA[6] > 0.799 and .currents_mA[6] < 0.801) | all' bad.jsonl) == true ]] \
    || fail "'$bad' changed RA's currents"
  last=$(tail -1 bad.jsonl | jq .t_s)
  awk -v t="$last" 'BEGIN { exit !(t < 0.95) }' || fail "'$bad': output ran on to $last s"
  echo "ok: '$bad' refused: $(tail -1 bad.err)"
done

# 3. SIGKILL mid-mix: nothing stops the output but the device's watchdog (300 ms).
start_emu --record kill.jsonl --watchdog-ms 300
stimctl --port "$PORT" --duration 5 < mix.json 2> /dev/null &
victim=$!
sleep 0.6
kill -9 "$victim"
wait "$victim" 2> /dev/null || true
sleep 0.8
stop_emu
last=$(tail -1 kill.jsonl | jq .t_s)
awk -v t="$last" 'BEGIN { exit !(t > 0.4 && t < 1.0) }' || fail "after SIGKILL at 0.6 s the output ran to $last s"
[[ $(jq -s 'map(.pattern) | unique | length' kill.jsonl) -eq 2 ]] || fail "not both patterns ran"
echo "ok: SIGKILL at ~0.6 s: both patterns stopped by the watchdog (last pulse at $last s)"

# 4. Raw frames: two patterns on channel 3 at 2 mA, 800 us + 800 us at 100 Hz: 0.8 mA RMS
# each, 1.13 mA together.  The device refuses the second pattern's codes and delivers
# nothing of them.
T=$(le32 $((0x3A1C0001)))
table() { echo "${T}$(le16 "$1")08$(le16 100)"; }
timing() { echo "${T}$(le16 "$1")$(le32 10000)$(le32 "$2")$(le16 800)$(le16 0)$(le16 800)$(le32 0)"; }
sparse() { echo "${T}$(le16 "$1")02$(printf '%02x' "$2")$(le16 2047)$(printf '%02x' "$3")$(le16 $((-2047 & 0xFFFF)))"; }
start_emu --record raw.jsonl
{ echo "send 1 16 $(table 2)"
  echo "send 2 17 $(timing 0 0)"
  echo "send 3 18 $(sparse 0 3 5)"
  echo "send 4 17 $(timing 1 5000)"
  echo "send 5 18 $(sparse 1 3 6)"      # channel 3 again: over the RMS bound
  echo "send 6 4 $T"                     # start: pattern 1 has no codes
  echo "send 7 18 $(sparse 1 4 6)"      # elsewhere: accepted
  echo "send 8 4 $T"
  echo "sleep 300"
  echo "send 9 5 $T"; } | raw-frames "$PORT" > acks.txt || fail "raw-frames: $(cat acks.txt)"
sleep 0.1
stop_emu
result() { awk -v s="$1" '$1 == s { r = $2 } END { print r }' acks.txt; }
[[ $(result 1) == 0 && $(result 3) == 0 && $(result 4) == 0 ]] || fail "table not set: $(cat acks.txt)"
[[ $(result 5) == 3 ]] || fail "the device accepted 1.13 mA RMS on one electrode: $(cat acks.txt)"
[[ $(result 6) == 4 ]] || fail "started with a pattern refused: $(cat acks.txt)"
[[ $(result 7) == 0 && $(result 8) == 0 ]] || fail "a table within the bounds refused: $(cat acks.txt)"
jq -se 'map(.pattern != 1 or .currents_mA[3] == 0) | all' raw.jsonl > /dev/null || fail "pattern 1 drove channel 3"
jq -se 'map(select(.pattern == 1) | .currents_mA[4] > 1.99) | all and length > 10' raw.jsonl > /dev/null \
  || fail "pattern 1 (channels 4 and 6) did not run: $(jq -sc 'map(select(.pattern == 1)) | length' raw.jsonl) pulses"
echo "ok: the device refused 1.13 mA RMS on one electrode (out_of_range); the table within its bounds ran ($(lines raw.jsonl) pulses)"

# 1 % of bytes corrupted, or dropped, in both directions: no wrong frame is ever applied
# (every recorded pulse carries one of the frames sent), and the host either recovers or
# stops with a clear message (exit 1), never silently.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 200 --duration 60
# 40 live frames, each a scaled copy of the pattern: the allowed current sets.
for k in $(seq 1 40); do
  awk -v k="$k" 'BEGIN { a = 0.2 + 0.02 * k; printf "{\"currents_mA\": [0, 0, %.6f, %.6f, %.6f, 0, 0, 0]}\n", -a / 2, a, -a / 2 }'
done > frames.jsonl
for fault in corrupt drop; do
  start_emu --record "$fault.jsonl" --"$fault" 0.01 --seed 7
  rc=0
  # The writer outlives a stimulus that completes (2 s): it stops at the closed pipe.
  { cat frames.jsonl; sleep 1.5; } | (trap '' PIPE; while IFS= read -r line; do
    echo "$line" 2> /dev/null || break; sleep 0.02; done) \
    | stimctl --port "$PORT" --live --stimulus stim.json --duration 2 2> "$fault.err" || rc=$?
  sleep 0.5
  stop_emu
  if [[ $rc -ne 0 ]]; then
    [[ $rc -eq 1 && $(wc -l < "$fault.err") -ge 1 ]] || fail "$fault: exit $rc: $(cat "$fault.err")"
    grep -qE "not responding|device stopped|device lost|refused" "$fault.err" || fail "$fault: unclear message: $(cat "$fault.err")"
  fi
  # Every recorded pulse is the initial pattern or one of the live frames (within the DAC step).
  jq -se --slurpfile f <(jq -c '.currents_mA' frames.jsonl) --argjson first "$EXPECTED" '
    ([$first] + $f) as $allowed
    | map(.currents_mA as $c | any($allowed[]; . as $a | [range(0; 8)] | all(($c[.] - $a[.]) | fabs <= 0.0015)))
    | all' "$fault.jsonl" > /dev/null || fail "$fault: a pulse carries currents that were never sent"
  check_record_sums() { jq -se 'map(.currents_mA | add | fabs) | max <= 1e-9' "$1" > /dev/null; }
  check_record_sums "$fault.jsonl" || fail "$fault: currents do not sum to zero"
  echo "ok: $fault 1%: exit $rc, $(lines "$fault.jsonl") pulses; $(tail -1 "$fault.err")"
done

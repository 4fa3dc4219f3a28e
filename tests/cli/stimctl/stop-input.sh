# The board's stop input (issue 41, item 4; docs/safety.md, "The stop input"): the skin's
# stop_input event presses it 0.35 s into each output (stim-emu: the emulated board's
# equivalent; the firmware under QEMU: its EXTI interrupt, pended by the simulated board).
# Checked from the device's own record:
#  - the output ends at once: the pulses at 0, 0.1, 0.2 and 0.3 s are delivered, nothing
#    after; stimctl exits 1 saying "stop input", the time and the count;
#  - the latch holds only until a new session: a second stimctl on the same device starts
#    again and is stopped the same way (its own record lines follow);
#  - with --contact-loss suspend (the guards pausing patterns, not stopping) the stop input
#    still ends everything.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 10 --duration 1
printf '%s\n' '{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},' \
  ' "events": [{"t_s": 0.35, "stop_input": true}]}' > stop.json
start_emu --record rec.jsonl --skin stop.json --compliance-v 60
for run in 1 2 3; do
  rc=0
  mode=()
  [[ $run == 3 ]] && mode=(--contact-loss suspend)
  stimctl --port "$PORT" "${mode[@]}" < stim.json 2> run$run.err || rc=$?
  [[ $rc == 1 ]] || fail "run $run: exit $rc: $(cat run$run.err)"
  grep -Eq "device stopped the output: its stop input was pressed at t = 0\.35[0-9]* s \(the output is latched off until a new session\); 4 of 10 pulses delivered" run$run.err \
    || fail "run $run: $(cat run$run.err)"
done
stop_emu
[[ $(jq -sc 'map(.t_s)' rec.jsonl) == '[0,0.1,0.2,0.3,0,0.1,0.2,0.3,0,0.1,0.2,0.3]' ]] \
  || fail "the record's pulses: $(jq -sc 'map(.t_s)' rec.jsonl)"
echo "ok: $(cat run1.err) | $(cat run2.err) | suspend: $(cat run3.err)"

# stimctl --hold-sensation (issue 41, item 6; docs/skin.md, "Sensation held"): a sweat ramp
# (Rp from 50 to 5 kOhm over 1 s on every pad) under a stimulus of +-1 mA on channels 0 and
# 1 whose reference impedance is 7.2413 kOhm (the circuit's |V / I| at 200 us with Rp 50).
# The law, pulse energy sum Z I^2 held (Tachi et al. 1977): pulse k's current is the
# ceiling's (2 mA: codes +-2047) x min(1, 0.5 x sqrt(E_ref / E_k-1)), E = sum over the pads
# of Z x code^2 with each pad's impedance at the previous pulse, in the device's 4-ohm units.
# Checked from the device's record on a real pseudo-terminal (stim-emu; the firmware under
# QEMU as firmware.hold-sensation): every pulse within one DAC step
# of the law (and 0.06 of a code for the scale's 1/32768), the width exactly 200 us; without
# --hold-sensation every pulse at 1 mA; refusals.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
cat > held.json <<'JSON'
{"format": "tactile-primaries/stimulus/1", "channels": 8, "currents_mA": [1, -1, 0, 0, 0, 0, 0, 0],
 "max_current_mA": 2.0, "pulse": {"width_us": 200, "interphase_us": 0, "balance_width_us": 200, "frequency_hz": 20},
 "count": 20, "reference_impedance_kohm": [7.2413, 7.2413, null, null, null, null, null, null]}
JSON
cat > sweat.json <<'JSON'
{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
 "events": [{"t_s": 0.0, "channels": "all", "rp_kohm": 5.0, "ramp_s": 1.0}]}
JSON
start_emu --record held.jsonl --skin sweat.json
stimctl --port "$PORT" --hold-sensation < held.json 2> held.err || fail "hold: $(cat held.err)"
sleep 0.2  # the firmware's monitor writes its last lines after the host has finished
stop_emu
grep -q "20 of 20 pulses.*sensation held (up to 2 x each amplitude)" held.err || fail "hold: $(cat held.err)"
jq -se '
  def units($z): (($z * 1000 | round) / 4 | floor);
  length == 20 and all(.[]; .width_us == 200 and .balance_width_us == 200) and
  (. as $r | [range(0; 20) as $k
    | (if $k == 0 then 1 else (2 * units(7.2413)) / (units($r[$k - 1].impedance_kohm[0]) + units($r[$k - 1].impedance_kohm[1])) end) as $ratio
    | (([1, 0.5 * ($ratio | sqrt)] | min) * 2047) as $law
    | ($r[$k].currents_mA[0] / 0.000977 | round) as $code
    | (($code - $law) | fabs) <= 1.06 and $r[$k].currents_mA[1] == -$r[$k].currents_mA[0]] | all)' held.jsonl > /dev/null \
  || fail "the law: $(jq -c '[.t_s, .currents_mA[0], .impedance_kohm[0]]' held.jsonl | tr '\n' ' ')"
# The law raised the current as the skin sweated: from 1 mA to above 1.1.
jq -se '.[0].currents_mA[0] < 1.001 and .[-1].currents_mA[0] > 1.1' held.jsonl > /dev/null \
  || fail "the current did not follow the sweat: $(jq -c '.currents_mA[0]' held.jsonl | tr '\n' ' ')"
# Without the law, nothing changes.
start_emu --record plain.jsonl --skin sweat.json
stimctl --port "$PORT" < held.json 2> plain.err || fail "plain: $(cat plain.err)"
sleep 0.2
stop_emu
jq -se 'length == 20 and all(.[]; .currents_mA[0] == 1.000448)' plain.jsonl > /dev/null || fail "without the law: $(jq -c '.currents_mA[0]' plain.jsonl | tr '\n' ' ')"
# Refused: no reference impedance, a device that does not measure, live mode.
jq 'del(.reference_impedance_kohm)' held.json > noref.json
refuses 2 --stdin noref.json --says "--hold-sensation: the stimulus has no reference impedance for channel 0 (make-pulse --profile" \
  -- stimctl --port emu --emu-skin sweat.json --hold-sensation
refuses 2 --stdin held.json --says "--hold-sensation: emu (in-process emulator) does not measure its pulses" -- stimctl --port emu --hold-sensation
refuses 2 --stdin /dev/null --says "--hold-sensation: not with --live" -- stimctl --port emu --emu-skin sweat.json --hold-sensation --live --stimulus held.json
jq '.reference_impedance_kohm[0] = -1' held.json > badref.json
refuses 2 --stdin badref.json --says "reference_impedance_kohm[0]: -1 kOhm outside [0.01, 100000] kOhm" -- stimctl --port emu
echo "ok: $(cat held.err)"

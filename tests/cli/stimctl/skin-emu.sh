# The emulator's skin (issue 41, items 1 and 2; docs/skin.md): with --emu-skin (in-process)
# and stim-emu --skin (a real pseudo-terminal), every recorded pulse carries each channel's
# voltage at the main phase's end and the impedance derived from it, null where a channel
# carried no current.  Checked against the circuit's closed form, I (Rs + Rp (1 - e^(-w/tau)))
# with the scenario's values at the pulse's time: a sweat ramp on one pad, half contact on
# another, the impedance |V / I| throughout.  (A pad lifted stops the output: guards-emu.sh.)
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 10 --duration 1
cat > skin.json <<'JSON'
{"format": "tactile-primaries/skin/1",
 "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
 "events": [{"t_s": 0.0, "channels": [3], "rp_kohm": 10.0, "ramp_s": 1.0},
            {"t_s": 0.25, "channels": [4], "contact": 0.5}]}
JSON
# The closed form for pulse k (t = 0.1 k s) and channel c, from the record's own current
# (the pulses are 100 ms apart: the interface, tau 1.5 ms, starts each discharged).
check_skin_record() {  # REC
  jq -se '
    def predicted($t; $c; $i):
      (if $c == 3 then 50 - 40 * $t else 50 end) as $rp
      | (if $c == 4 and $t >= 0.25 then 0.5 else 1 end) as $contact
      | $i * (1 / ($contact | sqrt) + $rp / $contact * (1 - ((-200 / ($rp * 30)) | exp)));
    length == 10 and all(.[]; . as $p
      | all(range(0; 8); . as $c | $p.currents_mA[$c] as $i
          | if $i == 0 then $p.voltage_V[$c] == null and $p.impedance_kohm[$c] == null
            else (($p.voltage_V[$c] - predicted($p.t_s; $c; $i)) | fabs) < 0.002
              and (($p.impedance_kohm[$c] - ($p.voltage_V[$c] / $i | fabs)) | fabs) < 0.002 end))' "$1" > /dev/null \
    || fail "record $1 against the closed form: $(jq -c '{t: .t_s, i: .currents_mA, v: .voltage_V}' "$1" | head -6)"
}
stimctl --port emu --emu-skin skin.json --record rec.jsonl < stim.json 2> err.txt || fail "stimctl: $(cat err.txt)"
check_skin_record rec.jsonl
# A real pseudo-terminal, a lower compliance (the largest voltage here is 7.2 V).
start_emu --record pty.jsonl --skin skin.json --compliance-v 20
stimctl --port "$PORT" < stim.json 2> perr.txt || fail "stimctl: $(cat perr.txt)"
stop_emu
check_skin_record pty.jsonl
# Without a skin: an ideal load, no measurements.
stimctl --port emu --record plain.jsonl < stim.json 2> /dev/null || fail "stimctl without a skin"
jq -se 'all(.[]; has("voltage_V") | not)' plain.jsonl > /dev/null || fail "measurements without a skin"
# Refused, naming the flag or the field, before anything is sent.
refuses 2 --stdin stim.json --says "--emu-compliance-v: applies with --emu-skin (an ideal load needs no voltage)" \
  -- stimctl --port emu --emu-compliance-v 50
refuses 2 --stdin stim.json --says "--emu-skin: only with --port emu" -- stimctl --port /dev/tp-no-such-port --emu-skin skin.json
jq '.events[0].channels = [8]' skin.json > bad.json
refuses 2 --stdin stim.json --says "--emu-skin bad.json: events[0].channels: 8 is not a channel (0 to 7)" \
  -- stimctl --port emu --emu-skin bad.json --record bad.jsonl
[[ ! -s bad.jsonl ]] || fail "a bad skin delivered pulses"
refuses 2 --says "--compliance-v: 2000 V outside [1, 1000] V" -- stim-emu --skin skin.json --compliance-v 2000
refuses 2 --says "--compliance-v: applies with --skin" -- stim-emu --compliance-v 50
echo "ok: $(head -1 rec.jsonl | jq -c '{voltage_V, impedance_kohm}')"

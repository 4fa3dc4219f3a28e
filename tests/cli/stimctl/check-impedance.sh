# stimctl --check-impedance (issue 41, item 5; docs/skin.md, "Before a session"): a probe
# of 0.05 mA on every used pad of a device that measures; a table of impedance and contact
# on stderr; a lifted pad or a stimulus whose peak needs more than the compliance refuses
# the stimulus (exit 2, one line naming the channel), and nothing above the probe is
# delivered (checked from the record: the probe's pulses only).  With good contact the
# stimulus follows.  On stim-emu's real pseudo-terminal too.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
make_stimulus stim.json --frequency 10 --duration 1
skin() {  # FILE OVERRIDES_JSON
  printf '{"format": "tactile-primaries/skin/1", "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0}, "overrides": %s}\n' "$2" > "$1"
}
skin ok.json '[{"channels": [4], "rp_kohm": 80.0}]'
skin lifted.json '[{"channels": [4], "contact": 0.0}]'
# Only the probe: at most 0.05 mA (and a DAC step) on every pad, five pulses at most.
only_probe() {
  jq -se 'length <= 5 and all(.[]; all(.currents_mA[]; fabs <= 0.051))' "$1" > /dev/null \
    || fail "$1: more than the probe: $(jq -c .currents_mA "$1" | sort | uniq -c)"
}

refuses 2 --stdin stim.json --says "--check-impedance: channel 4 has no contact (no current flowed at the probe): the stimulus was not started" \
  -- stimctl --port emu --emu-skin lifted.json --check-impedance --record lifted.jsonl
only_probe lifted.jsonl
# The closed form at the probe: channel 3 anodic at 0.05 mA for 200 us, 1 + 50 (1 - e^(-2/15)) kOhm.
refuses 2 --stdin stim.json --says "--check-impedance: channel 3 would need 7.2 V at the stimulus's 1 mA (7.245 kOhm at the probe), above the device's 5 V compliance" \
  -- stimctl --port emu --emu-skin ok.json --emu-compliance-v 5 --check-impedance --record compliance.jsonl
only_probe compliance.jsonl

stimctl --port emu --emu-skin ok.json --check-impedance --record ok.jsonl < stim.json 2> ok.err || fail "good contact: $(cat ok.err)"
grep -Eq "^ +4 +7.4 +0.188 +yes +0.500 +3.8$" ok.err || fail "the table: $(cat ok.err)"
[[ $(jq -s 'map(select(.currents_mA[3] == 1.000448)) | length' ok.jsonl) == 10 ]] || fail "the stimulus after the check: $(jq -s length ok.jsonl) pulses"

# A real pseudo-terminal.
start_emu --record pty.jsonl --skin lifted.json
refuses 2 --stdin stim.json --says "--check-impedance: channel 4 has no contact" -- stimctl --port "$PORT" --check-impedance
stop_emu
only_probe pty.jsonl

# Refused with nothing but identify sent (the record stays empty).
refuses 2 --stdin stim.json --says "--check-impedance: emu (in-process emulator) does not measure its pulses" \
  -- stimctl --port emu --check-impedance --record none.jsonl
[[ ! -s none.jsonl ]] || fail "a device that does not measure was probed"
refuses 2 --stdin stim.json --says "--probe-current: applies with --check-impedance" -- stimctl --port emu --probe-current 0.05
refuses 2 --stdin stim.json --says "--probe-current: 1 mA outside [0.01, 0.5] mA" -- stimctl --port emu --check-impedance --probe-current 1
echo "ok: $(grep -c yes ok.err) pads in contact"

# Shaped pulses (issue 40, protocol 6) delivered phase by phase: in-process (--port emu) and
# through a pty to stim-emu, each record's phases are the document's durations and its
# levels x U in units, the net charge 0, and each phase's currents within 1.5 x |units| DAC
# steps of the current asked (the base codes: docs/protocol.md); a live currents frame on a
# shaped pattern; the device's own refusals of raw set_shape frames (a net charge, a short
# phase, 17 phases), each with its result (every rule: unit tests, test_device_shape).
# TP_DEVICE=firmware (firmware.shaped): the pty parts against the board in QEMU.
source "$TP_SOURCE/tests/cli/stimctl/common.sh"
in=$TP_INPUTS/sai-weights.json
make-pulse --amplitude 1 --count 3 --frequency 100 --phases 500:0.1,200:1,50:0,500:-0.5 \
  < "$in" > shaped.json 2> /dev/null
# check_shaped FILE [TOL_US]: 3 records, each as the document asks, each phase's duration
# within TOL_US (0: exact; a firmware's are measured on its clock: 1).
check_shaped() {
  python3 - "$1" shaped.json "${2:-0}" <<'PY' || fail "record $1"
import json, sys
recs = [json.loads(l) for l in open(sys.argv[1])]
doc = json.load(open(sys.argv[2]))
tol = int(sys.argv[3])
U = doc["safety"]["level_unit"]
phases = doc["pulse"]["phases"]
want = [{"duration_us": p["duration_us"], "units": round(p["level"] * U)} for p in phases]
step = 977e-6
assert len(recs) == 3, f"{len(recs)} records"
for r in recs:
    got = r["phases"]
    assert [p["units"] for p in got] == [w["units"] for w in want], (got, want)
    assert all(abs(p["duration_us"] - w["duration_us"]) <= tol for p, w in zip(got, want)), (got, want)
    assert all(q == 0 for q in r["net_charge_nC"]), r["net_charge_nC"]
    for c, unit_mA in zip(doc["currents_mA"], r["unit_currents_mA"]):
        for p, w in zip(phases, want):
            asked = c * p["level"]
            given = unit_mA * w["units"]
            assert abs(given - asked) <= 1.5 * abs(w["units"]) * step + 1e-9, (c, p, unit_mA)
print(f"ok: {len(recs)} shaped pulses of {[p['duration_us'] for p in recs[0]['phases']]} us, U = {U}, main phase "
      f"{max(abs(u) for u in recs[0]['unit_currents_mA']) * U:.6g} mA of 1 mA")
PY
}
stimctl --port emu --stimulus shaped.json --record emu.jsonl 2> emu.txt || fail "emu: $(cat emu.txt)"
check_shaped emu.jsonl
grep -q "3 of 3 pulses" emu.txt || fail "emu: $(cat emu.txt)"
start_emu --record pty.jsonl
stimctl --port "$PORT" --stimulus shaped.json 2> pty.txt || fail "pty: $(cat pty.txt)"
sleep 0.2
stop_emu
# TP_DEVICE=firmware: the board in QEMU, its monitor's records (durations measured).
check_shaped pty.jsonl "$([[ ${TP_DEVICE:-} == firmware ]] && echo 1 || echo 0)"
# A live currents frame on the shaped pattern: its base codes from the frame's currents.
{ sleep 0.3; echo '{"currents_mA": [0, 0, -0.25, 0.5, -0.25, 0, 0, 0]}'; sleep 0.3; } |
  stimctl --port emu --live --stimulus shaped.json --duration 0.5 --record live.jsonl 2> live.txt ||
  fail "live: $(cat live.txt)"
jq -se 'map(.unit_currents_mA[3]) | (.[0] > 0.099 and .[-1] < 0.051 and .[-1] > 0.049)' live.jsonl > /dev/null ||
  fail "live frame: $(jq -sc 'map(.unit_currents_mA[3])' live.jsonl)"
echo "ok: a live frame on a shaped pattern"
# Raw set_shape frames (raw-frames), refused by the device itself with their reasons: a
# net charge, a phase shorter than any device's min_width_us, 17 phases; a shape within
# the rules accepted.  Body: token, index, period, phase, max_pulses, n, n x (us, units).
T=$(le32 $((0x5A4E0001)))
shape() { local n=$(($# / 2)); printf '%s' "${T}$(le16 0)$(le32 10000)$(le32 0)$(le32 0)$(printf '%02x' "$n")"
  while (($#)); do printf '%s' "$(le16 "$1")$(le16 $(($2 & 0xFFFF)))"; shift 2; done; }
seventeen=$(for i in $(seq 17); do echo 100 $((i % 2 ? 1 : -1)); done)
start_emu
{ echo "send 1 16 ${T}$(le16 1)08$(le16 100)"   # configure_table: 1 pattern, 8 channels
  echo "send 2 20 $(shape 100 1 100 -2)"          # charge 100 - 200 units x us
  echo "send 3 20 $(shape 5 2 10 -1)"             # a 5 us phase
  echo "send 4 20 $(shape $seventeen)"            # 17 phases
  echo "send 5 20 $(shape 100 2 50 0 200 -1)"     # within the rules
  echo "sleep 100"; } | raw-frames "$PORT" > acks.txt || fail "raw-frames: $(cat acks.txt)"
stop_emu
result() { awk -v s="$1" '$1 == s { r = $2 } END { print r }' acks.txt; }
[[ $(result 1) == 0 ]] || fail "configure_table: $(cat acks.txt)"
[[ $(result 2) == 11 ]] || fail "a shape with net charge: result $(result 2), expected 11 (charge_not_zero)"
[[ $(result 3) == 3 ]] || fail "a 5 us phase: result $(result 3), expected 3 (out_of_range)"
[[ $(result 4) == 2 ]] || fail "17 phases: result $(result 4), expected 2 (bad_length)"
[[ $(result 5) == 0 ]] || fail "a shape within the rules: result $(result 5), expected 0"
echo "ok: the device refused raw shapes (net charge, 5 us phase, 17 phases) and took a valid one"

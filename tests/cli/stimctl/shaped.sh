# Shaped pulses (issue 40, protocol 6) delivered phase by phase: in-process (--port emu) and
# through a pty to stim-emu, each record's phases are the document's durations and its
# levels x U in units, the net charge 0, and each phase's currents within 1.5 x |units| DAC
# steps of the current asked (the base codes: docs/protocol.md); a live currents frame on a
# shaped pattern; the device's own refusals of raw shapes are unit tests (test_device_shape).
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

"""The stimulator from Python: what is delivered (the emulator's record), Ctrl-C and
exceptions stop the output first (stim-emu's event log, a separate process), and the GIL
is released while a delivery waits."""
import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import tactile_primaries as tp


def records(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


@pytest.fixture
def stim(sai_doc):
    return tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)


@pytest.fixture
def emu(tmp_path):
    """stim-emu on a pty: (port, record path, event log path)."""
    rec, events = tmp_path / "rec.jsonl", tmp_path / "events.txt"
    p = subprocess.Popen(["stim-emu", "--record", str(rec), "--event-log", str(events)],
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = p.stdout.readline().strip()
    assert port, "stim-emu printed no port"
    yield port, rec, events
    p.terminate()
    p.wait(timeout=10)


def events_of(path, kind):
    with open(path) as f:
        return [int(line.split()[2]) for line in f if line.split()[0] == kind]


def test_deliver_on_the_emulator_as_stimctl_does(tmp_path, sai_doc):
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=0.5)
    rec = tmp_path / "rec.jsonl"
    with tp.Stimulator("emu", record=str(rec)) as s:
        report = s.deliver(stim)
    assert report["pulses"] == 100 and report["end"] == "stimulus complete"
    pulses = records(rec)
    assert len(pulses) == 100
    weights = sai_doc.weights
    for p in pulses:  # each pulse: the weights at 1 mA, within one DAC step
        assert max(abs(c - w) for c, w in zip(p["currents_mA"], weights)) < 0.000978
    # The same stimulus's JSON text and a file work too.
    with tp.Stimulator("emu") as s:
        assert s.deliver(stim.to_json(), duration_s=0.1)["pulses"] == 20


def test_a_shaped_pulse_is_delivered_phase_by_phase(tmp_path, sai_doc):
    shape = [(500, 0.1), (200, 1), (50, 0), (500, -0.5)]
    stim = tp.make_pulse(sai_doc, 1.0, 100, count=5, phases=shape)
    rec = tmp_path / "rec.jsonl"
    with tp.Stimulator("emu", record=str(rec)) as s:
        assert s.deliver(stim)["pulses"] == 5
    for p in records(rec):  # U = 10: units are the levels x 10; zero charge exactly
        assert p["phases"] == [{"duration_us": d, "units": round(l * 10)} for d, l in shape]
        assert all(q == 0 for q in p["net_charge_nC"])
        for unit_mA, w in zip(p["unit_currents_mA"], sai_doc.weights):
            assert abs(unit_mA * 10 - w) <= 1.5 * 10 * 0.000977 + 1e-9


def test_refused_stimuli_send_nothing(tmp_path, sai_doc):
    rec = tmp_path / "rec.jsonl"
    big = tp.make_pulse(sai_doc, 1.0, 200, duration_s=0.1).to_dict()
    big["currents_mA"] = [c * 3 for c in big["currents_mA"]]
    with pytest.raises(tp.BadInput):
        tp.Stimulus.from_json(json.dumps(big))
    with tp.Stimulator("emu", record=str(rec), emu_channels=4) as s:
        with pytest.raises(tp.BadInput, match="channels"):
            s.deliver(tp.make_pulse(sai_doc, 1.0, 200, duration_s=0.1))
        with pytest.raises(tp.BadInput, match="--duration"):
            s.deliver(tp.make_pulse(sai_doc, 1.0, 200), duration_s=0)
    assert not rec.exists() or records(rec) == []


def test_the_gil_is_released_while_delivering(sai_doc):
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=0.6)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.005)

    t = threading.Thread(target=count)
    with tp.Stimulator("emu") as s:
        t.start()
        start = len(ticks)
        report = s.deliver(stim)
        during = len(ticks) - start
        done.set()
    t.join()
    assert report["pulses"] == 120
    assert during >= 40, f"the other thread ran {during} times in 0.6 s"


def test_ctrl_c_stops_the_output_first(emu, tmp_path):
    port, rec, events = emu
    script = tmp_path / "trial.py"
    script.write_text(textwrap.dedent(f"""
        import sys, time
        import tactile_primaries as tp
        doc = tp.optimize_weights(tp.Document.create(), "SAI")
        stim = tp.make_pulse(doc, 1.0, 200, duration_s=10)
        with tp.Stimulator({port!r}) as s:
            print("delivering", flush=True)
            try:
                s.deliver(stim)
            except KeyboardInterrupt:
                print("interrupted", time.time(), flush=True)
                sys.exit(130)
    """))
    child = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "delivering"
    for _ in range(500):  # the output has started (stim-emu's event log)
        if os.path.exists(events) and events_of(events, "start"):
            break
        time.sleep(0.01)
    time.sleep(0.5)
    t_sigint = time.time()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=20)
    assert child.returncode == 130 and out.startswith("interrupted"), out
    time.sleep(0.2)
    stops = events_of(events, "stop")
    assert stops, "no stop frame reached the device"
    stop_ms = (stops[-1] / 1e9 - t_sigint) * 1e3
    assert stop_ms <= 100, f"the output stopped {stop_ms:.1f} ms after Ctrl-C"
    n = len(records(rec))
    assert 50 <= n <= 200, f"{n} pulses in about 0.5 s at 200 Hz"


def test_an_exception_in_a_live_session_stops_the_output(emu, sai_doc):
    port, rec, events = emu
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)
    with pytest.raises(ZeroDivisionError):
        with tp.Stimulator(port) as s:
            s.start_live(stim)
            assert s.running
            for a in (0.8, 0.6):
                s.set_currents([a * w for w in sai_doc.weights])
                time.sleep(0.1)
            with pytest.raises(tp.BadInput):
                s.set_currents([5.0 * w for w in sai_doc.weights])  # above the limit
            t_raise = time.time()
            1 / 0
    time.sleep(0.2)
    stops = events_of(events, "stop")
    assert stops and (stops[-1] / 1e9 - t_raise) * 1e3 <= 100
    pulses = records(rec)
    assert 20 <= len(pulses) <= 120
    peak = max(max(abs(c) for c in p["currents_mA"]) for p in pulses)
    assert peak <= 1.0 + 0.000977


def test_live_amplitudes_and_stop(tmp_path, sai_doc):
    rec = tmp_path / "rec.jsonl"
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)
    with tp.Stimulator("emu", record=str(rec)) as s:
        s.start_live(stim)
        s.set_amplitudes([0.5])
        time.sleep(0.2)
        report = s.stop()
        assert not s.running
    assert report["end"] and report["frames"] == 1
    pulses = records(rec)
    assert 0 < len(pulses) < 200
    last = max(abs(c) for c in pulses[-1]["currents_mA"])
    assert abs(last - 0.5) < 0.001


def test_close_from_another_thread_stops_a_delivery(emu, sai_doc):
    port, rec, events = emu
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)
    s = tp.Stimulator(port)
    s.open()
    result = {}

    def deliver():
        try:
            result["report"] = s.deliver(stim)
        except BaseException as e:  # noqa: B902  (what ended it)
            result["error"] = e

    t = threading.Thread(target=deliver)
    t.start()
    for _ in range(500):
        if os.path.exists(events) and events_of(events, "start"):
            break
        time.sleep(0.01)
    with pytest.raises(tp.BadInput, match="a delivery is running on another thread"):
        s.deliver(stim)  # one at a time
    t_close = time.time()
    s.close()  # stops the other thread's delivery first, then lets go of the port
    t.join(timeout=10)
    assert not t.is_alive()
    time.sleep(0.2)
    stops = events_of(events, "stop")
    assert stops and (stops[-1] / 1e9 - t_close) * 1e3 <= 100
    # What ended it is the caller's close(), not a signal (issue 38).
    assert "error" not in result, result
    assert result["report"]["end"] == "closed (Stimulator.close())"
    assert result["report"]["exit_code"] == 0


def test_an_amplitude_after_currents_scales_the_currents_in_force(tmp_path, sai_doc):
    """An amplitude is the current of a weight-1 electrode of the pattern in force: after
    set_currents([1, -1, 0...]) its weights are [1, -1, 0...], so 0.05 mA gives 0.05 mA
    (issue 38: it gave 0.5 mA, scaling the new codes by 0.05 / the stimulus's 0.1 mA)."""
    rec = tmp_path / "rec.jsonl"
    stim = tp.make_pulse(sai_doc, 0.1, 200, duration_s=10)
    with tp.Stimulator("emu", record=str(rec)) as s:
        s.start_live(stim)
        s.set_currents([1, -1, 0, 0, 0, 0, 0, 0])
        time.sleep(0.2)
        s.set_amplitudes([0.05])
        time.sleep(0.2)
        s.stop()
    pulses = records(rec)
    assert max(p["currents_mA"][0] for p in pulses) > 0.99  # the currents frame, delivered
    last = pulses[-1]["currents_mA"]
    assert abs(last[0] - 0.05) < 0.001 and abs(last[1] + 0.05) < 0.001, last


def test_frames_up_to_the_end_of_a_live_duration_complete_it(tmp_path, sai_doc):
    """Frames sent while a live session's duration runs out: the stimulus completes, and
    stop() reports it complete (issue 38: the device's refusal of a frame after its end was
    reported as a failure)."""
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)
    with tp.Stimulator("emu") as s:
        s.start_live(stim, duration_s=0.3)
        t0 = time.monotonic()
        taken = 0
        while time.monotonic() - t0 < 5 and s.set_amplitudes([0.5]):
            taken += 1
            time.sleep(0.002)
        assert taken > 10
        report = s.stop()
    assert report["end"] == "stimulus complete"
    assert report["pulses"] == 60


def test_frames_never_hang_when_the_session_ends(tmp_path, sai_doc):
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=10)
    frame = [0.5 * w for w in sai_doc.weights]
    with tp.Stimulator("emu") as s:
        s.start_live(stim, duration_s=0.3)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 20 and s.set_currents(frame):
            pass  # until the session's end says so: False once it has completed
        assert time.monotonic() - t0 < 10
        assert not s.running
        assert s.stop()["end"] == "stimulus complete"


def test_stimulator_refusals(tmp_path, sai_doc):
    stim = tp.make_pulse(sai_doc, 1.0, 200, duration_s=1)
    with tp.Stimulator("emu", record=tmp_path / "rec.jsonl") as s:  # a pathlib.Path
        with pytest.raises(tp.BadInput, match="no live session"):
            s.set_currents(list(sai_doc.weights))
        s.start_live(stim)
        with pytest.raises(tp.BadInput, match="a live session is running"):
            s.deliver(stim)
        with pytest.raises(tp.BadInput, match="set_currents: 2 currents for 8 channels"):
            s.set_currents([0.1, -0.1])
        with pytest.raises(tp.BadInput, match="not a finite number"):
            s.set_currents([float("nan")] * 8)
        with pytest.raises(tp.BadInput, match="outside"):
            s.set_amplitudes([1.5])
        s.set_amplitudes([0.5])
        assert s.stop()["frames"] == 1
        assert s.stop() is None  # twice: nothing more
    s.close()  # twice: nothing more
    for bad, words in ((dict(baud=10), "--baud: Value 10 not in range 300 to 4000000"),
                       (dict(emu_channels=65), "--emu-channels: Value 65 not in range 1 to 64"),
                       (dict(backend="x"), "--backend")):
        with pytest.raises(tp.BadInput, match=words):
            tp.Stimulator("emu", **bad)


def test_start_live_loads_what_frames_need_before_the_output_starts():
    # A new user's finding (issue 38 follow-up): the first set_amplitudes imported numpy,
    # ~0.3 s during which the output ran on unchanged.  In a fresh interpreter, numpy must
    # already be loaded when start_live returns.
    script = textwrap.dedent("""
        import sys
        import tactile_primaries as tp
        doc = tp.Document.create()
        stim = tp.make_pulse(tp.optimize_weights(doc, "SAI"), 1.0, 200, duration_s=10)
        assert "numpy" not in sys.modules or print("numpy before start_live")
        with tp.Stimulator("emu") as s:
            s.start_live(stim)
            print("numpy" in sys.modules, flush=True)
            s.stop()
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "True", out.stdout


def test_an_emulator_with_a_skin_records_what_it_measured(tmp_path, sai_doc):
    # Issue 41, items 2 and 4: the same skin as stimctl --emu-skin; every recorded pulse
    # carries each channel's voltage at the main phase's end (the closed form I (Rs + Rp (1
    # - e^(-w/tau)))) and |V / I|, null where no current flowed; a pad lifted at 0.25 s is
    # found by the pulse at 0.3 s, which is the last: the run fails naming it.
    import math
    skin = tmp_path / "skin.json"
    skin.write_text(json.dumps({
        "format": "tactile-primaries/skin/1",
        "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
        "events": [{"t_s": 0.25, "channels": [2], "contact": 0.0}]}))
    rec = tmp_path / "rec.jsonl"
    stim = tp.make_pulse(sai_doc, 1.0, 10, duration_s=0.5)
    with tp.Stimulator("emu", record=str(rec), emu_skin=str(skin), emu_compliance_V=40) as s:
        with pytest.raises(tp.Failure,
                           match=r"channel 2 lost contact at t = 0.3 s \(no current flowed\)"):
            s.deliver(stim)
    # The readings the session took when the guard stopped it: channel 2 open.
    z = s.impedances()
    assert len(z) == 8 and z[2] == math.inf
    closed = 1 + 50 * (1 - math.exp(-200 / 1500))
    assert all(z[c] is None or z[c] == pytest.approx(closed, abs=0.01) for c in range(8) if c != 2)
    assert sum(v is not None for v in z) >= 3
    pulses = records(rec)
    assert len(pulses) == 4
    for p in pulses:
        for c, (i, v, z) in enumerate(zip(p["currents_mA"], p["voltage_V"], p["impedance_kohm"])):
            if i == 0:
                assert v is None and z is None
                continue
            if p["t_s"] >= 0.25 and c == 2:
                assert abs(v) == 40 and z is None  # lifted: the rail, no current
                continue
            assert v == pytest.approx(i * (1 + 50 * (1 - math.exp(-200 / 1500))), abs=0.002)
            # V in mV resolution: |V / I| within half a mV over I, and the ohm's rounding.
            assert z == pytest.approx(abs(v / i), abs=0.0005 / abs(i) + 0.001)
    # Without the lift, the report carries the last readings; without a skin, none.
    skin.write_text(json.dumps({"format": "tactile-primaries/skin/1",
                                "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0}}))
    with tp.Stimulator("emu", emu_skin=str(skin)) as s:
        report = s.deliver(stim)
        assert report["impedances_kohm"] == s.impedances()
        assert report["impedances_kohm"][2] == pytest.approx(7.2413, abs=0.01)
    with tp.Stimulator("emu") as s:
        assert "impedances_kohm" not in s.deliver(stim) and s.impedances() == []
    # The impedance check: a row per used pad; a lifted one refused as stimctl refuses it.
    with tp.Stimulator("emu", emu_skin=str(skin), record=str(tmp_path / "probe.jsonl")) as s:
        rows = s.check_impedance(stim)
        currents = stim.to_dict()["currents_mA"]
        assert [r["channel"] for r in rows] == [c for c in range(8) if currents[c] != 0]
        assert all(r["contact"] and r["impedance_kohm"] == pytest.approx(closed, abs=0.01)
                   for r in rows)
        assert all(abs(r["probe_mA"]) <= 0.05 for r in rows)
    skin.write_text(json.dumps({"format": "tactile-primaries/skin/1",
                                "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
                                "overrides": [{"channels": [2], "contact": 0.0}]}))
    with tp.Stimulator("emu", emu_skin=str(skin)) as s:
        with pytest.raises(tp.BadInput, match="channel 2 has no contact"):
            s.check_impedance(stim)
    # contact_loss="suspend": the lifted pad's pattern goes on at the probe, nothing fails.
    with tp.Stimulator("emu", emu_skin=str(skin), contact_loss="suspend", probe_mA=0.04,
                       record=str(tmp_path / "suspend.jsonl")) as s:
        report = s.deliver(stim)
        assert report["pulses"] == 5 and report["impedances_kohm"][2] == math.inf
    # The first pulse finds the pad lifted (as asked); the rest are probes of 0.04 mA.
    peaks = [max(abs(c) for c in p["currents_mA"]) for p in records(tmp_path / "suspend.jsonl")]
    assert peaks[0] > 0.5 and all(0.035 < x <= 0.04 for x in peaks[1:]) and len(peaks) == 5
    # hold_sensation: a stimulus with reference impedances under a sweat ramp; the current
    # rises as the impedance falls, as stimctl --hold-sensation does; refused without them.
    held = json.loads(stim.to_json())
    held["reference_impedance_kohm"] = [closed if c != 0 else None for c in held["currents_mA"]]
    skin.write_text(json.dumps({"format": "tactile-primaries/skin/1",
                                "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
                                "events": [{"t_s": 0, "channels": "all", "rp_kohm": 5,
                                            "ramp_s": 0.5}]}))
    with tp.Stimulator("emu", emu_skin=str(skin), hold_sensation=True,
                       record=str(tmp_path / "held.jsonl")) as s:
        s.deliver(tp.Stimulus.from_json(json.dumps(held)))
    first, last = records(tmp_path / "held.jsonl")[0], records(tmp_path / "held.jsonl")[-1]
    big = max(range(8), key=lambda c: abs(first["currents_mA"][c]))
    assert abs(last["currents_mA"][big]) > abs(first["currents_mA"][big]) * 1.02
    with tp.Stimulator("emu", emu_skin=str(skin), hold_sensation=True) as s:
        with pytest.raises(tp.BadInput, match="--hold-sensation: the stimulus has no reference"):
            s.deliver(stim)
    with pytest.raises(tp.BadInput, match="--contact-loss: pause is not stop or suspend"):
        tp.Stimulator("emu", contact_loss="pause")
    for bad, words in ((dict(emu_compliance_V=50), "--emu-compliance-v: applies with --emu-skin"),
                       (dict(emu_skin=str(skin), emu_compliance_V=0.5),
                        "--emu-compliance-v: 0.5 V outside \\[1, 1000\\] V")):
        with pytest.raises(tp.BadInput, match=words):
            with tp.Stimulator("emu", **bad) as s:
                s.deliver(stim)


def test_the_stop_input_ends_a_delivery_and_a_new_session_delivers_again(tmp_path, sai_doc):
    # Issue 41, item 4: the skin's stop_input event presses the emulated board's stop input
    # 0.25 s into each output: the delivery fails saying so, with exactly the pulses before
    # it delivered; the same Stimulator's next delivery (a new session) starts again.
    skin = tmp_path / "skin.json"
    skin.write_text(json.dumps({
        "format": "tactile-primaries/skin/1",
        "electrode": {"rs_kohm": 1.0, "rp_kohm": 50.0, "cp_nf": 30.0},
        "events": [{"t_s": 0.25, "stop_input": True}]}))
    rec = tmp_path / "rec.jsonl"
    stim = tp.make_pulse(sai_doc, 1.0, 10, duration_s=0.5)
    with tp.Stimulator("emu", record=str(rec), emu_skin=str(skin)) as s:
        for _ in range(2):
            with pytest.raises(tp.Failure, match=r"its stop input was pressed at t = 0.25 s "
                                                 r"\(the output is latched off until a new "
                                                 r"session\); 3 of 5 pulses delivered"):
                s.deliver(stim)
    assert [p["t_s"] for p in records(rec)] == [0, 0.1, 0.2] * 2

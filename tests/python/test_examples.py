"""examples/python run as a user runs them, and do what they say."""
import csv
import io
import json
import os
import signal
import subprocess
import sys
import time

import tactile_primaries as tp
from conftest import run

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def example(name, *args, cwd):
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args], cwd=cwd,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return p.stdout, p.stderr


def test_field_map(tmp_path):
    out, _ = example("field_map.py", "-o", "map.png", cwd=tmp_path)
    png = (tmp_path / "map.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000
    assert "168881 points, SAI ratio 0.1024" in out


def test_sweep_is_sweep_spacings_numbers(tmp_path):
    out, _ = example("sweep.py", cwd=tmp_path)
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 27
    cli = run("optimize-weights", "--mode", "PC", "--electrodes", "6", "--pitch", "1.5")[0]
    row = next(r for r in rows if r["electrodes"] == "6" and r["pitch_mm"] == "1.5"
               and r["mode"] == "PC")
    assert float(row["ratio"]) == json.loads(cli)["ratio"]


def test_trial_loop_delivers_every_trial(tmp_path):
    _, err = example("trial_loop.py", "--answers", "yes", "--log", "t.csv",
                     "--record", "rec.jsonl", cwd=tmp_path)
    rows = list(csv.DictReader(open(tmp_path / "t.csv")))
    assert len(rows) == 6 and all(r["answer"] == "yes" for r in rows)
    expected = {"RA": 9, "SAI": 60, "PC": 75}  # 0.3 s at 30, 200 and 250 Hz
    assert all(int(r["pulses"]) == expected[r["mode"]] for r in rows)
    pulses = [json.loads(line) for line in open(tmp_path / "rec.jsonl")]
    assert len(pulses) == sum(int(r["pulses"]) for r in rows)
    assert "6 trials logged" in err


def trial_loop(*args, cwd, stdin=""):
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, "trial_loop.py"), *args],
                       cwd=cwd, input=stdin, capture_output=True, text=True, timeout=300)
    rows = list(csv.DictReader(open(cwd / "t.csv")))
    return p, rows


def test_trial_loop_q_ends_the_loop_and_is_logged_as_a_quit(tmp_path):
    # y, then something that is not an answer (asked again), then q: two rows, the second
    # a quit, not a "no"; exit 1 with one line saying so, no traceback.
    p, rows = trial_loop("--log", "t.csv", cwd=tmp_path, stdin="y\nmaybe\nq\n")
    assert p.returncode == 1, p.stderr
    assert [r["answer"] for r in rows] == ["yes", "quit"]
    assert "'maybe': answer y, n or q" in p.stderr and "Traceback" not in p.stderr
    assert p.stderr.splitlines()[-1] == (
        "trial_loop.py: stopped by the user (q) after trial 2; 2 trials logged in t.csv")
    # The answers ending is a quit too, said as such.
    p, rows = trial_loop("--log", "t.csv", cwd=tmp_path, stdin="n\n")
    assert p.returncode == 1 and [r["answer"] for r in rows] == ["no", "quit"]
    assert p.stderr.splitlines()[-1] == (
        "trial_loop.py: stopped by the end of the answers after trial 2; 2 trials logged in t.csv")


def interrupt(args, cwd, ready, stdin=""):
    """trial_loop.py with args and stdin, SIGINT once ready(stdout so far) says so: (exit
    code, stderr)."""
    p = subprocess.Popen([sys.executable, os.path.join(EXAMPLES, "trial_loop.py"), *args],
                         cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE)
    p.stdin.write(stdin.encode())
    p.stdin.flush()  # and left open: the next answer never comes
    os.set_blocking(p.stdout.fileno(), False)
    out, deadline = b"", time.monotonic() + 120
    while not ready(out.decode()):
        assert p.poll() is None and time.monotonic() < deadline, p.communicate()
        try:
            out += os.read(p.stdout.fileno(), 4096)
        except BlockingIOError:
            time.sleep(0.01)
    p.send_signal(signal.SIGINT)
    p.stdin.close()
    err = p.stderr.read().decode()
    p.wait(timeout=60)
    return p.returncode, err


def test_trial_loop_ctrl_c_stops_the_output_and_exits_130(tmp_path):
    # During a 10 s stimulus: the output stops at once (the Stimulator's doing), and the
    # example says so in one line, no traceback.
    rec = tmp_path / "rec.jsonl"
    code, err = interrupt(["--answers", "yes", "--log", "t.csv", "--record", "rec.jsonl",
                           "--trial-duration", "10"], tmp_path,
                          lambda _: rec.exists() and rec.stat().st_size > 0)
    assert code == 130, err
    assert "Traceback" not in err
    assert err.splitlines()[-1] == ("trial_loop.py: interrupted (Ctrl-C) during trial 1; "
                                    "output stopped; 0 trials logged in t.csv")
    pulses = [json.loads(line) for line in open(rec)]
    assert pulses and pulses[-1]["t_s"] < 5  # of 10 s
    # At the second question: nothing running, the first trial's row kept.
    code, err = interrupt(["--log", "t.csv", "--trial-duration", "0.05"], tmp_path,
                          lambda out: "trial 2: felt it?" in out, stdin="y\n")
    assert code == 130, err
    assert "Traceback" not in err
    assert err.splitlines()[-1] == ("trial_loop.py: interrupted (Ctrl-C) at trial 2; "
                                    "nothing running; 1 trials logged in t.csv")
    assert [r["answer"] for r in csv.DictReader(open(tmp_path / "t.csv"))] == ["yes"]

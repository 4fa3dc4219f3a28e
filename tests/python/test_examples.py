"""examples/python run as a user runs them, and do what they say."""
import csv
import io
import json
import os
import subprocess
import sys

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
    assert len(rows) == 6 and all(r["answer"] == "1" for r in rows)
    expected = {"RA": 9, "SAI": 60, "PC": 75}  # 0.3 s at 30, 200 and 250 Hz
    assert all(int(r["pulses"]) == expected[r["mode"]] for r in rows)
    pulses = [json.loads(line) for line in open(tmp_path / "rec.jsonl")]
    assert len(pulses) == sum(int(r["pulses"]) for r in rows)
    assert "6 trials logged" in err

"""Shared by the Python module's tests: the programs (on PATH, CTest puts build/tools
first) run on the same input as the module, for comparison."""
import json
import subprocess

import pytest

import tactile_primaries as tp


def run(*args, stdin=None, check=True):
    """A program's (stdout bytes, stderr text, exit code)."""
    p = subprocess.run(list(args), input=stdin, capture_output=True, timeout=300)
    if check and p.returncode != 0:
        raise AssertionError(f"{args} exited {p.returncode}: {p.stderr.decode()}")
    return p.stdout, p.stderr.decode(), p.returncode


def cli_message(*args, stdin=None):
    """A refusal's one line, without the program's name: what the module raises."""
    out, err, code = run(*args, stdin=stdin, check=False)
    assert code == 2 and out == b"" and err.count("\n") == 1, (code, out, err)
    program, _, message = err.rstrip("\n").partition(": ")
    assert program == args[0]
    return message


@pytest.fixture(scope="session")
def sai_doc():
    return tp.optimize_weights(tp.Document.create(), "SAI")


@pytest.fixture(scope="session")
def sai_json():
    return run("optimize-weights", "--mode", "SAI")[0]


def load(b):
    return json.loads(b.decode() if isinstance(b, bytes) else b)

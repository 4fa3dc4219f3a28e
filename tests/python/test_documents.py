"""Documents and the functions against the programs: byte-identical JSON where the
program writes JSON, equal numbers where it writes CSV."""
import json
import warnings

import numpy as np

import pytest

import tactile_primaries as tp
from conftest import load, run


@pytest.mark.parametrize("mode", ["RA", "SAI", "PC"])
def test_optimize_weights_is_the_programs_json(mode):
    cli = run("optimize-weights", "--mode", mode)[0]
    assert tp.optimize_weights(tp.Document.create(), mode).to_json().encode() == cli


def test_optimize_weights_with_options_and_models():
    cli = run("optimize-weights", "--mode", "PC", "--electrodes", "6", "--pitch", "1.5",
              "--model", "rect3d", "--max-current", "1.5", "--random-starts", "3")[0]
    doc = tp.Document.create(electrodes=6, pitch_mm=1.5, model="rect3d")
    out = tp.optimize_weights(doc, "PC", max_current_mA=1.5, random_starts=3)
    assert out.to_json().encode() == cli


def test_a_pixel_and_a_bank_are_the_programs_json():
    grid = ["--grid", "3x3", "--pitch", "2", "--pad", "1x1"]
    cli = run("optimize-weights", *grid, "--at", "2,0", "--mode", "SAI", "--threads", "1")[0]
    doc = tp.Document.create(grid="3x3", pitch_mm=2, pad="1x1")
    assert tp.optimize_weights(doc, "SAI", at=[2, 0], threads=1).to_json().encode() == cli
    cli = run("optimize-weights", "--bank", "--grid", "3x2", "--pitch", "2", "--pad", "1x1")[0]
    bank = tp.optimize_weights(tp.Document.create(grid="3x2", pitch_mm=2, pad="1x1"), bank=True)
    assert bank.to_json().encode() == cli
    # With the modes' recruitment (the gamut's colours), 2 afferents a class.
    cli = run("optimize-weights", "--bank", "--grid", "3x2", "--pitch", "2", "--pad", "1x1",
              "--population", "2", "--seed", "5")[0]
    bank = tp.optimize_weights(tp.Document.create(grid="3x2", pitch_mm=2, pad="1x1"), bank=True,
                               population=2, seed=5)
    assert bank.to_json().encode() == cli
    assert bank["recruitment"]["population"] == 2 and bank["recruitment"]["seed"] == 5


def test_the_threshold_objective_is_the_programs_json():
    # optimize-weights --objective threshold, on a small array and a coarse search (~1 s).
    fibre = ["--max-evaluations", "10", "--tolerance", "0.05", "--offsets", "1", "--threads", "1"]
    cli = run("optimize-weights", "--electrodes", "4", "--mode", "SAI", "--objective",
              "threshold", *fibre)[0]
    out = tp.optimize_weights(tp.Document.create(electrodes=4), "SAI", objective="threshold",
                              max_evaluations=10, tolerance=0.05, offsets=1, threads=1)
    assert out.to_json().encode() == cli
    assert out["objective"] == "threshold" and out["threshold_search"]["evaluations"] <= 10
    assert out["threshold_ratio"]["SAI"] <= out["af_optimum"]["threshold_ratio"]


def test_a_bank_of_several_places_and_timing():
    # --bank with --at repeated: at= a list of places.
    cli = run("optimize-weights", "--bank", "--mode", "PC", "--grid", "5x2", "--pitch", "2",
              "--pad", "1x1", "--neighbourhood", "3", "--at=-2,-1", "--at=0,-1", "--at=2,1")[0]
    doc = tp.Document.create(grid="5x2", pitch_mm=2, pad="1x1")
    bank = tp.optimize_weights(doc, bank=True, modes=["PC"], neighbourhood=3,
                               at=[[-2, -1], [0, -1], [2, 1]])
    assert bank.to_json().encode() == cli
    assert len(bank["pixels"]) == 3
    timed = tp.optimize_weights(tp.Document.create(), "SAI", timing=True)
    assert timed["solver"]["time_s"] >= 0
    assert "time_s" not in tp.optimize_weights(tp.Document.create(), "SAI")["solver"]


def test_document_round_trip_load_and_attributes(tmp_path, sai_json):
    doc = tp.Document.from_json(sai_json.decode())
    assert doc.to_json().encode() == sai_json
    path = tmp_path / "sai.json"
    path.write_bytes(sai_json)
    assert tp.Document.load(str(path)).to_json().encode() == sai_json
    d = load(sai_json)
    assert doc.array == d["array"] and doc.model == d["model"]
    assert doc.receptors == d["receptors"] and doc["mode"] == "SAI" and "ratio" in doc
    assert isinstance(doc.weights, np.ndarray) and list(doc.weights) == d["weights"]
    doc.weights = [0, 0, -1, 1, 0, 0, 0, 0]
    assert load(doc.to_json())["weights"] == [0, 0, -1, 1, 0, 0, 0, 0]
    with pytest.raises(tp.BadInput, match="expected 8 values"):
        doc.weights = [1, -1]


def axis(lo, hi, step):
    """af-field's axis: lo + i step, the last at most hi (lib/core/number.hpp's Axis)."""
    n = int(round((hi - lo) / step)) + 1
    return np.array([min(lo + i * step, hi) for i in range(n)])


def text(x, y, h, v):
    """Rows as af-field writes them: %.10g, -0 as 0."""
    def g(a):
        s = "%.10g" % a
        return "0" if s == "-0" else s
    return [",".join(g(a) for a in row) for row in zip(x, y, h, v)]


def test_af_field_equals_the_programs_grid(sai_json, tmp_path):
    out = run("af-field", "--config", "-", "--x", "-5:5:0.5", "--y", "0.2:3:0.2",
              stdin=sai_json)[0].decode().splitlines()
    doc = tp.Document.from_json(sai_json.decode())
    x, y = axis(-5, 5, 0.5), axis(0.2, 3, 0.2)[:, None]
    h, v = tp.af_field(doc, x, y)  # shapes broadcast: depths down, positions across
    assert h.shape == (len(y), len(x))
    X, Y = np.broadcast_arrays(x, y)
    assert text(X.ravel(), Y.ravel(), h.ravel(), v.ravel()) == out[1:]
    # The same points flat, and a scalar: linear in the amplitude.
    h2, v2 = tp.af_field(doc, X.ravel(), Y.ravel())
    assert np.array_equal(h2, h.ravel()) and np.array_equal(v2, v.ravel())
    hs, vs = tp.af_field(doc, x[11], float(y[4, 0]), amplitude_mA=1.0)
    assert hs.shape == () and float(hs) == pytest.approx(float(h[4, 11]) / 2, rel=1e-12)


def test_af_field_plane_of_a_grid_equals_the_programs():
    doc = tp.Document.create(grid="3x3", pitch_mm=2, pad="1x1")
    doc.weights = [0, 0, 0, -0.5, 1, -0.5, 0, 0, 0]
    out = run("af-field", "--grid", "3x3", "--pitch", "2", "--pad", "1x1",
              "--weights", "0,0,0,-0.5,1,-0.5,0,0,0", "--plane-depth", "0.9",
              "--x", "-4:4:0.5", "--z-grid", "-4:4:0.5")[0].decode().splitlines()
    x, z = axis(-4, 4, 0.5), axis(-4, 4, 0.5)[:, None]
    h, v = tp.af_field(doc, x, 0.9, z)
    X, Z = np.broadcast_arrays(x, z)
    assert text(X.ravel(), Z.ravel(), h.ravel(), v.ravel()) == out[1:]


def test_summarize_equals_the_programs_summary(sai_json):
    cli = load(run("af-field", "--config", "-", "--summary", stdin=sai_json)[0])
    assert tp.summarize(tp.Document.from_json(sai_json.decode())) == cli


def test_fiber_threshold_equals_the_programs(sai_json):
    cli = load(run("fiber-threshold", stdin=sai_json)[0])
    py = tp.fiber_threshold(tp.Document.from_json(sai_json.decode()))
    assert py == cli
    cli = load(run("fiber-threshold", "--model", "senn", "--width", "100", "--monophasic",
                   "--conductor", "rect3d", stdin=sai_json)[0])
    py = tp.fiber_threshold(tp.Document.from_json(sai_json.decode()), model="senn",
                            width_us=100, monophasic=True, conductor="rect3d")
    assert py == cli
    # RA as an afferent (RA alone, a coarse lattice: a few seconds).
    ra = json.loads(sai_json)
    ra["receptors"] = [r for r in ra["receptors"] if r["name"] == "RA"]
    ra = json.dumps(ra).encode()
    cli = load(run("fiber-threshold", "--geometry", "afferent", "--tolerance", "0.05",
                   stdin=ra)[0])
    py = tp.fiber_threshold(tp.Document.from_json(ra.decode()), geometry="afferent",
                            tolerance=0.05)
    assert py == cli
    assert py["thresholds"]["receptors"]["RA"]["stem"] in ("-x", "+x")


def test_fiber_threshold_warns_as_the_program_does():
    # The program's stderr warnings are UserWarnings, word for word: the PC mode's target
    # does not fire first on the paper's array; the SAI mode's does (no warning).
    pc = tp.optimize_weights(tp.Document.create(), "PC")
    _, err, _ = run("fiber-threshold", stdin=pc.to_json().encode())
    said = [l.removeprefix("fiber-threshold: warning: ") for l in err.splitlines()
            if l.startswith("fiber-threshold: warning: ")]
    assert len(said) == 1 and said[0].startswith("PC mode: SAI fires first")
    with pytest.warns(UserWarning) as w:
        tp.fiber_threshold(pc)
    assert [str(x.message) for x in w] == said
    sai = tp.optimize_weights(tp.Document.create(), "SAI")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tp.fiber_threshold(sai)


def columns(csv):
    """A CSV table as fiber_threshold returns it: {name: [values]}, numbers as floats, an
    empty cell None, the receptor and class columns str."""
    rows = [line.split(",") for line in csv.decode().splitlines()]
    def cell(name, text):
        if text == "":
            return None
        if name in ("receptor", "class"):
            return text
        try:
            return float(text)
        except ValueError:
            return text
    return {name: [cell(name, r[k]) for r in rows[1:]] for k, name in enumerate(rows[0])}


def test_fiber_threshold_tables_are_the_programs(sai_json, tmp_path):
    # The strength-duration table (a coarse lattice, two offsets: a few seconds).
    fast = ["--tolerance", "0.05", "--offsets", "2"]
    doc = tp.Document.from_json(sai_json.decode())
    cli = run("fiber-threshold", "--strength-duration", "--widths", "200,50", "--monophasic",
              *fast, stdin=sai_json)[0]
    py = tp.fiber_threshold(doc, strength_duration=True, widths_us=[200, 50], monophasic=True,
                            tolerance=0.05, offsets=2)
    assert py == columns(cli)
    assert py["width_us"] == [50.0, 200.0, 50.0, 200.0, 50.0, 200.0]
    assert py["receptor"] == ["RA", "RA", "SAI", "SAI", "PC", "PC"]
    # A population, its afferents and its recruitment curves.
    curves = tmp_path / "r.csv"
    cli = run("fiber-threshold", "--population", "2", "--seed", "5", "--recruitment",
              str(curves), *fast, stdin=sai_json)[0]
    py = tp.fiber_threshold(doc, population=2, seed=5, tolerance=0.05, offsets=2)
    assert py["afferents"] == columns(cli)
    assert py["recruitment"] == columns(curves.read_bytes())
    assert py["afferents"]["class"] == ["RA", "RA", "SAI", "SAI", "PC", "PC"]


def test_fiber_threshold_with_a_stimulus_is_the_programs(sai_json, tmp_path):
    # The stimulus's amplitude in units of each threshold (threshold_multiples); a stale
    # one in the document is replaced, as the program replaces it.
    doc = tp.Document.from_json(sai_json.decode())
    path = tmp_path / "sai-stimulus.json"
    path.write_text(tp.make_pulse(doc, 0.8, 200, duration_s=0.1).to_json())
    stale = json.loads(sai_json)
    stale["threshold_multiples"] = {"SAI": 9.0}
    stale = json.dumps(stale, indent=2).encode()
    cli = load(run("fiber-threshold", "--stimulus", str(path), "--tolerance", "0.05",
                   stdin=stale)[0])
    py = tp.fiber_threshold(tp.Document.from_json(stale.decode()), stimulus=path,
                            tolerance=0.05)
    assert py == cli
    assert py["threshold_multiples"]["SAI"] == pytest.approx(
        0.8 / py["thresholds"]["receptors"]["SAI"]["threshold_mA"], rel=1e-12)


def test_make_pulse_is_the_programs_json(sai_json):
    cli = run("make-pulse", "--amplitude", "1.2", "--frequency", "150", "--duration", "2",
              "--width", "100", "--balance-width", "300", stdin=sai_json)[0]
    s = tp.make_pulse(tp.Document.from_json(sai_json.decode()), 1.2, 150, duration_s=2,
                      width_us=100, balance_width_us=300)
    assert s.to_json().encode() == cli
    assert tp.Stimulus.from_json(cli.decode()).to_json().encode() == cli
    assert (s.channels, s.patterns, s.duration_s) == (8, 1, 2.0)


def test_a_shaped_pulse_is_the_programs(sai_json):
    """phases= is make-pulse's --phases; the document's pulse is the default for both."""
    shape = [(500, 0.1), (200, 1), (50, 0), (500, -0.5)]
    cli = run("make-pulse", "--amplitude", "1", "--count", "3",
              "--phases", ",".join(f"{d}:{l}" for d, l in shape), stdin=sai_json)[0]
    doc = tp.Document.from_json(sai_json.decode())
    assert tp.make_pulse(doc, 1.0, count=3, phases=shape).to_json().encode() == cli
    carried = json.loads(sai_json)
    carried["pulse"] = {"phases": [{"duration_us": d, "level": l} for d, l in shape]}
    carried = json.dumps(carried).encode()
    py = tp.make_pulse(tp.Document.from_json(carried.decode()), 1.0, count=3)
    assert py.to_json().encode() == run("make-pulse", "--amplitude", "1", "--count", "3",
                                        stdin=carried)[0]
    assert json.loads(py.to_json())["pulse"]["phases"][1] == {"duration_us": 200, "level": 1}
    with pytest.raises(ValueError, match="not charge balanced"):
        tp.make_pulse(doc, 1.0, count=3, phases=[(200, 1), (201, -1)])
    with pytest.raises(ValueError, match="--phases excludes --width"):
        tp.make_pulse(doc, 1.0, count=3, phases=shape, width_us=100)
    # fiber_threshold(phases=) is fiber-threshold --phases.
    cli = load(run("fiber-threshold", "--phases", "200:1,100:0,800:-0.25", "--tolerance", "0.05",
                   stdin=sai_json)[0])
    assert tp.fiber_threshold(doc, phases=[(200, 1), (100, 0), (800, -0.25)],
                              tolerance=0.05) == cli
    assert cli["thresholds"]["pulse"]["phases"][2] == {"duration_us": 800, "level": -0.25}


def test_af_field_reads_any_view_as_its_copy(sai_doc):
    """Broadcast, Fortran-ordered, reversed, strided and 3-D views give the values of their
    contiguous copies (the arrays are read through their strides)."""
    rng = np.random.default_rng(7)
    base_x = rng.uniform(-6, 6, size=(7, 9))
    base_y = rng.uniform(0.1, 3, size=(7, 9))
    views = [
        (base_x, base_y),
        (np.asfortranarray(base_x), base_y),
        (base_x[::-1, ::-2], base_y[::-1, ::-2]),
        (base_x[:, :1], base_y[:1, :]),            # broadcast to (7, 9)
        (base_x.T, base_y.T),
        (base_x.reshape(7, 3, 3), 0.9),           # a scalar depth, 3-D
        (base_x[2, :], base_y[:, 3][:, None]),     # row against column
        (np.array(1.5), np.array(0.7)),            # 0-d
        (np.empty((0, 4)), np.empty((0, 4))),      # nothing
    ]
    for x, y in views:
        h, v = tp.af_field(sai_doc, x, y)
        X, Y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        hc, vc = tp.af_field(sai_doc, np.array(X, order="C"), np.array(Y, order="C"))
        assert h.shape == X.shape and np.array_equal(h, hc) and np.array_equal(v, vc)

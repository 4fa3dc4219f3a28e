"""Bad input raises BadInput (a ValueError) with the program's message, and the
interpreter stays usable."""
import pytest

import tactile_primaries as tp
from conftest import cli_message


def test_messages_are_the_programs(sai_json, sai_doc):
    cases = [
        (lambda: tp.make_pulse(sai_doc, 3.0, 200),
         ("make-pulse", "--amplitude", "3"), sai_json),
        (lambda: tp.make_pulse(sai_doc, 1.0, 2000),
         ("make-pulse", "--amplitude", "1", "--frequency", "2000"), sai_json),
        (lambda: tp.make_pulse(sai_doc, 1.0, 200, width_us=5),
         ("make-pulse", "--amplitude", "1", "--width", "5"), sai_json),
        (lambda: tp.optimize_weights(tp.Document.create(), "XY"),
         ("optimize-weights", "--mode", "XY"), None),
        (lambda: tp.optimize_weights(tp.Document.create(grid="2x2"), "SAI"),
         ("optimize-weights", "--grid", "2x2", "--mode", "SAI"), None),
        (lambda: tp.fiber_threshold(sai_doc, model="hh"),
         ("fiber-threshold", "--model", "hh"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, geometry="bent"),
         ("fiber-threshold", "--geometry", "bent"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, model="senn", geometry="afferent"),
         ("fiber-threshold", "--model", "senn", "--geometry", "afferent"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, widths_us=[100]),
         ("fiber-threshold", "--widths", "100"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, strength_duration=True, widths_us=[100, 0]),
         ("fiber-threshold", "--strength-duration", "--widths", "100,0"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, strength_duration=True, population=2),
         ("fiber-threshold", "--strength-duration", "--population", "2"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, seed=3),
         ("fiber-threshold", "--seed", "3"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, population=1, seed=-1),
         ("fiber-threshold", "--population", "1", "--seed", "-1"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, population=1, seed=2**64),
         ("fiber-threshold", "--population", "1", "--seed", str(2**64)), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, population=10001),
         ("fiber-threshold", "--population", "10001"), sai_json),
        (lambda: tp.fiber_threshold(sai_doc, population=7600),
         ("fiber-threshold", "--population", "7600"), sai_json),
        (lambda: tp.Document.create(electrodes=300),
         ("af-field", "--electrodes", "300"), None),
        (lambda: tp.Document.create(model="nope"),
         ("af-field", "--model", "nope"), None),
    ]
    for call, args, stdin in cases:
        expected = cli_message(*args, stdin=stdin)
        with pytest.raises(tp.BadInput) as e:
            call()
        assert str(e.value) == expected
        assert isinstance(e.value, ValueError)
    # Still usable afterwards.
    assert tp.optimize_weights(tp.Document.create(), "SAI")["mode"] == "SAI"


def test_documents_that_do_not_parse(sai_json):
    bad = sai_json.decode().replace('"weights": [', '"weights": ["a", ', 1)
    with pytest.raises(ValueError, match="weights"):
        tp.Document.from_json(bad)
    with pytest.raises(ValueError):
        tp.Document.from_json("{not json")
    with pytest.raises(ValueError, match="cannot"):
        tp.Document.load("/nonexistent/doc.json")
    with pytest.raises(ValueError):
        tp.Stimulus.from_json('{"format": "tactile-primaries/stimulus/1"}')


def test_af_field_refuses_points_and_shapes(sai_doc):
    with pytest.raises(tp.BadInput, match="depths must be > 0"):
        tp.af_field(sai_doc, [0.0], [0.0])
    with pytest.raises(ValueError):
        tp.af_field(sai_doc, [0.0, 1.0], [0.5, 0.6, 0.7])  # do not broadcast
    with pytest.raises(tp.BadInput, match="z_mm"):
        tp.af_field(sai_doc, [0.0], [0.5], [0.0])  # line2d has no z
    with pytest.raises(tp.BadInput, match="--amplitude"):
        tp.af_field(sai_doc, [0.0], [0.5], amplitude_mA=1e9)
    # A point at a buried source (the conductor says where its sources are; model/setup).
    buried = tp.Document.from_json(
        '{"array": {"electrodes": 3, "pitch_mm": 1}, "weights": [1, -2, 1],'
        ' "model": {"conductor": "point3d", "source_depth_mm": 3}}')
    assert tp.af_field(buried, [0.0], [2.0])[0].shape == (1,)
    with pytest.raises(tp.BadInput, match=r"^point \(1, 2\.995\) mm is 0\.005 mm from a point "
                                          r"source \(model\.source_depth_mm 3 mm under the electrode at 1 mm\)"):
        tp.af_field(buried, [0.0, 1.0], [2.0, 2.995])


def test_flag_level_checks_say_what_the_programs_say(sai_doc, sai_json):
    # The programs' words (CLI11's without its "(see --help)").
    for call, args in (
        (lambda: tp.fiber_threshold(sai_doc, offsets=0), ("fiber-threshold", "--offsets", "0")),
        (lambda: tp.fiber_threshold(sai_doc, threads=300), ("fiber-threshold", "--threads", "300")),
        (lambda: tp.fiber_threshold(sai_doc, monophasic=True, interphase_us=10),
         ("fiber-threshold", "--monophasic", "--interphase", "10")),
        (lambda: tp.make_pulse(sai_doc, 1.0, 200, duration_s=1, count=3),
         ("make-pulse", "--amplitude", "1", "--duration", "1", "--count", "3")),
    ):
        expected = cli_message(*args, stdin=sai_json).removesuffix(" (see --help)")
        with pytest.raises(tp.BadInput) as e:
            call()
        assert str(e.value) == expected
    for call, args in (
        (lambda: tp.make_pulse(sai_doc, 1.0, float("inf")),
         ("make-pulse", "--amplitude", "1", "--frequency", "inf")),
        (lambda: tp.fiber_threshold(sai_doc, tolerance=0.2), ("fiber-threshold", "--tolerance", "0.2")),
    ):
        expected = cli_message(*args, stdin=sai_json)
        with pytest.raises(tp.BadInput) as e:
            call()
        assert str(e.value) == expected


def test_optimize_weights_refuses_as_the_program_does():
    # One request (lib/requests/optimize) behind both: the same checks, in the same order.
    doc = tp.Document.create()
    grid = tp.Document.create(grid="3x3", pitch_mm=2)
    for call, args in (
        (lambda: tp.optimize_weights(doc, "SAI", width_us=100), ("--width", "100")),
        (lambda: tp.optimize_weights(doc, "SAI", fibre_model="senn"), ("--fibre-model", "senn")),
        (lambda: tp.optimize_weights(doc, "SAI", offsets=8), ("--offsets", "8")),
        (lambda: tp.optimize_weights(doc, "SAI", threads=2), ("--threads", "2")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="threshold", certify=True),
         ("--objective", "threshold", "--certify")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="threshold", fibre_model="hh"),
         ("--objective", "threshold", "--fibre-model", "hh")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="threshold", max_evaluations=10,
                                     offsets=1, tolerance=0.1, width_us=0.5),
         ("--objective", "threshold", "--max-evaluations", "10", "--offsets", "1",
          "--tolerance", "0.1", "--width", "0.5")),
        (lambda: tp.optimize_weights(doc, "SAI", at=[-0.5], objective="threshold"),
         ("--at", "-0.5", "--objective", "threshold")),
        (lambda: tp.optimize_weights(doc, "SAI", population=10), ("--population", "10")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="selectivity", seed=-1),
         ("--objective", "selectivity", "--seed", "-1")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="selectivity", max_charge_nC=-5),
         ("--objective", "selectivity", "--max-charge", "-5")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="selectivity", population=1000,
                                     max_evaluations=1000),
         ("--objective", "selectivity", "--population", "1000", "--max-evaluations", "1000")),
        (lambda: tp.optimize_weights(doc, "SAI", at=[0, 0]), ("--at", "0,0")),
        (lambda: tp.optimize_weights(doc, "SAI", at=[-0.5], radius_mm=0),
         ("--at", "-0.5", "--radius", "0")),
        (lambda: tp.optimize_weights(doc, "SAI", min_target_af=-1), ("--min-target-af", "-1")),
        (lambda: tp.optimize_weights(grid, bank=True, pattern_starts=2),
         ("--grid", "3x3", "--pitch", "2", "--bank", "--pattern-starts", "2")),
        (lambda: tp.optimize_weights(grid, "SAI", at=[0, 0], neighbourhood=3),
         ("--grid", "3x3", "--pitch", "2", "--at", "0,0", "--neighbourhood", "3")),
    ):
        args = ("optimize-weights",) + (() if "--bank" in args else ("--mode", "SAI")) + args
        expected = cli_message(*args)
        with pytest.raises(tp.BadInput) as e:
            call()
        assert str(e.value) == expected, args
    # The parser's checks, in its words.
    for call, args in (
        (lambda: tp.optimize_weights(doc, "SAI", objective="charge"), ("--objective", "charge")),
        (lambda: tp.optimize_weights(doc, "SAI", pattern_starts=5), ("--pattern-starts", "5")),
        (lambda: tp.optimize_weights(doc, "SAI", objective="threshold", max_evaluations=5),
         ("--objective", "threshold", "--max-evaluations", "5")),
    ):
        expected = cli_message("optimize-weights", "--mode", "SAI", *args)
        with pytest.raises(tp.BadInput) as e:
            call()
        assert str(e.value) == expected.removesuffix(" (see --help)"), args


def test_modes_weights_and_paths(sai_doc, tmp_path, sai_json):
    doc = tp.Document.create(grid="2x2", pitch_mm=2, pad="1x1")
    with pytest.raises(tp.BadInput, match="no modes given"):
        tp.optimize_weights(doc, bank=True, modes=[])
    with pytest.raises(tp.BadInput, match="give one"):
        tp.optimize_weights(doc, "SAI", bank=True, modes=["RA"])
    with pytest.raises(tp.BadInput, match="bank=True only"):
        tp.optimize_weights(tp.Document.create(), modes=["RA", "SAI"])
    with pytest.raises(tp.BadInput, match="given twice"):
        tp.optimize_weights(doc, bank=True, modes=["RA", "RA"])
    with pytest.raises(ValueError):  # a read-only copy: item assignment would be lost
        sai_doc.weights[0] = 0.5
    with pytest.raises(tp.BadInput, match="not a finite number"):
        tp.Document.create().weights = [float("nan")] * 8
    path = tmp_path / "sai.json"
    path.write_bytes(sai_json)
    assert tp.Document.load(path).to_json().encode() == sai_json  # a pathlib.Path
    with pytest.raises(tp.BadInput, match="non-finite"):
        tp.af_field(sai_doc, [0.0], [0.5], amplitude_mA=float("nan"))


def test_messages_escape_user_text():
    # Issue 38: a byte that is not UTF-8 in a path made a UnicodeDecodeError instead of
    # BadInput, and a NUL in a document's key cut the message short.
    with pytest.raises(tp.BadInput) as e:
        tp.Document.load(b"/nonexistent/\xff\x1b")
    assert str(e.value) == "document: cannot open '/nonexistent/\\xFF\\x1B': No such file or directory"
    with pytest.raises(tp.BadInput) as e:
        tp.Document.from_json('{"format": "tactile-primaries/1", "array": '
                              '{"electrodes": 8, "pitch_mm": 1.0, "x\\u0000\\u001b": 1}}')
    assert str(e.value) == "array: unknown key 'x\\x00\\x1B'"

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

"""tactile-primaries from Python: the C++ library's documents, fields, weights, fibre
thresholds, stimuli and stimulator, with NumPy arrays in and out.

    import tactile_primaries as tp
    doc = tp.optimize_weights(tp.Document.create(), "SAI")
    af_h, af_v = tp.af_field(doc, x_mm, y_mm)          # NumPy arrays, any shapes that broadcast
    stim = tp.make_pulse(doc, 1.0, 200, duration_s=1)
    with tp.Stimulator("emu") as s:
        s.deliver(stim)

Every function checks its input as the programs do: bad input raises BadInput (a
ValueError), a runtime failure Failure (a RuntimeError), with the programs' message.
Reference: docs/python.md.
"""

from __future__ import annotations

# NumPy is imported where it is first needed, not here: `import tactile_primaries` stays
# fast (docs/python.md, benchmarks), and pybind11 loads it lazily too.
from ._core import (  # noqa: F401  (the public API)
    BadInput,
    Document,
    Failure,
    Stimulus,
    __version__,
    fiber_threshold,
    make_pulse,
    optimize_weights,
    summarize,
)
from . import _core

__all__ = [
    "BadInput",
    "Document",
    "Failure",
    "Stimulator",
    "Stimulus",
    "__version__",
    "af_field",
    "fiber_threshold",
    "make_pulse",
    "optimize_weights",
    "summarize",
]


def af_field(doc, x_mm, y_mm, z_mm=None, *, amplitude_mA=None):
    """The activating function (V/ms) of the document's weights at points.

    x_mm along the skin, y_mm the depth (> 0), and for 3-D models z_mm across (required
    under a 2-D array): array-likes of any shapes that broadcast together.  Returns
    (af_h, af_v), the AF of a horizontal fibre along x and of a vertical one, of the
    reference 10 um fibre, with every electrode at its weight times amplitude_mA (default:
    the document's max_current_mA), as af-field prints them.
    """
    import numpy as _np

    arrays = [x_mm, y_mm] if z_mm is None else [x_mm, y_mm, z_mm]
    # Views of one shape (nothing copied): the library reads them through their strides.
    arrays = _np.broadcast_arrays(*[_np.asarray(a, dtype=float) for a in arrays])
    return _core._af_points(doc, arrays[0], arrays[1], arrays[2] if z_mm is not None else None,
                            amplitude_mA)


def _as_stimulus(stimulus):
    if isinstance(stimulus, Stimulus):
        return stimulus
    if isinstance(stimulus, str):
        text = stimulus.lstrip()
        return Stimulus.from_json(stimulus) if text.startswith("{") else Stimulus.load(stimulus)
    raise TypeError("stimulus: a Stimulus, its JSON text or a file's path")


class Stimulator:
    """A stimulator, as stimctl drives it: port "emu" (the in-process emulator) or a serial
    port's path.

        with Stimulator("emu", record="pulses.jsonl") as s:
            s.deliver(stimulus, duration_s=1)        # blocks; the GIL is released
            s.start_live(stimulus)                   # then live frames:
            s.set_currents([...])                    #   a single stimulus's currents, or
            s.set_amplitudes([...])                  #   each pattern's amplitude
            s.stop()                                 # the end of the live input

    Every way a delivery ends stops the output first: its own end, an exception, leaving
    the `with` block, close() (from any thread: a delivery running on another stops first),
    KeyboardInterrupt (Ctrl-C) and any exception a signal handler raises while deliver()
    or a live frame waits.  One delivery or live session at a time holds the port.  Only this host's session can keep the output alive; if
    the process dies, the device's watchdog stops it within 300 ms.
    """

    def __init__(self, port="emu", *, baud=115200, emu_channels=8, record=None,
                 backend="auto", emu_skin=None, emu_compliance_V=None, contact_loss="stop",
                 probe_mA=None, hold_sensation=False):
        """emu_skin: the emulator's skin file (stimctl --emu-skin; docs/skin.md): every
        recorded pulse then carries voltage_V and impedance_kohm; emu_compliance_V its
        output stage's compliance (1 to 1000 V [100]).  contact_loss: on a device that
        measures, "stop" the whole output when a pad loses contact, or "suspend" only the
        patterns that drive it, at probe_mA (0.01 to 0.5 [0.05]) until a probe finds the
        contact again (stimctl --contact-loss, --probe-current).  hold_sensation: hold each
        pattern's pulse energy against the stimulus's reference_impedance_kohm as the skin
        changes (stimctl --hold-sensation; not with start_live)."""
        self._s = _core._Stimulator(port, baud, emu_channels, record, backend, emu_skin,
                                    emu_compliance_V, contact_loss, probe_mA, hold_sensation)
        self.port = port

    def __enter__(self):
        self._s.open()
        return self

    def __exit__(self, exc_type, exc, tb):
        try:
            if exc_type is None:
                self._s.stop()  # a live session's end: raises what ended it, if it failed
        finally:
            self.close()  # stops any output at once
        return False

    def open(self):
        """Opens the port (exclusively); deliver() opens it when needed."""
        self._s.open()

    def deliver(self, stimulus, duration_s=None):
        """Delivers a stimulus (a Stimulus, its JSON or a file) and returns stimctl's report:
        pulses, peak_mA, seconds, end, retransmissions (and impedances_kohm from a device
        that measures).  duration_s stops it sooner; a guard of a device that measures
        stopping it raises Failure naming the channel, the time and the cause."""
        return self._s.deliver(_as_stimulus(stimulus), duration_s)

    def start_live(self, stimulus, duration_s=None):
        """Starts the stimulus and returns at once; live frames follow (set_currents,
        set_amplitudes) until stop(), or until duration_s (s) has run.  What the frames
        need (numpy) is loaded before the output starts, so that the first frame is not
        held up by an import while the output runs."""
        import numpy  # noqa: F401  (about 0.3 s on a first import)

        self._s.start_live(_as_stimulus(stimulus), duration_s)

    def set_currents(self, currents_mA):
        """A live frame: every channel's current (mA, + cathodic), checked as the stimulus
        was; applied at the next pulse.  Its amplitude (for set_amplitudes) is its largest
        current.  True when taken; False when the live session had already completed its
        duration (nothing sent; stop() returns its report)."""
        import numpy as _np

        return self._s.set_currents([float(c) for c in _np.asarray(currents_mA, dtype=float).ravel()])

    def set_amplitudes(self, amplitudes_mA):
        """A live frame: each pattern's amplitude (mA, 0 to its own): the current of a
        weight-1 electrode of the pattern in force (after set_currents, that frame's).
        True when taken; False when the live session had already completed its duration."""
        import numpy as _np

        return self._s.set_amplitudes([float(a) for a in _np.asarray(amplitudes_mA, dtype=float).ravel()])

    def stop(self):
        """Ends a live session (the output stops) and returns its report."""
        return self._s.stop()

    @property
    def running(self):
        """True while a live session runs."""
        return self._s.running

    def check_impedance(self, stimulus, probe_mA=0.05):
        """stimctl --check-impedance without the stimulus: a probe of probe_mA (0.01 to 0.5)
        on every pad the stimulus uses, on a device that measures.  Returns one dict per
        pad (channel, probe_mA, contact, impedance_kohm, voltage_V, peak_mA, needed_V: the
        voltage at the stimulus's peak); raises BadInput naming a pad without contact, or
        one whose peak needs more than the device's compliance, as stimctl refuses."""
        return self._s.check_impedance(_as_stimulus(stimulus), probe_mA)

    def impedances(self):
        """A device that measures (protocol 7: stimctl --emu-skin, stim-emu --skin): each
        channel's last impedance in kOhm, as the session last read it (every 0.25 s while
        it runs, when a guard stops it, and at its end): None where the channel carried no
        current, inf where none flowed (no contact).  Empty before any reading, and from a
        device that does not measure.  A delivery's report has the final ones as
        impedances_kohm; each record line has voltage_V and impedance_kohm per pulse."""
        return self._s.impedances()

    def close(self):
        """Stops any output at once and closes the port."""
        self._s.close()

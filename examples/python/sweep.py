#!/usr/bin/env python3
"""A design sweep in a few lines: every mode's ratio over array sizes and pitches (lower
is more selective), as sweep-spacing computes it, without a process per design.

    python3 sweep.py > sweep.csv
"""
import csv
import sys

import tactile_primaries as tp

out = csv.writer(sys.stdout)
out.writerow(["electrodes", "pitch_mm", "mode", "ratio"])
for n in (4, 6, 8):
    for pitch in (0.5, 1.0, 1.5):
        doc = tp.Document.create(electrodes=n, pitch_mm=pitch)
        for mode in ("RA", "SAI", "PC"):
            out.writerow([n, pitch, mode, tp.optimize_weights(doc, mode)["ratio"]])

#!/usr/bin/env python3
"""A field map: the SAI mode's activating function under the paper's array, horizontal
fibres (SAI, PC) and vertical ones (RA), over depth and position, plotted with Matplotlib.

    python3 field_map.py -o sai-field.png
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tactile_primaries as tp  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("-o", "--output", default="sai-field.png")
parser.add_argument("--mode", default="SAI", choices=["RA", "SAI", "PC"])
args = parser.parse_args()

doc = tp.optimize_weights(tp.Document.create(), args.mode)
x = np.linspace(-6, 6, 601)            # mm along the skin
y = np.linspace(0.2, 3, 281)[:, None]  # mm deep: a column, so the two broadcast
af_h, af_v = tp.af_field(doc, x, y)    # V/ms, one value per (y, x)

fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), sharey=True)
for ax, af, title in ((axes[0], af_h, "horizontal fibres (SAI, PC)"),
                      (axes[1], af_v, "vertical fibres (RA)")):
    lim = np.percentile(np.abs(af), 99)
    im = ax.pcolormesh(x, y[:, 0], af, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
    ax.set_title(title)
    ax.set_xlabel("x (mm)")
    fig.colorbar(im, ax=ax, label="AF (V/ms)")
axes[0].set_ylabel("depth (mm)")
axes[0].invert_yaxis()
fig.suptitle(f"{args.mode} mode, ratio {doc['ratio']:.3f}, at {doc.max_current_mA} mA")
fig.tight_layout()
fig.savefig(args.output, dpi=120)
print(f"{args.output}: {af_h.size} points, {args.mode} ratio {doc['ratio']:.4f}")

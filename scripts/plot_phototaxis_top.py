#!/usr/bin/env python3
"""Top view of the phototaxis moths over the second half of the run, the lamp's pull at
0° (the curl-noise paper's words alone) and at the scenario's 70° (docs/path-field.md,
"Chasing and phototaxis"), with the mean angular momentum about the lamp's vertical axis.

    ./build/swarmcl run examples/scenarios/path_phototaxis.json --out out/ph70 --format npy --every 1
    mkdir -p out && sed 's/"angle_deg": 70/"angle_deg": 0/' examples/scenarios/path_phototaxis.json > out/ph0.json
    ./build/swarmcl run out/ph0.json --out out/ph0 --format npy --every 1
    python scripts/plot_phototaxis_top.py out/ph0 out/ph70 docs/images/path_phototaxis_top.png
"""
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LAMP, BULB = np.array([7.2, 5.0, 5.8]), 0.25


def main(straight: str, turned: str, out: str) -> None:
    fig, axs = plt.subplots(1, 2, figsize=(8, 4), dpi=90)
    for ax, d, title in [(axs[0], straight, "angle 0° (the paper's words alone)"),
                         (axs[1], turned, "angle 70° (the scenario)")]:
        p = np.load(f"{d}/path_phototaxis_positions.npy")
        v = np.load(f"{d}/path_phototaxis_velocities.npy")
        h = p.shape[0] // 2
        x, w = p[h:] - LAMP, v[h:]
        lz = (x[..., 0] * w[..., 1] - x[..., 1] * w[..., 0]).mean()
        for a in range(p.shape[1]):
            ax.plot(p[h:, a, 0], p[h:, a, 1], lw=0.6)
        ax.add_patch(plt.Circle((LAMP[0], LAMP[1]), BULB, color="gold", zorder=5))
        ax.set_xlim(LAMP[0] - 1.3, LAMP[0] + 1.3)
        ax.set_ylim(LAMP[1] - 1.3, LAMP[1] + 1.3)
        ax.set_aspect("equal")
        ax.set_title(f"{title}\nmean L_z = {lz:+.3f} m²/s", fontsize=9)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.tight_layout()
    fig.savefig(out)


if __name__ == "__main__":
    main(*sys.argv[1:4])

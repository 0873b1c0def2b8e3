#!/usr/bin/env python3
"""Draws docs/images/energy-scenarios.png: the FASTSWARM Table 1 scenarios
(examples/scenarios/energy_*.json) after a few seconds, through the Python
package.  python3 scripts/plot_energy_figures.py [out.png]"""
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import swarmcl  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def run(ctx, name, steps, trail=0):
    with open(os.path.join(ROOT, "examples", "scenarios", name + ".json")) as f:
        sc = json.load(f)
    with swarmcl.Scenario.parse(json.dumps(sc)) as s, s.create_swarm(ctx) as swarm:
        swarm.step(steps - trail)
        tr = []
        for _ in range(trail):
            swarm.step(1)
            tr.append(swarm.positions)
        return sc, swarm.positions, np.array(tr)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "docs", "images", "energy-scenarios.png")
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.2))
    with swarmcl.Context() as ctx:
        for ax, name, title in ((axes[0], "energy_heart", "heart, 500 insects, 11 keypoints"),
                                (axes[1], "energy_star", "star, 500 insects, 10 keypoints")):
            sc, p, tr = run(ctx, name, 800, trail=40)
            for i in range(0, tr.shape[1], 5):
                ax.plot(tr[:, i, 0], tr[:, i, 2], lw=0.5, color="0.6")
            ax.scatter(p[:, 0], p[:, 2], s=2, c=np.arange(len(p)) % 2, cmap="coolwarm")
            kp = np.array(sc["model"]["keypoints"])
            ax.plot(*np.vstack([kp, kp[:1]])[:, [0, 2]].T, "k--", lw=0.8)
            ax.scatter(kp[:, 0], kp[:, 2], marker="x", c="k")
            ax.set_title(title + " (8 s)")
        sc, p, tr = run(ctx, "energy_aggregation_300", 1000, trail=50)
        for i in range(0, tr.shape[1], 3):
            axes[2].plot(tr[:, i, 0], tr[:, i, 1], lw=0.5, color="0.6")
        axes[2].scatter(p[:, 0], p[:, 1], s=3)
        axes[2].set_title("aggregation, 300 insects (10 s), last 0.5 s")
        sc, p, tr = run(ctx, "energy_escaping", 300, trail=1)
        st = sc["model"]["stimuli"][0]
        o = np.array(st["position"]) + np.array(st["velocity"]) * 300 * sc["dt"]
        axes[3].scatter(p[:, 0], p[:, 1], s=4)
        axes[3].add_patch(plt.Circle(o[:2], st["d_danger"], fill=False, color="r"))
        axes[3].scatter([o[0]], [o[1]], c="r", marker="o")
        axes[3].set_title("escaping: obstacle (red, d_danger) at 3 s")
    for ax in axes:
        ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    main()

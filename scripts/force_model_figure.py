"""Draws docs/images/force_model.png: 3000 insects (Table 1 parameters,
neighbor_sample 64) forming a sphere, morphing to a mammoth, then a shark, and
a crescent moon; one panel per shape, taken just before the next keyframe.

    PYTHONPATH=bindings/python python scripts/force_model_figure.py [out.png]
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import swarmcl

N = 3000
DOMAIN = ((-8.0, -8.0, -8.0), (8.0, 8.0, 8.0))


def main(out):
    shots = []
    with swarmcl.Context() as ctx, swarmcl.Swarm(ctx, agent_count=N, seed=5, domain=DOMAIN,
                                                 interaction_radius=1.0, dt=1 / 60) as s:
        s.set_force_model(swarmcl.ForceModel(min_spacing=0.0, neighbor_sample=64, min_distance=0.02, keyframes=[
            swarmcl.Keyframe(0, "sphere", scale=2.5), swarmcl.Keyframe(900, "mammoth", scale=2.5),
            swarmcl.Keyframe(1800, "shark", scale=2.5), swarmcl.Keyframe(2700, "moon", scale=2.5)]))
        for name in ("sphere", "mammoth", "shark", "moon"):
            s.step(890)
            shots.append((name, s.positions, np.linalg.norm(s.velocities, axis=1).mean()))
            s.step(10)
    fig = plt.figure(figsize=(16, 4.6))
    for k, (name, p, speed) in enumerate(shots):
        ax = fig.add_subplot(1, 4, k + 1, projection="3d")
        ax.scatter(p[:, 0], p[:, 1], p[:, 2], s=0.6, c=p[:, 2], cmap="viridis", linewidths=0)
        ax.set_title(f"{name}: step {900 * k + 890}, mean speed {speed:.2f} m/s", fontsize=9)
        ax.view_init(elev=75 if name == "moon" else 15, azim=-70)
        for axis in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
            axis(-3.6, 3.6)
        ax.set_box_aspect((1, 1, 1))
        ax.set_axis_off()
    fig.suptitle("Force model, 3000 insects, Table 1 parameters (neighbor_sample 64)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/images/force_model.png")

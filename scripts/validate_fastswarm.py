#!/usr/bin/env python3
"""Validation of the FASTSWARM energy model against real mosquito tracks (a
script, not a unit test; docs/energy-model.md, "Validation").

    python3 scripts/validate_fastswarm.py [--data ../shared/data/anopheles-coluzzii-swarm.csv]
                                          [--seconds 30] [--seed 4] [--png FILE]

1. Reads the real tracks (Anopheles coluzzii, 100 Hz, positions in cm) with
   swarmcl's loader: speed and |a| of every forward-difference sample, and the
   nearest-neighbour distance of every insect in every frame with two or more.
2. Builds the reference dataset (k = 300) from the same file.
3. Runs the aggregation scenario (Table 1 weights) from the most crowded real
   frame: its insects, positions and velocities; radii from the real
   nearest-neighbour distances (d_rep = 5th percentile, d_att1 = median,
   d_att2 = 2 x median), the swarm centre fixed at the tracks' mean position.
4. Runs the curl-noise field model (model.type "field", seed 4, the
   aggregation settings of examples/scenarios/aggregation.json with the goal
   at the same centre) from the same start.
5. Runs the papers' baselines from the same start (docs/baselines.md):
   FASTSWARM Fig. 7's BSwarm-style force model with Gaussian noise, and seed
   004 §7.1's Boids + Perlin noise and Boids + random noise, each the force
   model's three-zone interaction without shape forces plus a noise term
   (examples/scenarios/baseline_*.json at the data's scale).
6. Prints, for each, the L1 distance between the simulated and the real
   distributions of speed, |a| and nearest-neighbour distance, each z-scored
   with the real mean and standard deviation (histograms of 40 bins on
   [-4, 4], outliers in the end bins; 0 = identical, 2 = disjoint).

Skips (exit 0) when the data file is absent.
"""

import argparse
import csv
import json
import os
import sys
from collections import defaultdict

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_DATA = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "data", "anopheles-coluzzii-swarm.csv"))
COLUMNS = {"id": "id", "time": "datetime", "x": "x_cm", "y": "y_cm", "z": "z_cm"}
DT = 0.01  # the data's frame time and the simulation step


def l1_zscored(sim, real, bins=40, lim=4.0):
    mu, sd = float(np.mean(real)), float(np.std(real))
    edges = np.linspace(-lim, lim, bins + 1)

    def hist(x):
        z = np.clip((np.asarray(x, dtype=np.float64) - mu) / sd, -lim, lim)
        h, _ = np.histogram(z, edges)
        return h / max(1, h.sum())

    return float(np.abs(hist(sim) - hist(real)).sum())


def nearest(points):
    d = np.linalg.norm(points[:, None] - points[None], axis=2)
    np.fill_diagonal(d, np.inf)
    return d.min(axis=1)


def read_frames(path):
    frames = defaultdict(list)
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            frames[r["datetime"]].append((r["id"], float(r["x_cm"]) / 100, float(r["y_cm"]) / 100,
                                          float(r["z_cm"]) / 100))
    return frames


def kinematics(traj):
    """Speeds and |a| by forward differences of (steps, N, 3) positions."""
    v = np.diff(traj, axis=0) / DT
    a = np.diff(v, axis=0) / DT
    return np.linalg.norm(v[:-1], axis=2).ravel(), np.linalg.norm(a, axis=2).ravel()


def run(swarm, steps):
    traj = [swarm.positions.copy()]
    nn = []
    for _ in range(steps):
        swarm.step(1)
        p = swarm.positions
        traj.append(p.copy())
        nn.append(nearest(p.astype(np.float64)))
    return np.array(traj, dtype=np.float64), np.concatenate(nn)


def baseline_scenarios(n, domain, p5, p50, acc_real, speed_real, seed):
    """(name, scenario dict) of the baselines, at the data's scale.

    Radii: r_rep = 5th percentile of the real nearest-neighbour distance,
    r_ali = its median, r_att = 30 m (Table 1 of the shape paper: every insect
    attracts every other, the swarm's only cohesion).  Speed limit 1.5 m/s
    (above the data's 95th percentile).  BSwarm has self-propulsion: the
    force model's cruise floor at the real 5th-percentile speed; Boids has
    none (floor 0).  Noise gain: sigma, the per-axis standard deviation of
    white acceleration noise whose |a| median (1.538 sigma, Maxwell) is the
    real |a| median: Gaussian lambda = sigma; white uniform in [-g, g] with
    g = sqrt(3) sigma (the same variance); Perlin (values about +-0.5) 2 sqrt(3)
    sigma; curl (derivatives of Perlin, about +-1) sigma; Perlin and curl with
    the real median spacing as feature size and a 1 s time scale."""
    sigma = float(np.median(acc_real)) / 1.538
    cruise = float(np.percentile(speed_real, 5))
    base = os.path.join(HERE, "..", "examples", "scenarios")
    out = []
    for name, file, noise, gain, floor in (
            ("BSwarm-style + Gaussian", "baseline_bswarm.json", "gaussian", sigma, cruise),
            ("BSwarm-style + curl", "baseline_bswarm.json", "curl", sigma, cruise),
            ("Boids + Perlin noise", "baseline_boids_perlin.json", "perlin", 2 * np.sqrt(3) * sigma, 0.0),
            ("Boids + random noise", "baseline_boids_random.json", "white", np.sqrt(3) * sigma, 0.0)):
        with open(os.path.join(base, file)) as f:
            sc = json.load(f)
        sc.pop("output", None)
        sc.update(seed=seed, dt=DT, steps=0, domain={"min": list(domain[0]), "max": list(domain[1])},
                  interaction_radius=float(p50), agents={"count": n})
        m = sc["model"]
        m.update(r_rep=float(p5), r_ali=float(p50), r_att=30.0, max_speed=1.5, cruise_speed=floor)
        m["noise"].update(type=noise, gain=float(gain), seed=seed)
        if noise in ("perlin", "curl"):
            m["noise"].update(scale=float(p50), time_scale=1.0)
        out.append((name, sc))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=os.environ.get("SWARMCL_MOSQUITO_CSV", DEFAULT_DATA))
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--seed", type=int, default=4)
    ap.add_argument("--png", default=None, help="write the distributions here (docs/images/baselines_validation.png)")
    args = ap.parse_args()
    if not os.path.isfile(args.data):
        print(f"validate_fastswarm: skipped, no data at {args.data}")
        return 0
    import swarmcl

    # ---- the real distributions ---------------------------------------------------
    every = swarmcl.Dataset.from_csv(args.data, columns=COLUMNS, unit_scale=0.01, k=1 << 24, groups=1)
    v_real, a_real = every.samples()
    speed_real = np.linalg.norm(v_real, axis=1)
    acc_real = np.linalg.norm(a_real, axis=1)
    frames = read_frames(args.data)
    nn_real = np.concatenate([nearest(np.array([p[1:] for p in f])) for f in frames.values() if len(f) >= 2])
    all_pos = np.array([p[1:] for f in frames.values() for p in f])
    centre = tuple(float(c) for c in all_pos.mean(axis=0))
    lo, hi = np.percentile(all_pos, 1, axis=0), np.percentile(all_pos, 99, axis=0)
    p5, p50 = np.percentile(nn_real, [5, 50])
    print(f"real data: {len(speed_real)} (v, a) samples, {len(nn_real)} nearest-neighbour distances, "
          f"frame time {every.info()['frame_time']:.4f} s")
    print(f"  speed median {np.median(speed_real):.3f} m/s, |a| median {np.median(acc_real):.2f} m/s^2, "
          f"nearest neighbour 5/50/95% {p5:.3f} / {p50:.3f} / {np.percentile(nn_real, 95):.3f} m")

    # ---- the start: the most crowded real frame --------------------------------------
    t0 = max(frames, key=lambda t: len(frames[t]))
    start = frames[t0]
    n = len(start)
    pos0 = np.array([p[1:] for p in start], dtype=np.float32)
    times = sorted(frames)
    nxt = frames[times[times.index(t0) + 1]] if times.index(t0) + 1 < len(times) else []
    nxt_pos = {p[0]: np.array(p[1:]) for p in nxt}
    vel0 = np.array([(nxt_pos[p[0]] - np.array(p[1:])) / DT if p[0] in nxt_pos else np.zeros(3) for p in start],
                    dtype=np.float32)
    steps = int(round(args.seconds / DT))
    print(f"start: frame {t0} with {n} insects; {steps} steps of {DT} s; seed {args.seed}")
    domain = (tuple(float(x) for x in lo - 1.0), tuple(float(x) for x in hi + 1.0))

    dataset = swarmcl.Dataset.from_csv(args.data, columns=COLUMNS, unit_scale=0.01, k=300, seed=args.seed)
    results = {}
    with swarmcl.Context() as ctx:
        model = swarmcl.EnergyModel(d_rep=float(p5), d_att1=float(p50), d_att2=float(2 * p50), centre=centre,
                                    noise=swarmcl.NoiseDesc(scale=float(p50), time_scale=1.0, seed=args.seed))
        with swarmcl.Swarm(ctx, capacity=n, seed=args.seed, domain=domain, interaction_radius=float(2 * p50),
                           dt=DT) as s:
            s.write_positions(pos0)
            s.write_velocities(vel0)
            s.set_energy_model(dataset, model)
            results["energy (FASTSWARM)"] = run(s, steps)
        field = swarmcl.FieldModel(
            noise=swarmcl.NoiseDesc(type="curl", scale=0.4, gain=0.25, seed=7, time_scale=2.0, domain_walls=True,
                                    region=(tuple(float(x) for x in lo), tuple(float(x) for x in hi))),
            goal=centre, goal_radius=1.2, goal_speed=1.5, goal_falloff=1.0, min_distance=0.03)
        with swarmcl.Swarm(ctx, capacity=n, seed=args.seed, domain=domain, interaction_radius=0.4, dt=DT) as s:
            s.write_positions(pos0)
            s.write_velocities(vel0)
            s.set_field_model(field)
            results["field (curl noise)"] = run(s, steps)

        # The papers' baselines (docs/baselines.md): the force model's
        # three-zone interaction without shape forces (alpha 1, no keyframes)
        # plus a noise term, from the same start; examples/scenarios/baseline_*.json
        # with the radii, speed limit and noise gain set from the data here.
        for name, scenario in baseline_scenarios(n, domain, p5, p50, acc_real, speed_real, args.seed):
            with swarmcl.Scenario.parse(json.dumps(scenario)) as sc, sc.create_swarm(ctx) as s:
                s.write_positions(pos0)
                s.write_velocities(vel0)
                results[name] = run(s, steps)

    print("\nL1 distance of z-scored distributions to the real data (0 = identical, 2 = disjoint)")
    print(f"{'model':24s} {'speed':>8s} {'|a|':>8s} {'nn dist':>8s}   medians: speed, |a|, nn")
    print(f"{'real':24s} {0.0:8.3f} {0.0:8.3f} {0.0:8.3f}   {np.median(speed_real):.3f} m/s, "
          f"{np.median(acc_real):.2f} m/s^2, {np.median(nn_real):.3f} m")
    for name, (traj, nn) in results.items():
        sp, ac = kinematics(traj)
        print(f"{name:24s} {l1_zscored(sp, speed_real):8.3f} {l1_zscored(ac, acc_real):8.3f} "
              f"{l1_zscored(nn, nn_real):8.3f}   {np.median(sp):.3f} m/s, {np.median(ac):.2f} m/s^2, "
              f"{np.median(nn):.3f} m")
    if args.png:
        figure(args.png, results, speed_real, acc_real, nn_real)
        print(f"wrote {args.png}")
    return 0


def figure(png, results, speed_real, acc_real, nn_real):
    """FASTSWARM Fig. 7-like: the distributions of speed, nearest-neighbour
    distance and |a| of every model against the real data."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), dpi=72)
    panels = (("speed (m/s)", 0, speed_real, np.linspace(0, 2, 41)),
              ("nearest-neighbour distance (m)", 1, nn_real, np.linspace(0, 2.5, 41)),
              ("|a| (m/s^2)", 2, acc_real, np.linspace(0, 40, 41)))
    sims = {name: (*kinematics(traj), nn) for name, (traj, nn) in results.items()}
    for title, k, real, edges in panels:
        ax = axes[k]
        ax.hist(np.clip(real, edges[0], edges[-1]), edges, density=True, color="0.8", label="real")
        for name, (sp, ac, nn) in sims.items():
            x = (sp, nn, ac)[k]
            h, _ = np.histogram(np.clip(x, edges[0], edges[-1]), edges, density=True)
            ax.plot(0.5 * (edges[1:] + edges[:-1]), h, lw=1.2, label=name)
        ax.set_xlabel(title, fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())

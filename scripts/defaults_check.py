#!/usr/bin/env python3
"""Measures the four defaults that are not in a paper (issue 19, item 6), each
on and off, from the example scenarios: the force model's cruise_speed floor,
the energy model's keep_out rule, the field model's time-varying noise in the
main job (time_scale) and goal_falloff in the path scenarios.  Writes
bench/results/defaults/<name>.json and docs/images/default_<name>.png.

    PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build \\
        python scripts/defaults_check.py [cruise keep_out time_scale goal_falloff]
"""
import copy
import json
import os
import sys

import numpy as np

import swarmcl

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCEN = os.path.join(ROOT, "examples", "scenarios")
OUT = os.path.join(ROOT, "bench", "results", "defaults")
IMG = os.path.join(ROOT, "docs", "images")


def load(name):
    s = json.load(open(os.path.join(SCEN, name + ".json")))
    s.pop("output", None)
    return s


def swarm_of(ctx, s):
    return swarmcl.Scenario.parse(json.dumps(s)).create_swarm(ctx)


def nn_distances(p):
    p = p[:, :3].astype(np.float64)
    out = np.empty(len(p))
    for a in range(0, len(p), 512):
        d2 = ((p[a:a + 512, None, :] - p[None, :, :]) ** 2).sum(-1)
        d2[np.arange(d2.shape[0]), np.arange(a, a + d2.shape[0])] = np.inf
        out[a:a + 512] = np.sqrt(d2.min(1))
    return out


def cruise(ctx):
    """500 insects holding a sphere (force model, the paper's Table 1
    weights): mean speed and distance to the sphere with the floor on/off."""
    base = load("force_sphere_mammoth_shark_5k")
    base["agents"]["count"] = 500
    base["steps"] = 900
    base["model"]["keyframes"] = [{"frame": 0, "shape": "sphere", "scale": 1}]
    base["model"]["neighbor_sample"] = 0
    base["agents"]["initial"] = {"type": "sphere", "center": [0, 0, 0], "radius": 1.5}
    res = {}
    for label, c in (("cruise_speed 0.375 (default)", None), ("cruise_speed 0 (paper)", 0.0)):
        s = copy.deepcopy(base)
        if c is not None:
            s["model"]["cruise_speed"] = c
        sw = swarm_of(ctx, s)
        speed, shell = [], []
        for t in range(s["steps"] // 10):
            sw.step(10)
            v = sw.read_velocities()[:, :3]
            r = np.linalg.norm(sw.read_positions()[:, :3], axis=1)
            speed.append(float(np.linalg.norm(v, axis=1).mean()))
            shell.append(float(np.quantile(np.abs(r - np.median(r)), 0.93)))
        res[label] = {"step": list(range(10, s["steps"] + 1, 10)), "mean_speed": speed, "r_spread_p93": shell,
                      "final_median_radius": float(np.median(r))}
        print(f"cruise {label}: final mean speed {speed[-1]:.3f} m/s, 93% within {shell[-1]:.3f} m of the median radius", flush=True)
    return res, "mean_speed", "mean speed (m/s)"


def keep_out(ctx):
    """The escaping scenario: the closest insect to the startling obstacle."""
    base = load("energy_escaping")
    st = base["model"]["stimuli"][0]
    res = {}
    for label, k in (("keep_out on (default)", True), ("keep_out off (paper's Eq. 11-12)", False)):
        s = copy.deepcopy(base)
        s["model"]["keep_out"] = k
        sw = swarm_of(ctx, s)
        closest = []
        for t in range(1, s["steps"] + 1):
            sw.step(1)
            c = np.array(st["position"]) + np.array(st["velocity"]) * t * s["dt"]
            closest.append(round(float(np.linalg.norm(sw.read_positions()[:, :3] - c, axis=1).min()), 5))
        res[label] = {"step": list(range(1, s["steps"] + 1)), "closest_to_danger": closest, "min": min(closest)}
        print(f"keep_out {label}: closest {min(closest):.3f} m (d_danger {st['d_danger']})", flush=True)
    return res, "closest_to_danger", "closest insect to the danger (m)"


def time_scale(ctx):
    """The main job (aggregation.json, field model) with a static and a
    time-varying curl noise: how much of the room the swarm visits, its nearest
    neighbour distances and the share MDE moves."""
    base = load("aggregation")
    res = {}
    for label, ts in (("time_scale 2 (default job)", 2.0), ("time_scale 0 (static noise)", 0.0)):
        s = copy.deepcopy(base)
        s["model"]["noise"]["time_scale"] = ts
        s["steps"] = 600
        sw = swarm_of(ctx, s)
        n = s["agents"]["count"]
        mde, nn5, cells, tracks = [], [], [], []
        visited = set()
        sw.take_step_stats()
        for t in range(1, s["steps"] + 1):
            sw.step(1)
            mde.append(round(100 * sw.take_step_stats().mde_moved_total / n, 4))
            p = sw.read_positions()[:, :3]
            tracks.append(np.round(p[:12], 4).tolist())
            if t > s["steps"] // 2:
                # cells of 5 cm a single insect passes through in the second half
                visited.update(map(tuple, np.floor(p[:100] / 0.05).astype(int).tolist()))
            if t % 20 == 0:
                nn5.append(float(np.quantile(nn_distances(p), 0.05)))
        res[label] = {"step": list(range(1, s["steps"] + 1)), "mde_percent": mde, "nn_p5_every20": nn5,
                      "cells_visited_by_100_insects_2nd_half": len(visited), "tracks_first12": tracks[::2]}
        print(f"time_scale {label}: MDE {np.mean(mde):.3f}% (2nd half {np.mean(mde[300:]):.3f}%), nn p5 end {nn5[-1]:.4f} m, "
              f"5 cm cells visited by 100 insects in the 2nd half {len(visited)}", flush=True)
    return res, "mde_percent", "MDE moved (% per step)"


def goal_falloff(ctx):
    """The three path scenarios with goal_falloff: their MDE share and how
    insects sit in the goal with falloff 1 m and 0 (the paper's pull)."""
    res = {}
    for name in ("path_aggregation", "path_two_blocks", "path_chasing"):
        base = load(name)
        for o in base.get("obstacles", []):
            if "file" in o:
                o["file"] = os.path.normpath(os.path.join(SCEN, o["file"]))
        for label, f in (("goal_falloff 1 (shipped)", base["model"]["goal_falloff"]), ("goal_falloff 0 (paper)", 0.0)):
            s = copy.deepcopy(base)
            s["model"]["goal_falloff"] = f
            sw = swarm_of(ctx, s)
            n = s["agents"]["count"]
            mde = []
            sw.take_step_stats()
            for t in range(s["steps"]):
                sw.step(1)
                mde.append(round(100 * sw.take_step_stats().mde_moved_total / n, 4))
            p = sw.read_positions()[:, :3]
            g = s["model"]["goals"][0]
            if g.get("type", "sphere") == "sphere":
                depth = np.linalg.norm(p - np.array(g["center"]), axis=1) - g["radius"]
            else:  # box: signed distance to its surface along the axis of travel (z)
                depth = (g["center"][2] - g["half_extents"][2]) - p[:, 2]
                depth = np.where(depth < 0, -np.minimum(-depth, 2 * g["half_extents"][2] + depth), depth)
            nn = nn_distances(p)
            key = f"{name}: {label}"
            res[key] = {"step": list(range(1, s["steps"] + 1)), "mde_percent": mde, "final_depth_hist": np.histogram(depth, bins=np.linspace(-1.2, 0.6, 37))[0].tolist(),
                        "final_nn_p5": float(np.quantile(nn, 0.05)), "final_nn_p50": float(np.median(nn))}
            print(f"goal_falloff {key}: MDE {np.mean(mde):.3f}% (last third {np.mean(mde[-len(mde)//3:]):.3f}%), final nn p5/p50 "
                  f"{res[key]['final_nn_p5']:.4f}/{res[key]['final_nn_p50']:.4f} m", flush=True)
    return res, "mde_percent", "MDE moved (% per step)"


def plot(name, res, key, ylabel):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    if name == "time_scale":
        fig, axes = plt.subplots(1, 3, figsize=(10, 3.2))
        for ax, (label, r) in zip(axes[:2], res.items()):
            tr = np.array(r["tracks_first12"])
            for i in range(tr.shape[1]):
                ax.plot(tr[:, i, 0], tr[:, i, 1], lw=0.6)
            ax.set_title(label + ": 12 insects, 20 s", fontsize=8)
            ax.set_aspect("equal"); ax.set_xlim(-1.5, 1.5); ax.set_ylim(-1.5, 1.5)
        ax = axes[2]
    elif name == "goal_falloff":
        fig, axes = plt.subplots(1, 2, figsize=(9, 3.2))
        edges = np.linspace(-1.2, 0.6, 37)
        for label, r in res.items():
            axes[0].plot(np.convolve(r["mde_percent"], np.ones(10) / 10, mode="valid"), lw=0.8, label=label)
            if label.startswith("path_aggregation"):
                axes[1].step(0.5 * (edges[1:] + edges[:-1]), r["final_depth_hist"], where="mid", label=label.split(": ")[1])
        axes[0].set_yscale("symlog", linthresh=0.01); axes[0].set_xlabel("step"); axes[0].set_ylabel("MDE moved (% per step, 10-step mean)", fontsize=8)
        axes[0].legend(fontsize=6)
        axes[1].set_xlabel("distance outside the goal sphere (m), final frame", fontsize=8); axes[1].set_ylabel("insects")
        axes[1].set_title("path_aggregation", fontsize=8); axes[1].legend(fontsize=7)
        fig.tight_layout(); fig.savefig(os.path.join(IMG, f"default_{name}.png"), dpi=80)
        return
    else:
        fig, axes = plt.subplots(1, 1, figsize=(5, 3.2))
        ax = axes
    for label, r in res.items():
        y = np.array(r[key])
        if name == "time_scale":
            y = np.convolve(y, np.ones(10) / 10, mode="valid")
        ax.plot(r["step"][:len(y)], y, lw=0.8, label=label)
    if name == "keep_out":
        ax.axhline(0.3, color="k", ls="--", lw=0.8, label="d_danger")
    ax.set_xlabel("step"); ax.set_ylabel(ylabel, fontsize=8); ax.legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(IMG, f"default_{name}.png"), dpi=80)


def main():
    os.makedirs(OUT, exist_ok=True)
    which = sys.argv[1:] or ["cruise", "keep_out", "time_scale", "goal_falloff"]
    ctx = swarmcl.Context()
    for name in which:
        res, key, ylabel = globals()[name](ctx)
        json.dump({"check": name, "command": "PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python scripts/defaults_check.py " + name,
                   "runs": res}, open(os.path.join(OUT, name + ".json"), "w"))
        plot(name, res, key, ylabel)


if __name__ == "__main__":
    main()

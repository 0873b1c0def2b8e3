#!/usr/bin/env python3
"""Why does minimum distance enforcement (MDE) move more insects per step than
the curl-noise paper's Table 1 (0.01-0.68 %)?  Runs every Table 1 path scenario
(examples/scenarios/path_*.json) with one parameter changed at a time and
records the share of insects MDE moved per step (swcl step stats) over the
scenario's whole run and over path_bench's window (steps 3-203), plus the
nearest-neighbour distances of a few frames.  Writes one JSON per scenario to
bench/results/mde_share/ and, with --plot, docs/images/mde_share_*.png.

    PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build \\
        python scripts/mde_share.py [--only path_aggregation] [--plot]
"""
import argparse
import copy
import json
import os
import sys

import numpy as np

import swarmcl

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCEN = os.path.join(ROOT, "examples", "scenarios")
OUT = os.path.join(ROOT, "bench", "results", "mde_share")
IMG = os.path.join(ROOT, "docs", "images")
PAPER = {"path_two_blocks": 0.36, "path_chasing": 0.54, "path_aggregation": 0.03,
         "path_phototaxis": 0.01, "path_locusts": 0.68}  # Table 1, % per frame


def nn_distances(p):
    """Distance of every agent to its nearest neighbour (brute force, blocks)."""
    p = p[:, :3].astype(np.float64)
    out = np.empty(len(p))
    for a in range(0, len(p), 512):
        d2 = ((p[a:a + 512, None, :] - p[None, :, :]) ** 2).sum(-1)
        d2[np.arange(d2.shape[0]), np.arange(a, a + d2.shape[0])] = np.inf
        out[a:a + 512] = np.sqrt(d2.min(1))
    return out


def variants(name, base):
    m = base["model"]
    d = m.get("min_distance", 0.0)
    v = [("as shipped", {})]
    for k in (2 / 3, 1 / 3, 1 / 6, 1 / 10):
        v.append((f"min_distance {d * k:.4g}", {"min_distance": d * k}))
    v.append(("noise gain 0", {"noise.gain": 0.0}))
    v.append(("noise gain x2", {"noise.gain": 2 * m["noise"]["gain"]}))
    v.append(("goal_falloff 0" if m.get("goal_falloff", 0) else "goal_falloff 1", {"goal_falloff": 0.0 if m.get("goal_falloff", 0) else 1.0}))
    v.append(("speed x0.5", {"speed": 0.5 * m["speed"]}))
    v.append(("dt /2 (same time)", {"dt": base["dt"] / 2}))
    v.append(("MDE off (counted)", {"min_distance": 0.0}))
    return v


def apply(base, change):
    s = copy.deepcopy(base)
    s.pop("output", None)
    for k, val in change.items():
        if k == "dt":
            s["dt"] = val
            s["steps"] = 2 * base["steps"]
        elif k.startswith("noise."):
            s["model"]["noise"][k[6:]] = val
        else:
            s["model"][k] = val
    return s


def run(ctx, scen, d_count, nn_every):
    """Share of agents moved per step (from MDE's own count; with MDE off,
    the share closer than d_count to a neighbour after each step)."""
    sc = swarmcl.Scenario.parse(json.dumps(scen))
    sw = sc.create_swarm(ctx)
    n, steps = scen["agents"]["count"], scen["steps"]
    mde = scen["model"].get("min_distance", 0.0) > 0
    per_step, nn = [], {}
    sw.take_step_stats()
    for t in range(1, steps + 1):
        sw.step(1)
        if mde:
            per_step.append(sw.take_step_stats().mde_moved_total / n)
        if not mde or t % nn_every == 0 or t == steps:
            d = nn_distances(sw.read_positions())
            if not mde:
                per_step.append(float((d < d_count).mean()))
            if t % nn_every == 0 or t == steps:
                nn[t] = d
    per_step = np.array(per_step)
    return per_step, nn


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", action="append")
    ap.add_argument("--plot", action="store_true")
    ap.add_argument("--replot", action="store_true", help="plot the JSON already written")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    names = a.only or list(PAPER)
    if not a.replot:
        ctx = swarmcl.Context()
        for name in names:
            base = json.load(open(os.path.join(SCEN, name + ".json")))
            # Relative paths in a parsed scenario resolve against the cwd.
            for o in base.get("obstacles", []):
                if "file" in o:
                    o["file"] = os.path.normpath(os.path.join(SCEN, o["file"]))
            d0 = base["model"]["min_distance"]
            rows = []
            for label, change in variants(name, base):
                scen = apply(base, change)
                per, nn = run(ctx, scen, d0, max(1, scen["steps"] // 6))
                k = 2 if "dt" in change else 1
                rows.append({"variant": label, "change": change,
                             "share_percent_all": 100 * float(per.mean()),
                             "share_percent_bench": 100 * float(per[3 * k:203 * k].mean()),
                             "share_percent_first_third": 100 * float(per[: len(per) // 3].mean()),
                             "share_percent_last_third": 100 * float(per[-(len(per) // 3):].mean()),
                             "per_step_percent": [round(100 * float(x), 4) for x in per[::k]],
                             "nn_quantiles": {str(t): [round(float(np.quantile(d, q)), 6) for q in (0.01, 0.05, 0.25, 0.5)] for t, d in nn.items()},
                             # histograms only where the figure draws them
                             "nn_hist": {str(t): np.histogram(d, bins=np.geomspace(1e-4, 10, 61))[0].tolist() for t, d in nn.items()}
                             if label in ("as shipped", "MDE off (counted)") else {}})
                print(f"{name:18s} {label:24s} all {rows[-1]['share_percent_all']:.3f}%  bench {rows[-1]['share_percent_bench']:.3f}%"
                      f"  first/last third {rows[-1]['share_percent_first_third']:.3f}/{rows[-1]['share_percent_last_third']:.3f}%", flush=True)
            meta = {"scenario": name, "paper_mde_percent": PAPER[name], "agents": base["agents"]["count"],
                    "min_distance": d0, "dt": base["dt"], "steps": base["steps"], "hist_edges": np.geomspace(1e-4, 10, 61).tolist(),
                    "command": "PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python scripts/mde_share.py --only " + name}
            head = json.dumps(meta)[:-1]
            with open(os.path.join(OUT, name + ".json"), "w") as f:  # one line per variant
                f.write(head + ', "rows": [\n' + ",\n".join(json.dumps(r) for r in rows) + "\n]}\n")
    if a.plot or a.replot:
        plot(names)


def plot(names):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, len(names), figsize=(3.2 * len(names), 5.6), squeeze=False)
    for i, name in enumerate(names):
        r = json.load(open(os.path.join(OUT, name + ".json")))
        edges = np.array(r["hist_edges"])
        mid = np.sqrt(edges[1:] * edges[:-1])
        ax = axes[0, i]
        base = r["rows"][0]
        for t, h in list(base["nn_hist"].items())[::2]:
            h = np.array(h, float)
            ax.step(mid, np.cumsum(h) / h.sum(), where="mid", label=f"step {t}")
        off = [x for x in r["rows"] if x["variant"] == "MDE off (counted)"][0]
        t_last = list(off["nn_hist"])[-1]
        h = np.array(off["nn_hist"][t_last], float)
        ax.step(mid, np.cumsum(h) / h.sum(), where="mid", ls=":", color="k", label=f"MDE off, step {t_last}")
        ax.axvline(r["min_distance"], color="r", lw=0.8)
        ax.set_xscale("log"); ax.set_yscale("log"); ax.set_ylim(1e-4, 1)
        ax.set_title(name.replace("path_", ""), fontsize=9)
        ax.set_xlabel("nearest-neighbour distance (m)", fontsize=8)
        if i == 0:
            ax.set_ylabel("share of insects closer", fontsize=8)
        ax.legend(fontsize=6)
        ax = axes[1, i]
        for row in r["rows"]:
            if row["variant"] == "as shipped" or row["variant"].startswith("min_distance"):
                y = np.convolve(row["per_step_percent"], np.ones(20) / 20, mode="valid")  # 20-step mean
                ax.plot(np.arange(20, len(y) + 20), y, lw=0.8, label=row["variant"])
        ax.axhline(r["paper_mde_percent"], color="k", ls="--", lw=0.8, label="paper")
        ax.set_yscale("symlog", linthresh=0.01)
        ax.set_ylim(0, 100)
        ax.set_xlabel("step", fontsize=8)
        if i == 0:
            ax.set_ylabel("MDE moved (% per step, 20-step mean)", fontsize=8)
        ax.legend(fontsize=5)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "mde_share.png"), dpi=80)


if __name__ == "__main__":
    sys.exit(main())

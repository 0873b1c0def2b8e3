#!/usr/bin/env python3
"""Minimum distance enforcement: the explicit-width kernel against the scalar
one by cell size (host/swarm/min_distance.cpp picks the wide kernel for cells
of at most kWideCellPerDistance d_min on CPU devices).  The field model's
whole step (curl noise, MDE at d_min, optionally a goal gathering the agents)
of N agents uniform in a 10 m cube, with the grid's cells set through the
interaction radius, each case run with $SWARMCL_MDE_KERNEL=wide and =scalar
alternated (wide, scalar, scalar, wide), best of 3 timings of 10 steps each.

Then a fit's worlds: 64 worlds of 300 agents of
examples/evaluation/field_mosquito.json (cells of about 0.28 m, the grid's
cap of 4 cells an agent over each world's 3 m domain) with d_min set for
cells of about 10, 14 and 20 d_min, with its goal gathering the agents (200
steps first) and without, 3 timings of 50 steps each.

    python bench/mde_kernel_bench.py [--agents 200000] [--d-min 0.03] [--ratios 5,7.5,10,14,20]

Writes bench/results/mde_kernel.json.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scenario(agents: int, radius: float, d_min: float, goal: bool) -> dict:
    s = {"name": "mde_kernel", "seed": 1, "dt": 0.01, "steps": 10,
         "domain": {"min": [-5, -5, -5], "max": [5, 5, 5]}, "interaction_radius": radius,
         "agents": {"count": agents, "initial": {"type": "uniform"}},
         "model": {"type": "field", "noise": {"type": "curl", "scale": 0.4, "gain": 0.5, "seed": 2},
                   "min_distance": d_min}}
    if goal:
        s["model"]["goal"] = {"center": [0, 0, 0], "radius": 0.3, "speed": 2.0}
    return s


def step_ms(swarmcl, ctx, doc: dict, goal: bool) -> float:
    """Best of 3 timings of 10 steps, after 20 steps (a goal's gathering) or 2."""
    with swarmcl.Scenario.parse(json.dumps(doc)) as sc, sc.create_swarm(ctx) as sw:
        sw.step(20 if goal else 2)
        sw.read_positions()
        best = float("inf")
        for _ in range(3):
            t = time.perf_counter()
            sw.step(10)
            sw.read_positions()  # waits for the queue
            best = min(best, (time.perf_counter() - t) / 10)
        return best * 1e3


def world_step_ms(swarmcl, ctx, d_min: float, goal: bool) -> float:
    """Best of 3 timings of 50 steps of 64 worlds of field_mosquito (300
    agents each, seeds 5..68), after 200 steps."""
    with open(os.path.join(ROOT, "examples", "evaluation", "field_mosquito.json"), encoding="utf-8") as f:
        doc = json.load(f)
    doc["agents"]["count"] = 300
    doc["model"]["min_distance"] = d_min
    if not goal:
        doc["model"].pop("goal")
    with swarmcl.Scenario.parse(json.dumps(doc)) as sc:
        sw = sc.create_world_swarm(ctx, 64, [5 + k for k in range(64)], None)
    with sw:
        sw.step(200)
        sw.read_positions()
        best = float("inf")
        for _ in range(3):
            t = time.perf_counter()
            sw.step(50)
            sw.read_positions()
            best = min(best, (time.perf_counter() - t) / 50)
        return best * 1e3


def alternated(run):
    """run() timed with $SWARMCL_MDE_KERNEL wide, scalar, scalar, wide: the
    times of each and the best of each."""
    times = {"wide": [], "scalar": []}
    for kernel in ("wide", "scalar", "scalar", "wide"):
        os.environ["SWARMCL_MDE_KERNEL"] = kernel
        times[kernel].append(run())
    os.environ.pop("SWARMCL_MDE_KERNEL")
    return times, min(times["wide"]), min(times["scalar"])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--agents", type=int, default=200000)
    ap.add_argument("--d-min", type=float, default=0.03)
    ap.add_argument("--ratios", default="5,7.5,10,14,20", help="cell edges in units of d_min")
    ap.add_argument("--json", default=os.path.join(ROOT, "bench", "results", "mde_kernel.json"))
    args = ap.parse_args()
    import swarmcl
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    from evaluation_studies import cpu_model
    from result_paths import write_result
    out = {"cpu": cpu_model(), "agents": args.agents, "d_min": args.d_min, "cases": []}
    with swarmcl.Context() as ctx:
        out["device"] = ctx.device.device_name
        print(f"MDE kernels on {out['cpu']} ({out['device']}): the field model's step, {args.agents} agents "
              f"uniform in a 10 m cube, d_min {args.d_min} m; wide and scalar alternated, best of 3 x 10 steps; "
              f"load {os.getloadavg()[0]:.2f}")
        for goal in (False, True):
            for ratio in (float(r) for r in args.ratios.split(",")):
                doc = scenario(args.agents, ratio * args.d_min, args.d_min, goal)
                times, w, s = alternated(lambda: step_ms(swarmcl, ctx, doc, goal))
                out["cases"].append({"cell_over_d_min": ratio, "goal": goal, "wide_ms": times["wide"],
                                     "scalar_ms": times["scalar"], "wide_over_scalar": w / s})
                print(f"  cells {ratio:4.1f} d_min, {'goal' if goal else 'no goal'}: wide {w:6.2f} ms, "
                      f"scalar {s:6.2f} ms a step: wide / scalar {w / s:.2f}")
        out["world_cases"] = []
        for goal in (True, False):
            for d_min in (0.028, 0.02, 0.014):
                times, w, s = alternated(lambda: world_step_ms(swarmcl, ctx, d_min, goal))
                out["world_cases"].append({"worlds": 64, "agents": 300, "d_min": d_min, "goal": goal,
                                           "wide_ms": times["wide"], "scalar_ms": times["scalar"],
                                           "wide_over_scalar": w / s})
                print(f"  64 worlds x 300, d_min {d_min} (cells ~{0.28 / d_min:.0f} d_min), "
                      f"{'goal' if goal else 'no goal'}: wide {w:6.3f} ms, scalar {s:6.3f} ms a step: "
                      f"wide / scalar {w / s:.2f}")
    write_result(out, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Soak test: every model (field, path, force, energy) at small N for many steps.

Why a Python script and not a C++ tool in bench/: it drives the library through
the same C API a user does (via the Python binding), needs no extra build
target, writes its figures as JSON directly, and the short version is a plain
pytest (tests/python/test_soak.py) that imports run_soak from here.

Each model runs one example scenario (examples/scenarios/) with the agent count
lowered; every `--every` steps it checks
  - every position and velocity finite (no NaN/Inf),
  - every speed within the model's bound (see speed_bound below),
  - every agent inside the scenario's domain grown by 10 % of its extent,
  - the process's resident memory (VmRSS), sampled at every check: after the
    first 10 % of the run (warm-up) the median of the last quarter of the
    samples may not exceed that of the first quarter by more than
    --rss-slack-mib (RSS wanders up and down by tens of MiB between samples
    on PoCL, so single samples are not compared).
Figures go to bench/results/soak/<model>.json, rewritten after every check so
an interrupted run still leaves how far it got.

  python3 scripts/soak.py --steps 1000000            # all four, one at a time
  python3 scripts/soak.py --models force --steps 10000
"""
from __future__ import annotations

import argparse
import json
import math
import pathlib
import sys
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bindings" / "python"))
import swarmcl  # noqa: E402

# model -> (scenario file, agents)
MODELS = {
    "field": ("aggregation.json", 64),
    "path": ("path_aggregation.json", 64),
    "force": ("force_moon_5k.json", 64),
    "energy": ("energy_aggregation_37.json", 37),
}


def rss_mib() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def _noise_max(ctx, noise: dict, domain, times) -> float:
    """The largest |curl noise| over a 24^3 lattice of the domain at the given
    times: the field and path models add it to their speed s0."""
    lo, hi = np.array(domain["min"], np.float32), np.array(domain["max"], np.float32)
    axes = [np.linspace(lo[k], hi[k], 24, dtype=np.float32) for k in range(3)]
    pts = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3).astype(np.float32)
    desc = swarmcl.NoiseDesc(type=noise.get("type", "curl"), scale=noise["scale"], gain=noise["gain"],
                             seed=noise.get("seed", 0), time_scale=noise.get("time_scale", 0.0),
                             domain_walls=noise.get("domain_walls", False),
                             region=(tuple(domain["min"]), tuple(domain["max"])),
                             **({"boundary_distance": noise["boundary_distance"]}
                                if "boundary_distance" in noise else {}))
    m = 0.0
    for t in times:
        v = swarmcl.noise_sample(ctx, desc, pts, time=float(t))
        m = max(m, float(np.linalg.norm(v, axis=1).max()))
    return m


def speed_bound(ctx, sc: dict) -> tuple[float, str]:
    """Each model's speed bound, from its definition:
    field  (kernels/field_model.cl): V = curl N + s0 * ramp * unit(goal - p), ramp <= 1
    path   (kernels/path_model.cl, Eq. 9): V = curl N + s0 * trilinear(unit -grad C), |.| <= 1
       -> s0 + max|curl N|; max|curl N| is sampled on a lattice, so 1.5x it
          (the lattice misses peaks between nodes);
    force  (docs/force-model.md step 7): speed clamped to max_speed;
    energy (kernels/energy_model.cl, Eq. 1): v is one dataset sample -> max |v| of the dataset."""
    m = sc["model"]
    kind = m["type"]
    if kind == "force":
        return float(m["max_speed"]) * (1 + 1e-5), "max_speed"
    if kind == "energy":
        d = m["dataset"]
        ds = swarmcl.Dataset.synthetic(k=d["k"], groups=d["groups"], seed=d["seed"])
        v, _ = ds.samples()
        ds.close()
        return float(np.linalg.norm(v, axis=1).max()) * (1 + 1e-5), "max |v| over the dataset samples"
    s0 = float(m["goal"]["speed"]) if kind == "field" else float(m["speed"])
    dt = float(sc["dt"])
    nm = _noise_max(ctx, m["noise"], sc["domain"], [0.0, 7 * dt, 1000 * dt, 123456 * dt])
    return s0 + 1.5 * nm, f"s0 {s0} + 1.5 x sampled max|curl N| {nm:.4f}"


def run_soak(model: str, steps: int, every: int, out: pathlib.Path | None = None,
             rss_slack_mib: float = 16.0, log=None) -> dict:
    fname, agents = MODELS[model]
    sc = json.loads((REPO / "examples" / "scenarios" / fname).read_text())
    sc["agents"]["count"] = agents
    sc["steps"] = steps
    lo = np.array(sc["domain"]["min"], np.float32)
    hi = np.array(sc["domain"]["max"], np.float32)
    margin = 0.1 * (hi - lo)
    rep = {"model": model, "scenario": fname, "agents": agents, "steps_requested": steps, "every": every,
           "steps_done": 0, "finite": True, "max_speed": 0.0, "outside_domain": 0,
           "domain": [sc["domain"]["min"], sc["domain"]["max"]], "rss_mib": [], "ok": None,
           "failures": []}
    t0 = time.time()
    with swarmcl.Context() as ctx:
        bound, why = speed_bound(ctx, sc)
        rep["speed_bound"], rep["speed_bound_from"] = bound, why
        scen = swarmcl.Scenario.parse(json.dumps(sc))
        with scen.create_swarm(ctx) as s:
            done = 0
            while done < steps:
                k = min(every, steps - done)
                s.step(k)
                done += k
                p = s.read_positions()
                v = s.read_velocities()
                finite = bool(np.isfinite(p).all() and np.isfinite(v).all())
                vmax = float(np.linalg.norm(v, axis=1).max())
                outside = int((((p < lo - margin) | (p > hi + margin)).any(axis=1)).sum())
                rep["steps_done"] = done
                rep["finite"] = rep["finite"] and finite
                if math.isfinite(vmax):
                    rep["max_speed"] = max(rep["max_speed"], vmax)
                rep["outside_domain"] = max(rep["outside_domain"], outside)
                rep["rss_mib"].append([done, round(rss_mib(), 2)])
                rep["wall_s"] = round(time.time() - t0, 1)
                if not finite:
                    rep["failures"].append(f"non-finite state at step {done}")
                if vmax > bound:
                    rep["failures"].append(f"speed {vmax} > bound {bound} at step {done}")
                if outside:
                    rep["failures"].append(f"{outside} agents outside the domain at step {done}")
                if out is not None:
                    out.write_text(json.dumps(rep, indent=1))
                if log:
                    log(f"{model}: {done}/{steps} vmax {vmax:.4f} (bound {bound:.4f}) "
                        f"rss {rep['rss_mib'][-1][1]} MiB {rep['wall_s']} s")
                if rep["failures"]:
                    break
    # Memory flat: glibc and PoCL let RSS wander up and down by tens of MiB
    # between samples (per-launch buffers, malloc arenas), so "flat" is judged
    # on the trend: after the first 10 % (warm-up: kernel builds, caches) the
    # median RSS of the last quarter may exceed that of the first quarter by at
    # most the slack; the least-squares slope is reported too.
    samples = rep["rss_mib"]
    warm = [(d, r) for d, r in samples if d >= max(every, steps // 10)]
    if len(warm) >= 8:
        q = len(warm) // 4
        first, last = [r for _, r in warm[:q]], [r for _, r in warm[-q:]]
        rep["rss_median_first_quarter_mib"] = float(np.median(first))
        rep["rss_median_last_quarter_mib"] = float(np.median(last))
        rep["rss_min_max_after_warmup_mib"] = [min(r for _, r in warm), max(r for _, r in warm)]
        d = np.array([w[0] for w in warm], float)
        r = np.array([w[1] for w in warm], float)
        rep["rss_slope_mib_per_1e6_steps"] = round(float(np.polyfit(d, r, 1)[0]) * 1e6, 2)
        growth = rep["rss_median_last_quarter_mib"] - rep["rss_median_first_quarter_mib"]
        rep["rss_median_growth_mib"] = round(growth, 2)
        if growth > rss_slack_mib:
            rep["failures"].append(f"median RSS grew {growth:.1f} MiB after warm-up")
    rep["steps_per_s"] = round(rep["steps_done"] / max(time.time() - t0, 1e-9), 1)
    rep["ok"] = not rep["failures"] and rep["steps_done"] == steps
    if out is not None:
        out.write_text(json.dumps(rep, indent=1))
    return rep


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", default="field,path,force,energy")
    ap.add_argument("--steps", type=int, default=1_000_000)
    ap.add_argument("--every", type=int, default=0, help="steps between checks (default steps/200)")
    ap.add_argument("--out-dir", default=str(REPO / "bench" / "results" / "soak"))
    ap.add_argument("--rss-slack-mib", type=float, default=16.0)
    a = ap.parse_args()
    every = a.every or max(1, a.steps // 200)
    out_dir = pathlib.Path(a.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ok = True
    for m in a.models.split(","):
        rep = run_soak(m, a.steps, every, out_dir / f"{m}.json", a.rss_slack_mib,
                       log=lambda s: print(s, flush=True))
        print(json.dumps({k: rep[k] for k in ("model", "steps_done", "ok", "max_speed", "speed_bound", "rss_median_growth_mib",
                                              "outside_domain", "failures")}), flush=True)
        ok = ok and rep["ok"]
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

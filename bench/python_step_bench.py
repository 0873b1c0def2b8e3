#!/usr/bin/env python3
"""Stepping a swarm from Python vs the same calls from C.

Creates a 100k-agent swarm (ballistic, and with the curl-noise field model of
the README's aggregation scenario), steps it 10 steps per call for K calls,
and times it from Python (the `swarmcl` package, cffi ABI mode) and from C
(bench/c_step_bench.c, compiled here against the very library the package
loads, making exactly the same calls).  Two sync patterns:

  end   K calls of step(10), then one read of the positions (device work and
        call overhead; the read makes the queue finish)
  each  every call: step(10), then read_positions into a caller-owned array

Runs alternate C and Python per repeat so both see the same machine load; the
figure compared is the median per-call time (minimum also written).  A third
figure is free of device time and load: the per-call overhead of step(0) in
each language, which bounds what the binding can add to a call
(overhead_bound_ratio = 1 + extra overhead / C time per call).  Writes
bench/results/python_step.json.

  python bench/python_step_bench.py [--agents 100000] [--steps 10] [--calls 20]
                                    [--repeats 7] [--device SEL] [--json PATH]
Needs the package importable (pip install .) and a C compiler.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import swarmcl

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent


def make_swarm(ctx, mode: str, agents: int) -> swarmcl.Swarm:
    # Must match c_step_bench.c
    s = swarmcl.Swarm(ctx, capacity=agents, agent_count=agents, seed=2024,
                      domain=((-1.5, -1.5, 0.5), (1.5, 1.5, 3.5)), interaction_radius=0.05, dt=1 / 30)
    if mode == "field":
        s.set_field_model(swarmcl.FieldModel(
            noise=swarmcl.NoiseDesc(type="curl", seed=7, time_scale=2.0, domain_walls=True),
            goal=(0.0, 0.0, 2.0), goal_radius=1.2, goal_speed=1.5, goal_falloff=1.0, min_distance=0.03))
    return s


def build_c_driver(workdir: pathlib.Path) -> pathlib.Path:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        sys.exit("python_step_bench: no C compiler (cc) found")
    libpath = pathlib.Path(swarmcl.library_path)
    include = pathlib.Path(swarmcl.header_path).parent.parent
    exe = workdir / "c_step_bench"
    cmd = [cc, "-O2", "-std=c99", "-D_POSIX_C_SOURCE=199309L", f"-I{include}", str(HERE / "c_step_bench.c"),
           str(libpath), f"-Wl,-rpath,{libpath.parent}", "-o", str(exe)]
    subprocess.run(cmd, check=True)
    return exe


def run_c(exe, mode, agents, steps, calls, sync, device) -> list:
    args = [str(exe), mode, str(agents), str(steps), str(calls), "1", sync]
    if device:
        args.append(device)
    env = dict(os.environ)
    out = subprocess.run(args, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out)["per_call_s"]


def run_python(swarm, steps, calls, sync, pos) -> float:
    # warm-up right before the timed loop, as in the C driver (wakes the
    # device's worker threads, which slept while the C run went on)
    swarm.step(steps)
    swarm.read_positions(pos)
    t0 = time.perf_counter()
    if sync == "each":
        for _ in range(calls):
            swarm.step(steps)
            swarm.read_positions(pos)
    else:
        for _ in range(calls):
            swarm.step(steps)
        swarm.read_positions(pos)
    return (time.perf_counter() - t0) / calls


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--agents", type=int, default=100_000)
    ap.add_argument("--steps", type=int, default=10, help="steps per call")
    ap.add_argument("--calls", type=int, default=10, help="calls per timed run (K)")
    ap.add_argument("--field-calls", type=int, default=None,
                    help="calls per timed run for the field model (default: --calls)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--device", default=None)
    ap.add_argument("--modes", default="ballistic,field")
    ap.add_argument("--json", default=str(HERE / "results" / "python_step.json"))
    a = ap.parse_args()

    ctx = swarmcl.Context(a.device)
    device = str(ctx.device)
    print(f"swarmcl {swarmcl.__version__} on {device}")
    print(f"library {swarmcl.library_path}")
    print(f"{a.agents} agents, {a.steps} steps per call, {a.calls} calls per run, {a.repeats} runs each, "
          "C and Python alternating")
    print(f"{'mode':10} {'sync':5} {'C ms/call':>10} {'Py ms/call':>11} {'Py/C':>7}   (median; min)")
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        exe = build_c_driver(pathlib.Path(tmp))
        for mode in a.modes.split(","):
            for sync in ("end", "each"):
                calls = (a.field_calls or a.calls) if mode == "field" else a.calls
                swarm = make_swarm(ctx, mode, a.agents)
                pos = np.empty((a.agents, 3), np.float32)
                c_times, py_times = [], []
                for _ in range(a.repeats):
                    c_times += run_c(exe, mode, a.agents, a.steps, calls, sync, a.device)
                    py_times.append(run_python(swarm, a.steps, calls, sync, pos))
                swarm.close()
                c_med, py_med = statistics.median(c_times), statistics.median(py_times)
                c_min, py_min = min(c_times), min(py_times)
                ratio, ratio_min = py_med / c_med, py_min / c_min
                print(f"{mode:10} {sync:5} {c_med * 1e3:10.3f} {py_med * 1e3:11.3f} {ratio:7.3f}   "
                      f"({c_min * 1e3:.3f} / {py_min * 1e3:.3f} = {ratio_min:.3f})")
                results.append({
                    "mode": mode, "sync": sync, "calls_per_run": calls,
                    "c_per_call_s": c_times, "python_per_call_s": py_times,
                    "c_median_s": c_med, "python_median_s": py_med, "ratio_median": ratio,
                    "c_min_s": c_min, "python_min_s": py_min, "ratio_min": ratio_min,
                    "within_5_percent": ratio <= 1.05,
                })
        # Per-call cost of the binding itself, free of device time and machine
        # load: step(0) does no device work, so this is pure call overhead.
        n_noop = 200_000
        swarm = make_swarm(ctx, "ballistic", 1000)
        c_noop = min(run_c(exe, "ballistic", 1000, 0, n_noop, "end", a.device)[0] for _ in range(3))
        py_noop = min(run_python(swarm, 0, n_noop, "end", np.empty((1000, 3), np.float32)) for _ in range(3))
        swarm.close()
    extra = py_noop - c_noop
    print(f"call overhead, step(0): C {c_noop * 1e6:.3f} us, Python {py_noop * 1e6:.3f} us "
          f"(+{extra * 1e6:.3f} us per call)")
    for r in results:
        r["overhead_bound_ratio"] = 1 + extra / r["c_median_s"]
        print(f"  {r['mode']:10} {r['sync']:5} Python/C bound from call overhead: {r['overhead_bound_ratio']:.5f}")
    ctx.close()
    doc = {
        "benchmark": "python_step",
        "what": "stepping from Python (swarmcl package, cffi ABI mode) vs the same C API calls from C",
        "agents": a.agents, "steps_per_call": a.steps, "calls_per_run": a.calls, "runs": a.repeats,
        "device": device, "field_calls_per_run": a.field_calls or a.calls,
        "swarmcl_version": swarmcl.__version__,
        "python": platform.python_version(), "numpy": np.__version__,
        "cffi": __import__("cffi").__version__,
        "host": platform.node(), "cpus": os.cpu_count(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "target": "Python within 5% of C (median per-call time)",
        "call_overhead_s": {"c": c_noop, "python": py_noop, "extra_per_call": extra},
        "results": results,
    }
    path = pathlib.Path(a.json)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc, indent=2) + "\n")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

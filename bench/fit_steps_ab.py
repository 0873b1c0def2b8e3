#!/usr/bin/env python3
"""A change measured on a fit generation's stepping: the worlds of one
generation (bench/fit_bench.py's scenario, 64 individuals x 300 agents),
stepped 100 steps at a time (with --frames as a fit steps them, each step's
positions read back with step_frames), under two or more variants
alternated (A, B, B, A, ...), so a before/after pair meets the same machine
at the same time (docs/benchmarks.md).  Prints and stores each variant's
seconds per 500 steps.

    python bench/fit_steps_ab.py A B [C ...] [--frames] [--model force] [--rounds 10] [--json PATH]

A variant is a kernel directory (kernels as kernels/ holds them, from an
older revision or changed; SWARMCL_KERNEL_DIR is set to it while its
context builds; all variants step in this process) or a library file
(libswarmcl.so of another build, for host changes; SWARMCL_LIBRARY, a
process per variant and round, each stepping one warm-up and then the
timed 100 steps five times).

--metrics (library files): instead of the stepping, the measuring of the
generation's frames on the host (Metrics.from_frames of each world, two
threads, as PopulationEvaluator does): each library's process steps the
worlds 500 steps once, reading every frame back, then measures them five
times.
"""
from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))


def world_swarm(ctx, args, real):
    """The generation's worlds as one swarm (None: refused)."""
    import fit_bench
    from swarmcl.fitting import PopulationEvaluator, load_ranges
    s = fit_bench.scenario(args.agents, 500, args.model)
    ranges = fit_bench.RANGES_OF[args.model]
    pop = [np.random.default_rng(i).uniform(size=len(ranges)) for i in range(args.population)]
    ev = PopulationEvaluator(s, load_ranges(ranges, s), real, ctx, worlds=True, streamed=False)
    return ev._world_swarm([(u, 0) for u in pop], list(range(args.population)))


def hundred_steps(swarm, frames) -> float:
    """Seconds of 100 steps, their frames read back when frames is an array."""
    t = time.perf_counter()
    if frames is None:
        swarm.step(100)
        swarm.read_positions()  # waits for the queue
    else:
        swarm.step_frames(100, 1, out=frames)
    return 5 * (time.perf_counter() - t)


def frames_of(args, swarm):
    """The array step_frames fills with --frames (None without)."""
    return np.zeros((100, args.population, swarm.agent_count, 3), np.float32) if args.frames else None


def measure_seconds(swarmcl, frames) -> float:
    """Seconds to measure every world's frames (frames, worlds, agents, 3)
    on the host, two threads."""
    from concurrent.futures import ThreadPoolExecutor

    def measure(k):
        swarmcl.Metrics.from_frames(frames[:, k], 0.01).close()
    t = time.perf_counter()
    with ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(measure, range(frames.shape[1])))
    return time.perf_counter() - t


def worker(args) -> int:
    """One library's rounds (SWARMCL_LIBRARY is set by the parent): JSON of
    its seconds per 500 steps (--metrics: to measure 500 steps' frames)."""
    import fit_bench
    import swarmcl
    with swarmcl.Context() as ctx, fit_bench.synthetic_tracks(swarmcl) as real:
        swarm = world_swarm(ctx, args, real)
        if swarm is None:
            return 1
        with swarm:
            if args.metrics:
                frames = np.empty((501, args.population, swarm.agent_count, 3), np.float32)
                swarm.read_positions(out=frames[0])
                swarm.step_frames(500, 1, out=frames[1:])
                measure_seconds(swarmcl, frames)  # first touch of the samples' memory
                print(json.dumps([round(measure_seconds(swarmcl, frames), 4) for _ in range(5)]))
                return 0
            frames = frames_of(args, swarm)
            hundred_steps(swarm, frames)  # builds the kernels, first touch of the frames
            print(json.dumps([round(hundred_steps(swarm, frames), 4) for _ in range(5)]))
    return 0


def in_process(args) -> dict:
    """Kernel directories: a context and a swarm each, alternated here."""
    import fit_bench
    import swarmcl
    held, swarms = [], []
    with fit_bench.synthetic_tracks(swarmcl) as real:
        try:
            for d in args.variants:
                os.environ["SWARMCL_KERNEL_DIR"] = os.path.abspath(d)
                ctx = swarmcl.Context()
                held.append(ctx)
                swarm = world_swarm(ctx, args, real)
                if swarm is None:
                    raise SystemExit(f"{d}: the scenario was refused (or these kernels do not build with this library)")
                swarms.append(swarm)
            frames = [frames_of(args, s) for s in swarms]
            for s, f in zip(swarms, frames):
                hundred_steps(s, f)  # builds the kernels
            seconds = {d: [] for d in args.variants}
            for r in range(args.rounds):
                order = range(len(swarms)) if r % 2 == 0 else reversed(range(len(swarms)))
                for i in order:
                    seconds[args.variants[i]].append(round(hundred_steps(swarms[i], frames[i]), 4))
            return seconds
        finally:
            for swarm in swarms:
                swarm.close()
            for ctx in held:
                ctx.close()


def by_process(args) -> dict:
    """Library files: a process per variant and round, alternated."""
    seconds = {lib: [] for lib in args.variants}
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", "--model", args.model, "--population",
           str(args.population), "--agents", str(args.agents)] + (["--frames"] if args.frames else []) \
        + (["--metrics"] if args.metrics else [])
    for r in range(args.rounds):
        for lib in args.variants if r % 2 == 0 else args.variants[::-1]:
            env = dict(os.environ, SWARMCL_LIBRARY=os.path.abspath(lib))
            p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600)
            if p.returncode != 0:
                raise SystemExit(f"{lib}: the worker failed:\n{p.stdout}{p.stderr}")
            seconds[lib] += json.loads(p.stdout.strip().splitlines()[-1])
    return seconds


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("variants", nargs="*", help="kernel directories, or libswarmcl files; two or more")
    ap.add_argument("--frames", action="store_true", help="read every step's positions back, as a fit does")
    ap.add_argument("--metrics", action="store_true",
                    help="library files: time measuring the frames on the host, not the stepping")
    ap.add_argument("--model", choices=("force", "field", "path"), default="force")
    ap.add_argument("--population", type=int, default=64)
    ap.add_argument("--agents", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--json", help="where to store the figures (default: print only)")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return worker(args)
    if len(args.variants) < 2 or len(set(map(os.path.abspath, args.variants))) < len(args.variants):
        ap.error("give two or more different variants")
    dirs = [os.path.isdir(v) for v in args.variants]
    if not all(dirs) and not all(os.path.isfile(v) for v in args.variants):
        ap.error("the variants must all be kernel directories or all library files")
    if args.metrics and any(dirs):
        ap.error("--metrics compares library files")
    from evaluation_studies import cpu_model
    seconds = in_process(args) if all(dirs) else by_process(args)
    what = "kernel directory" if all(dirs) else "library"
    timed = ("seconds to measure 500 steps' frames on the host (Metrics.from_frames, 2 threads)" if args.metrics
             else "seconds per 500 steps" + (", each step's positions read back (step_frames)" if args.frames else ""))
    print(f"{args.model} model, {args.population} worlds x {args.agents} agents on {cpu_model()}: {timed}, "
          f"by {what}, alternated")
    base = float(np.median(seconds[args.variants[0]]))
    for v in args.variants:
        s = seconds[v]
        print(f"  {v}: min {min(s):.3f}  median {np.median(s):.3f}  ({base / np.median(s):.2f}x the first's median)")
    if args.json:
        from result_paths import shown_path, shown_value, write_result
        write_result({"what": f"{timed}, a fit generation's worlds, by {what}",
                      "command": "python bench/fit_steps_ab.py " + shlex.join(shown_value(a) for a in sys.argv[1:]),
                      "cpu": cpu_model(), "model": args.model, "population": args.population,
                      "agents": args.agents, "rounds": args.rounds,
                      "seconds_to_measure" if args.metrics else "seconds_per_500_steps":
                          {shown_path(v): s for v, s in seconds.items()}}, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())

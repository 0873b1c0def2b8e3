#!/usr/bin/env python3
"""A kernel change measured on a fit generation's stepping: the worlds of one
generation (bench/fit_bench.py's scenario, 64 individuals x 300 agents) are
built once per kernel directory, each in its own context, and stepped 100
steps at a time, the directories alternated (A, B, B, A, ...) in one process,
so a before/after pair meets the same machine at the same time
(docs/benchmarks.md).  Prints and stores each directory's seconds per 500
steps (a generation's stepping, without its frames read back).

    python bench/fit_steps_ab.py DIR_A DIR_B [DIR_C ...] [--model force] [--rounds 10] [--json PATH]

A directory holds kernels as kernels/ does (a copy of an older revision's,
or a variant): SWARMCL_KERNEL_DIR is set to it while its context builds.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+", help="kernel directories, two or more")
    ap.add_argument("--model", choices=("force", "field", "path"), default="force")
    ap.add_argument("--population", type=int, default=64)
    ap.add_argument("--agents", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=10)
    ap.add_argument("--json", help="where to store the figures (default: print only)")
    args = ap.parse_args()
    if len(args.dirs) < 2:
        ap.error("give two or more kernel directories")
    for d in args.dirs:
        if not os.path.isdir(d):
            ap.error(f"no such kernel directory: {d}")
    import fit_bench
    import swarmcl
    from evaluation_studies import cpu_model
    from swarmcl.fitting import PopulationEvaluator, load_ranges
    s = fit_bench.scenario(args.agents, 500, args.model)
    ranges = fit_bench.RANGES_OF[args.model]
    pop = [np.random.default_rng(i).uniform(size=len(ranges)) for i in range(args.population)]
    runs = [(u, 0) for u in pop]
    held, swarms = [], []
    with fit_bench.synthetic_tracks(swarmcl) as real:
        try:
            for d in args.dirs:
                os.environ["SWARMCL_KERNEL_DIR"] = os.path.abspath(d)
                ctx = swarmcl.Context()
                held.append(ctx)
                ev = PopulationEvaluator(s, load_ranges(ranges, s), real, ctx, worlds=True, streamed=False)
                swarm = ev._world_swarm(runs, list(range(args.population)))
                if swarm is None:
                    print(f"{d}: the scenario was refused", file=sys.stderr)
                    return 1
                swarm.step(20)  # builds the kernels
                swarm.read_positions()
                swarms.append(swarm)
            seconds = {d: [] for d in args.dirs}
            for r in range(args.rounds):
                order = range(len(args.dirs)) if r % 2 == 0 else reversed(range(len(args.dirs)))
                for i in order:
                    t = time.perf_counter()
                    swarms[i].step(100)
                    swarms[i].read_positions()  # waits for the queue
                    seconds[args.dirs[i]].append(round(5 * (time.perf_counter() - t), 4))
        finally:
            for swarm in swarms:
                swarm.close()
            for ctx in held:
                ctx.close()
    print(f"{args.model} model, {args.population} worlds x {args.agents} agents on {cpu_model()}: "
          f"seconds per 500 steps, {args.rounds} alternated rounds of 100 steps")
    base = float(np.median(seconds[args.dirs[0]]))
    for d in args.dirs:
        v = seconds[d]
        print(f"  {d}: min {min(v):.3f}  median {np.median(v):.3f}  ({base / np.median(v):.2f}x the first's median)")
    if args.json:
        import shlex
        from result_paths import shown_path, shown_value, write_result
        write_result({"what": "seconds per 500 steps of a fit generation's worlds, by kernel directory",
                      "command": "python bench/fit_steps_ab.py " + shlex.join(shown_value(a) for a in sys.argv[1:]),
                      "cpu": cpu_model(), "model": args.model, "population": args.population,
                      "agents": args.agents, "rounds": args.rounds,
                      "seconds_per_500_steps": {shown_path(d): v for d, v in seconds.items()}}, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())

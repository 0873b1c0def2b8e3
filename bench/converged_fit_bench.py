#!/usr/bin/env python3
"""A converged fit of the force model (issue 26's target): the 8 parameters
of examples/evaluation/force_mosquito.ranges.json fitted to the first half
of the mosquito recording by CMA-ES until it stops on a tolerance, through
`python -m swarmcl fit` in one process and under `mpirun -np 2`, in the same
run (the same seed gives the same search on any rank count, so the two
differ only in time).  Targets: <= 300 s in one process, <= 180 s on 2 ranks.

    python bench/converged_fit_bench.py [--population 16 --generations 150 --seeds 2 --patience 20]

Needs ../shared/data/anopheles-coluzzii-swarm.csv (skips when absent),
pip install 'swarmcl[fit,mpi]' and mpirun for the 2-rank run.  Writes
bench/results/eval/converged_fit.json.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from evaluation_studies import DATA, split_tracks  # noqa: E402  scripts/evaluation_studies.py
from result_paths import write_result  # noqa: E402
from machine_info import cpu_model  # noqa: E402  scripts/machine_info.py

TARGET = {1: 300.0, 2: 180.0}


def run_fit(ranks: int, args, train: str, out: str) -> dict:
    """One fit through the CLI on `ranks` ranks: its result and wall time."""
    cmd = [sys.executable, "-m", "swarmcl", "fit", os.path.join(ROOT, "examples", "evaluation", "force_mosquito.json"),
           "--ranges", os.path.join(ROOT, "examples", "evaluation", "force_mosquito.ranges.json"),
           "--tracks", train, "--warmup", "200", "--population", str(args.population),
           "--generations", str(args.generations), "--seeds", str(args.seeds), "--tolerance", str(args.tolerance),
           "--step-tolerance", str(args.step_tolerance), "--patience", str(args.patience), "--seed", "1",
           "--out", out, "--quiet"]
    env = dict(os.environ)
    if ranks > 1:
        cmd = [shutil.which("mpirun"), "-np", str(ranks)] + cmd
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=3600)
    seconds = time.perf_counter() - t
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:4])} ... failed:\n{p.stdout}{p.stderr}")
    with open(out, encoding="utf-8") as f:
        r = json.load(f)
    return {"ranks": ranks, "wall_seconds": seconds, "fit_seconds": r["seconds"], "converged": r["converged"],
            "stop": r["stop"], "generations_run": len(r["history"]), "evaluations": r["evaluations"],
            "best_score": r["best_score"], "best": r["best"]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--population", type=int, default=16)
    ap.add_argument("--generations", type=int, default=150)
    ap.add_argument("--seeds", type=int, default=2, help="simulation seeds per candidate (default 2)")
    ap.add_argument("--tolerance", type=float, default=0.01)
    ap.add_argument("--step-tolerance", type=float, default=0.01)
    ap.add_argument("--patience", type=int, default=20)
    ap.add_argument("--json", default=os.path.join(ROOT, "bench", "results", "eval", "converged_fit.json"))
    args = ap.parse_args()
    if not os.path.exists(DATA):
        print(f"skipped: no {DATA} (the real tracks are not in the repository)")
        return 0
    out = {"cpu": cpu_model(), "population": args.population, "generations": args.generations,
           "seeds": args.seeds, "tolerance": args.tolerance, "step_tolerance": args.step_tolerance,
           "patience": args.patience, "runs": []}
    print(f"converged-fit benchmark on {out['cpu']}: force model, 8 parameters, CMA-ES population "
          f"{args.population} x {args.seeds} simulation seeds, 30 agents x 700 steps a run, "
          f"against the mosquito recording's first half")
    rank_counts = [1, 2] if shutil.which("mpirun") else [1]
    with tempfile.TemporaryDirectory() as tmp:
        files, _, _ = split_tracks(DATA, tmp)
        for ranks in rank_counts:
            r = run_fit(ranks, args, files["train"], os.path.join(tmp, f"fit{ranks}.json"))
            out["runs"].append(r)
            state = "converged" if r["converged"] else "did NOT converge"
            print(f"  {ranks} rank(s): {r['wall_seconds']:6.1f} s wall ({r['fit_seconds']:.1f} s fitting), "
                  f"{r['generations_run']} generations, {state} ({', '.join(r['stop'])}), best E "
                  f"{r['best_score']:.4f}; target {TARGET[ranks]:.0f} s: "
                  f"{'met' if r['converged'] and r['wall_seconds'] <= TARGET[ranks] else 'NOT met'}")
    if len(out["runs"]) == 2:
        out["speedup_2_ranks"] = out["runs"][0]["wall_seconds"] / out["runs"][1]["wall_seconds"]
        out["same_answer"] = out["runs"][0]["best"] == out["runs"][1]["best"]
        print(f"  2 ranks {out['speedup_2_ranks']:.2f}x one process; same answer: {out['same_answer']}")
    else:
        print("  no mpirun: the 2-rank run is skipped")
    write_result(out, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())

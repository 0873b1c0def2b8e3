"""Parameter sweeps (issue 25): a grid or a list of parameter values of a
scenario, each row run as one world of one swarm where the model runs worlds
(docs/architecture.md, "Worlds"; otherwise one swarm a row), split over MPI
ranks; one result row per world with its statistics and, given tracks, its
score E against them (Eq. 1 of the noise paper, docs/evaluation.md).

    python -m swarmcl sweep SCENARIO.json --grid GRID.json [--tracks FILE.csv] [--out sweep.json|sweep.csv]

GRID.json is either a grid, ``{"model.noise.scale": [0.2, 0.4], "model.goal.speed": [0.5, 1.0]}``
(every combination, the first key slowest), or a list,
``{"runs": [{"model.noise.scale": 0.2, "model.goal.speed": 0.5}, ...]}``.
Keys are scenario paths as in a fit's ranges file; each value is checked
against the scenario and the model's parameter table before anything runs.
"seed" gives each row its own seed (replicates run as worlds too).
"""
from __future__ import annotations

import argparse
import csv
import itertools
import json
import math
import os
import sys
import time
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ._core import Context, Scenario
from .errors import SwarmclError
from .evaluation import METRICS, Metrics, distances, score, wasserstein
from .fitting import (_check_against_table, _context_for_rank, add_track_options, is_domain_key, mpi_comm,
                      numeric_param, track_window, world_domains, world_groups, world_key, world_model)

__all__ = ["load_grid", "sweep"]

#: The statistics of each row, from the world's last state.
STATISTICS = ("mean_speed", "median_nearest_distance", "radius_of_gyration", "mde_moved_total")


def _number(path: str, v, integer: bool):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError(f"grid: {path!r}: {v!r} is not a finite number")
    if integer and float(v) != int(v):
        raise ValueError(f"grid: {path!r}: {v!r} is not an integer (the parameter is one)")
    return int(v) if integer else float(v)


def _key_info(scenario: dict, path: str) -> Tuple[bool, Optional[dict], Optional[str]]:
    """(integer, table row, model) of a grid key, or ValueError naming it."""
    return numeric_param(scenario, path, "grid")


def load_grid(grid, scenario: dict) -> Tuple[List[str], List[List[float]]]:
    """(keys, rows) of a grid file (path) or dict: a grid of value lists
    (every combination, the first key slowest) or {"runs": [{key: value}]}.
    Every key and value is checked (the scenario, the model's table and its
    valid range) before anything runs: ValueError naming the key."""
    if isinstance(grid, (str, os.PathLike)):
        with open(grid, encoding="utf-8") as f:
            try:
                grid = json.load(f)
            except json.JSONDecodeError as e:
                raise ValueError(f"grid: not JSON: {e}") from None
    if not isinstance(grid, dict) or not grid:
        raise ValueError('grid: expected {"scenario.path": [values], ...} or {"runs": [{...}, ...]}')
    if "runs" in grid:
        runs = grid["runs"]
        if len(grid) != 1 or not isinstance(runs, list) or not runs or not all(isinstance(r, dict) for r in runs):
            raise ValueError('grid: "runs" must be the only key, a non-empty list of {"scenario.path": value} objects')
        keys = list(runs[0])
        if not keys:
            raise ValueError("grid: a run sets no parameter")
        for i, r in enumerate(runs):
            if list(r) != keys:
                raise ValueError(f"grid: run {i} sets {sorted(r)}, run 0 sets {sorted(keys)}: every run sets the same keys")
        columns = [[r[k] for r in runs] for k in keys]
        combine = False
    else:
        keys = list(grid)
        columns = []
        for k in keys:
            v = grid[k]
            if not isinstance(v, list) or not v:
                raise ValueError(f"grid: {k!r}: expected a non-empty list of values, got {v!r}")
            columns.append(v)
        combine = True
    checked = []
    for k, values in zip(keys, columns):
        integer, row, model = _key_info(scenario, k)
        vals = [_number(k, v, integer) for v in values]
        if k == "seed" and not all(0 <= v < 2**64 for v in vals):
            raise ValueError(f"grid: 'seed': expected integers in [0, 2**64), got {values!r}")
        if row is not None:
            _check_against_table(k, model, row, min(vals), max(vals))
        checked.append(vals)
    rows = [list(r) for r in itertools.product(*checked)] if combine else [list(r) for r in zip(*checked)]
    return keys, rows


def _statistics(positions: np.ndarray, velocities: np.ndarray, nearest: np.ndarray, moved: int) -> dict:
    """One world's statistics (None where its state is not finite)."""
    if not (np.isfinite(positions).all() and np.isfinite(velocities).all()):
        return {"finite": False, **{k: None for k in STATISTICS}}
    centre = positions.mean(axis=0)
    finite_nn = nearest[np.isfinite(nearest)]
    return {"finite": True,
            "mean_speed": float(np.linalg.norm(velocities, axis=1).mean()),
            "median_nearest_distance": float(np.median(finite_nn)) if finite_nn.size else None,
            "radius_of_gyration": float(np.sqrt(((positions - centre) ** 2).sum(axis=1).mean())),
            "mde_moved_total": int(moved)}


class _Runner:
    """Runs rows of a sweep on one context: as the worlds of one swarm where
    the model runs them, else one swarm a row."""

    def __init__(self, scenario: dict, keys: Sequence[str], context: Context, tracks: Optional[Metrics], *,
                 steps=None, every=None, warmup=0, bins=50, half_width=4.0, robust=False):
        from .fitting import Parameter
        integer = [_key_info(scenario, k)[0] for k in keys]
        # Parameters whose value at u is u itself (low 0, high 1): a row's
        # values go through the evaluator's scenario and world paths as they are.
        self.params = [Parameter(k, 0.0, 1.0, i) for k, i in zip(keys, integer)]
        self.tracks = tracks
        self.scenario, self.context = scenario, context
        info = Scenario.parse(json.dumps(scenario)).info
        self.dt = info["dt"]
        self.steps = info["steps"] if steps is None else int(steps)
        self.every = (max(1, round(tracks.frame_time / self.dt)) if tracks is not None else self.steps) \
            if every is None else int(every)
        self.warmup = int(warmup)
        self.bins, self.half_width, self.robust = bins, half_width, robust
        # "seed" (the scenario's) is each world's seed: replicates of a
        # scenario run as worlds too.
        self.seed_index = keys.index("seed") if "seed" in keys else None
        # A domain key ("domain.max.0") gives each world its own domain.
        self.worlds = world_model(scenario) and all(
            k == "seed" or is_domain_key(k) or world_key(scenario, k) is not None for k in keys)
        self.swarms = 0  # how many swarms run() stepped

    def run(self, rows: List[List[float]]) -> List[dict]:
        """Each row's result: the rows as few swarms of worlds as the model
        allows (world_groups: rows the model refuses together, such as a
        noise time scale of 0 beside one above 0, are split), else one
        swarm a row."""
        if not rows:
            return []
        idx = list(range(len(rows)))
        groups = world_groups(lambda part: self._world_swarm([rows[i] for i in part]), idx) if self.worlds \
            else [(None, [i]) for i in idx]
        self.swarms += len(groups)
        out = [None] * len(rows)
        try:
            for swarm, part in groups:
                if swarm is None:
                    with Scenario.parse(json.dumps(self._scenario_for(rows[part[0]]))) as parsed:
                        swarm = parsed.create_swarm(self.context)
                    alone = True
                else:
                    alone = False
                with swarm:
                    for i, r in zip(part, self._run_swarm(swarm, [rows[i] for i in part], alone)):
                        out[i] = r
        finally:
            for swarm, _ in groups:
                if swarm is not None:
                    swarm.close()
        return out

    def _world_swarm(self, rows):
        """The rows as the worlds of one swarm, made from the first row's
        values (so what selects a kernel is the group's own) and every world
        with the row's "seed" or else the scenario's (a row is the scenario
        alone with its values, wherever it falls in the swarm or the ranks);
        None where the model refuses the values together."""
        seed = int(self.scenario.get("seed", 0))
        seeds = [int(r[self.seed_index]) if self.seed_index is not None else seed for r in rows]
        domains = world_domains(self.scenario, [{p.path: p.value(v) for p, v in zip(self.params, r)} for r in rows])
        try:
            with Scenario.parse(json.dumps(self._scenario_for(rows[0]))) as parsed:
                swarm = parsed.create_world_swarm(self.context, len(rows), seeds, domains)
        except SwarmclError:
            # Refused together (the path model's one domain; a row the
            # scenario refuses fails again alone, with its own message).
            return None
        try:
            for k, p in enumerate(self.params):
                if k != self.seed_index and not is_domain_key(p.path):
                    swarm.set_world_param(world_key(self.scenario, p.path), [p.value(r[k]) for r in rows])
        except SwarmclError:
            swarm.close()
            return None
        return swarm

    def _run_swarm(self, swarm, rows, alone: bool) -> List[dict]:
        frames = []
        w = len(rows)

        def sample():
            if self.tracks is not None:
                frames.append(swarm.read_positions().reshape(w, -1, 3))
        for done in range(0, self.warmup, self.every):
            swarm.step(min(self.every, self.warmup - done))
        sample()
        for _ in range(self.steps // self.every):
            swarm.step(self.every)
            sample()
        pos = swarm.read_positions().reshape(w, -1, 3)
        vel = swarm.read_velocities().reshape(w, -1, 3)
        nn, _ = swarm.nearest_neighbor()
        nn = nn.reshape(w, -1)
        stats = swarm.take_world_step_stats() if not alone else [swarm.take_step_stats()]
        out = []
        for k, r in enumerate(rows):
            row = {p.path: p.value(v) for p, v in zip(self.params, r)}
            row.update(_statistics(pos[k], vel[k], nn[k], stats[k].mde_moved_total))
            if self.tracks is not None:
                row.update(self._score(np.stack([f[k] for f in frames]), row["finite"]))
            out.append(row)
        return out

    def _scenario_for(self, row) -> dict:
        from .fitting import _with_values
        return _with_values(self.scenario, self.params, row)

    def _score(self, frames: np.ndarray, finite: bool) -> dict:
        if not finite or not np.isfinite(frames).all():
            return {"score": None, **{f"E_{m}": None for m in METRICS}}
        with Metrics.from_frames(frames, self.every * self.dt) as sim:
            e = distances(self.tracks, sim, self.bins, self.half_width, self.robust)
            w1 = wasserstein(self.tracks, sim)
        out = {"score": float(score(e)), **{f"E_{m}": float(x) for m, x in zip(METRICS, e)}}
        out.update({f"W1_{m}": (None if w1[m] is None else float(w1[m])) for m in METRICS})
        return out


def sweep(scenario, grid, *, tracks: Optional[Metrics] = None, context: Optional[Context] = None, comm=None,
          steps: Optional[int] = None, every: Optional[int] = None, warmup: int = 0, bins: int = 50,
          half_width: float = 4.0, robust: bool = False) -> Optional[dict]:
    """Runs every row of ``grid`` (load_grid) on ``scenario`` (a path or a
    dict): a dict with the keys, one row per world (the parameter values,
    the statistics of its last state and, with ``tracks``, its score E and
    the seven E_phi and W1), whether the rows ran as worlds, how many swarms
    were stepped (rows the model refuses together are split, world_groups),
    the ranks and the seconds.  With ``comm`` (mpi4py, R ranks) every rank calls it with
    the same arguments: the rows are split into R contiguous blocks and rank
    0 returns the result, the others None."""
    if isinstance(scenario, (str, os.PathLike)):
        with open(scenario, encoding="utf-8") as f:
            scenario = json.load(f)
    keys, rows = load_grid(grid, scenario)
    rank, size = (comm.Get_rank(), comm.Get_size()) if comm is not None else (0, 1)
    own = context is None
    ctx = _context_for_rank(rank) if own else context
    began = time.perf_counter()
    try:
        runner = _Runner(scenario, keys, ctx, tracks, steps=steps, every=every, warmup=warmup, bins=bins,
                         half_width=half_width, robust=robust)
        per = -(-len(rows) // size)
        mine = runner.run(rows[rank * per:(rank + 1) * per])
    finally:
        if own:
            ctx.close()
    parts = comm.gather((mine, runner.swarms), root=0) if comm is not None else [(mine, runner.swarms)]
    if rank != 0:
        return None
    out_rows = [r for part, _ in parts for r in part]
    return {"scenario": scenario.get("name", ""), "keys": keys, "rows": out_rows, "worlds": bool(runner.worlds),
            "swarms": sum(n for _, n in parts), "ranks": size, "steps": runner.steps,
            "seconds": time.perf_counter() - began, "scored": tracks is not None}


def _write(result: dict, path: str) -> None:
    """JSON, or CSV for a .csv path; atomically (nothing partial at path)."""
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8", newline="") as f:
        if path.lower().endswith(".csv"):
            columns = list(result["rows"][0]) if result["rows"] else result["keys"]
            w = csv.writer(f)
            w.writerow(columns)
            for r in result["rows"]:
                w.writerow(["" if r.get(c) is None else r.get(c) for c in columns])
        else:
            json.dump(result, f, indent=1)
            f.write("\n")
    os.replace(tmp, path)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="swarmcl sweep", description=__doc__.splitlines()[0])
    p.add_argument("scenario")
    p.add_argument("--grid", required=True, help='JSON {"scenario.path": [values], ...} or {"runs": [{...}, ...]}')
    add_track_options(p, tracks_required=False)  # --tracks: score each row against them
    p.add_argument("--out", default="sweep.json", help="JSON, or CSV for a .csv name (default %(default)s)")
    p.add_argument("--device", help="device index or name part (default: SWARMCL_DEVICE, or round-robin by rank)")
    p.add_argument("--quiet", action="store_true")
    return p


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    comm = mpi_comm()
    rank = comm.Get_rank() if comm is not None else 0
    try:
        device = int(args.device) if args.device and args.device.isdigit() else args.device
        ctx = _context_for_rank(rank, device)
        with ctx:
            real = None
            if args.tracks:
                real = Metrics.from_csv(args.tracks, window=track_window(args.window), unit_scale=args.unit_scale,
                                        columns=args.columns, delimiter=args.delimiter)
            try:
                result = sweep(args.scenario, args.grid, tracks=real, context=ctx, comm=comm, steps=args.steps,
                               every=args.every, warmup=args.warmup, bins=args.bins, half_width=args.half_width,
                               robust=args.robust)
            finally:
                if real is not None:
                    real.close()
    except (ValueError, OSError, SwarmclError) as e:
        print(f"swarmcl sweep: {e}", file=sys.stderr)
        if comm is not None:
            comm.Abort(1)
        return 1
    if rank == 0:
        _write(result, args.out)
        if not args.quiet:
            how = (f"as the worlds of {result['swarms']} swarm(s)" if result["worlds"] else "one swarm a row")
            print(f"{len(result['rows'])} rows ({how}) on {result['ranks']} rank(s) in {result['seconds']:.1f} s; "
                  f"written to {args.out}")
    return 0

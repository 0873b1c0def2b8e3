"""Parameter estimation against real insects (the noise paper's Par-Est,
Fig. 1; docs/evaluation.md): maximise the score E of Eq. 1 over a model's
parameters, with CMA-ES (``cma``) or the paper's genetic algorithm (DEAP),
each generation's individuals simulated together, optionally spread over MPI
ranks (mpi4py).

    mpirun -np 2 swarmcl fit scenario.json --tracks tracks.csv --ranges ranges.json
    python -m swarmcl fit scenario.json --tracks tracks.csv --ranges ranges.json --method ga

A ranges file maps scenario-file paths of numeric fields to [low, high]:

    {"model.noise.gain": [0.05, 1.0], "model.speed": [0.5, 3.0], "model.goals.0.radius": [0.2, 1.0]}

``pip install swarmcl[fit]`` brings cma and DEAP; ``swarmcl[mpi]`` mpi4py
(with an MPI library such as Debian's openmpi-bin).
"""
from __future__ import annotations

import argparse
import copy
import json
import math
import os
import random
import re
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Sequence

import numpy as np

from ._core import Context, Scenario, devices
from .descriptors import DeviceType
from .errors import SwarmclError
from .evaluation import METRICS, Metrics, distances, entropy_weights, score, wasserstein
from .params import model_parameters

__all__ = ["Parameter", "load_ranges", "PopulationEvaluator", "fit", "compare", "main"]

#: The score an individual gets when its scenario is refused (a value the
#: model does not accept): below any real score, finite for the optimisers.
REFUSED_SCORE = -1.0e6


@dataclass(frozen=True)
class Parameter:
    """One fitted field: its scenario-file path, range, and whether the file
    holds an integer there (then values are rounded)."""
    path: str
    low: float
    high: float
    integer: bool = False

    def value(self, u: float):
        """The field's value at u in [0, 1] of the range."""
        v = self.low + float(u) * (self.high - self.low)
        return int(round(v)) if self.integer else v


def _walk(doc, path: str, create: bool = False):
    """(container, key) of a dotted path ("model.goals.0.radius"); with
    ``create``, missing objects on the way are made (a table parameter the
    scenario leaves at its default)."""
    parts = path.split(".")
    node = doc
    for i, part in enumerate(parts[:-1]):
        if create and isinstance(node, dict) and part not in node:
            node[part] = {}
        node = _child(node, part, ".".join(parts[: i + 1]))
    if create and isinstance(node, dict):
        return node, parts[-1]
    last = parts[-1]
    if isinstance(node, list):
        if not last.isdigit() or int(last) >= len(node):
            raise ValueError(f"ranges: {path!r}: no element {last!r} in the list")
        return node, int(last)
    if not isinstance(node, dict) or last not in node:
        raise ValueError(f"ranges: {path!r}: the scenario has no field {last!r} there")
    return node, last


def _child(node, part: str, where: str):
    if isinstance(node, list):
        if part.isdigit() and int(part) < len(node):
            return node[int(part)]
        raise ValueError(f"ranges: {where!r}: no element {part!r} in the list")
    if isinstance(node, dict) and part in node:
        return node[part]
    raise ValueError(f"ranges: {where!r}: the scenario has no field {part!r} there")


def _table_row(scenario: dict, path: str):
    """(model, row) of a "model.<key>" path in the model's parameter table
    (swcl_model_parameters); (None, None) for other paths and for models
    without a table; (model, None) for a key the table does not hold."""
    model_obj = scenario.get("model") if isinstance(scenario, dict) else None
    if not path.startswith("model.") or not isinstance(model_obj, dict):
        return None, None
    model = model_obj.get("type", "field")
    try:
        rows = model_parameters(model)
    except ValueError:
        return None, None
    key = path[len("model."):]
    return model, next((r for r in rows if r["key"] == key and r["scenario"]), None)


def _check_against_table(path: str, model: str, row: dict, low: float, high: float) -> None:
    lo, hi, excl = row.get("min"), row.get("max"), row.get("min_exclusive", False)
    if (lo is not None and (low < lo or (excl and low <= lo))) or (hi is not None and high > hi):
        raise ValueError(f"ranges: {path!r}: [{low:g}, {high:g}] leaves the parameter's valid range "
                         f"{row['range']} ({row['doc']})")


def load_ranges(ranges, scenario: dict) -> List[Parameter]:
    """Parameters from a ranges file (path) or dict ``{path: [low, high]}``,
    checked against the scenario and the model's parameter table: each path
    must name a number (not a boolean) in the scenario or a numeric
    parameter of the model's table (then it may be left out of the
    scenario), each range be finite with low < high and inside the
    parameter's valid range; an unknown key lists the model's parameters."""
    if isinstance(ranges, (str, os.PathLike)):
        with open(ranges, encoding="utf-8") as f:
            try:
                ranges = json.load(f)
            except json.JSONDecodeError as e:
                raise ValueError(f"ranges: not JSON: {e}") from None
    if not isinstance(ranges, dict) or not ranges:
        raise ValueError("ranges: expected an object {\"scenario.path\": [low, high], ...} with at least one entry")
    params = []
    for path, bounds in ranges.items():
        integer, row, model = numeric_param(scenario, path)
        if (not isinstance(bounds, (list, tuple)) or len(bounds) != 2
                or not all(isinstance(b, (int, float)) and not isinstance(b, bool) for b in bounds)):
            raise ValueError(f"ranges: {path!r}: expected [low, high], got {bounds!r}")
        low, high = float(bounds[0]), float(bounds[1])
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise ValueError(f"ranges: {path!r}: expected finite low < high, got {bounds!r}")
        if row is not None:
            _check_against_table(path, model, row, low, high)
        params.append(Parameter(path, low, high, integer))
    return params


def numeric_param(scenario: dict, path: str, what: str = "ranges") -> tuple:
    """(integer, table row or None, model) of a numeric parameter named by
    ``path``: a number in the scenario, or a numeric row of its model's table
    (then it may be left out of the scenario); ValueError naming it (and
    listing the model's parameters for an unknown key) otherwise."""
    model, row = _table_row(scenario, path)
    try:
        node, key = _walk(scenario, path)
        current = node[key]
    except ValueError as e:
        if row is None:
            if model is not None:
                known = ", ".join("model." + r["key"] for r in model_parameters(model) if r["scenario"])
                raise ValueError(f"{what}: {path!r} is neither in the scenario nor a parameter of the {model} "
                                 f"model; its parameters: {known}") from None
            raise ValueError(str(e).replace("ranges:", f"{what}:", 1)) from None
        current = row["default"]  # left at its default in the scenario
    if row is not None and row["type"] not in ("float", "uint32", "uint64"):
        raise ValueError(f"{what}: {path!r} is a {row['type']} parameter of the {model} model, not a number")
    if isinstance(current, bool) or not isinstance(current, (int, float)):
        raise ValueError(f"{what}: {path!r} is {type(current).__name__}, not a number")
    # A coordinate written as 0 in the scenario is still a coordinate.
    integer = row["type"] in ("uint32", "uint64") if row is not None else \
        isinstance(current, int) and not is_domain_key(path)
    return integer, row, model


def _with_values(scenario: dict, params: Sequence[Parameter], u) -> dict:
    doc = copy.deepcopy(scenario)
    for p, x in zip(params, u):
        node, key = _walk(doc, p.path, create=True)
        node[key] = p.value(x)
    return doc


def world_model(scenario) -> bool:
    """Whether the scenario's model runs a swarm of worlds
    (PopulationEvaluator.WORLD_MODELS): the path model refuses worlds with
    chasing targets and a baked noise (docs/architecture.md, "Worlds"),
    which its host would rebake for every world as the targets move."""
    model = scenario.get("model", {}) if isinstance(scenario, dict) else {}
    if not isinstance(model, dict) or model.get("type", "field") not in PopulationEvaluator.WORLD_MODELS:
        return False
    if model.get("type") == "path":
        noise = model.get("noise")
        return not (model.get("targets") and isinstance(noise, dict) and noise.get("baked"))
    return True


#: The path model's goal radii: set per world by keys of their own (the
#: table does not hold the goals; host/models/path_worlds.cpp).
_PATH_GOAL_RADIUS = re.compile(r"model\.((?:groups\.\d+\.)?goals\.\d+\.radius)")


#: A corner coordinate of the scenario's domain: a world's own domain
#: (Scenario.create_world_swarm's world_domains), not a model parameter.
_DOMAIN_KEY = re.compile(r"domain\.(min|max)\.([012])")


def is_domain_key(path: str) -> bool:
    """Whether ``path`` is a corner coordinate of the domain
    ("domain.min.0" ... "domain.max.2"), which worlds take as their own."""
    return _DOMAIN_KEY.fullmatch(path) is not None


def world_domains(scenario: dict, rows: Sequence[Dict[str, float]]) -> Optional[np.ndarray]:
    """Each row's domain ((len(rows), 2, 3): the scenario's with the row's
    domain keys), or None where no row has one."""
    if not any(is_domain_key(k) for row in rows for k in row):
        return None
    d = scenario.get("domain", {})
    base = np.array([d.get("min", [0.0] * 3), d.get("max", [0.0] * 3)], dtype=np.float64)
    out = np.repeat(base[None], len(rows), axis=0)
    for w, row in enumerate(rows):
        for path, v in row.items():
            m = _DOMAIN_KEY.fullmatch(path)
            if m:
                out[w, 0 if m.group(1) == "min" else 1, int(m.group(2))] = v
    return out


def world_groups(make: Callable[[list], object], idx: list) -> list:
    """idx as few swarms of worlds as the model allows: make(part) gives the
    swarm of the items `part` or None where the model refuses them together
    (a kernel-selecting value that differs within them, such as a noise
    time scale of 0 beside one above 0); a refused group is halved until
    each part runs or is one item.  [(swarm, part)], or (None, [i]) for an
    item that must run alone."""
    swarm = make(idx)
    if swarm is not None:
        return [(swarm, idx)]
    if len(idx) == 1:
        return [(None, idx)]
    half = len(idx) // 2
    return world_groups(make, idx[:half]) + world_groups(make, idx[half:])


def world_key(scenario: dict, path: str) -> Optional[str]:
    """The key Swarm.set_world_param takes for a scenario path ("model.speed"
    -> "speed", a path model's "model.goals.0.radius" -> "goals.0.radius"),
    or None where the value cannot be set per world (not a row of the
    model's table, or one the table says is the same in every world)."""
    model = scenario.get("model") if isinstance(scenario, dict) else None
    if isinstance(model, dict) and model.get("type") == "path":
        goal = _PATH_GOAL_RADIUS.fullmatch(path)
        if goal:
            return goal.group(1)
    row = _table_row(scenario, path)[1]
    return row["key"] if row is not None and row.get("per_world", True) else None


class PopulationEvaluator:
    """Scores a population (a list of points in [0, 1]^d): every individual's
    scenario is made into a swarm on one context, and all the swarms are
    stepped together, sampled on the tracks' clock and scored against the
    real metrics (Eq. 1).  Deterministic: an individual's score depends only
    on its parameters."""

    def __init__(self, scenario: dict, params: Sequence[Parameter], real: Metrics, context: Context, *,
                 steps: Optional[int] = None, every: Optional[int] = None, warmup: int = 0, bins: int = 50,
                 half_width: float = 4.0, weights=None, p1=None, p2=None,
                 streamed: Optional[bool] = None, robust: bool = False, scale_penalty: float = 0.0,
                 seeds: int = 1, worlds: bool = True, scale_metrics: Optional[Sequence[str]] = None,
                 pool: bool = False):
        self.scenario, self.params, self.real, self.context = scenario, list(params), real, context
        # seeds S: each individual is run S times, with the scenario's seed
        # replaced by seed, seed + 1, ..., seed + S - 1 (the same S for every
        # individual: common random numbers), and scores the mean of its runs
        # (a run that blows up refuses the individual).
        if int(seeds) < 1:
            raise ValueError(f"seeds: an integer >= 1, got {seeds!r}")
        self.seeds = int(seeds)
        # pool: an individual's S runs are measured as one sample set (their
        # samples together, Metrics.merge) and scored once, instead of the
        # mean of S scores: E of the model's distribution estimated from
        # S times the samples, so less of it is one short run's histogram
        # noise (docs/evaluation.md, "Pooled runs").  Keeps each run's
        # samples until its individual is scored.
        self.pool = bool(pool)
        self.base_seed = self.scenario_seed = int(scenario.get("seed", 0))
        # robust: the PDFs z-scored with median and MAD (docs/evaluation.md).
        # scale_penalty λ: the objective is E - λ P, P the mean over the
        # metrics of W1(real, sim) / (1.4826 MAD of the real samples): how
        # far the run is in physical units, in the data's own spreads (the
        # z-scored E cannot see a swarm that is too fast or too dense).
        self.robust = bool(robust)
        self.scale_penalty = float(scale_penalty)
        if not (self.scale_penalty >= 0.0 and np.isfinite(self.scale_penalty)):
            raise ValueError(f"scale_penalty: a finite number >= 0, got {scale_penalty!r}")
        # scale_metrics: the metrics P averages over (None: all seven); e.g.
        # ("speed", "nearest_distance") holds the fit to the real speed and
        # spacing without pulling on the others.
        self.scale_metrics = list(METRICS) if scale_metrics is None else list(scale_metrics)
        unknown = [m for m in self.scale_metrics if m not in METRICS]
        if unknown or not self.scale_metrics or len(set(self.scale_metrics)) != len(self.scale_metrics):
            raise ValueError(f"scale_metrics: distinct names among {', '.join(METRICS)}; got {scale_metrics!r}")
        self.spread = [1.4826 * real.info(k)["mad"] for k in range(len(METRICS))]
        # streamed True: each run's metrics computed on the device into fine
        # histograms (Metrics.attach, per world on a swarm of worlds; nothing
        # per frame is read back); False: positions are read every sample
        # and measured on the host (exact PDFs).  None (the default): the
        # host for worlds on a CPU device (there the host's threads measured
        # faster than the device's metrics on the same cores: fit_bench,
        # docs/evaluation.md "Speed"), else the device.
        self.streamed = True if streamed is None else bool(streamed)
        info = Scenario.parse(json.dumps(scenario)).info
        self.dt = info["dt"]
        self.steps = info["steps"] if steps is None else int(steps)
        self.every = max(1, round(real.frame_time / self.dt)) if every is None else int(every)
        self.warmup = int(warmup)
        if self.steps < self.every or self.warmup < 0:
            raise ValueError("fit: steps must be >= every (one sampled interval at least), warmup >= 0")
        self.bins, self.half_width = int(bins), float(half_width)
        self.weights, self.p1, self.p2 = weights, p1, p2
        self.evaluations = 0
        self.refused = 0
        # Worlds: a generation's runs as the worlds of one swarm (one launch
        # per stage for all of them; docs/architecture.md, "Worlds") where
        # the scenario's model runs worlds and every fitted parameter is a
        # row of its table.  Each world gives bitwise the run of its
        # scenario alone, and so do its metrics (per world on the device, or
        # on the host from the frames with streamed=False), so a score equals
        # that of the run alone (tested).  worlds=False: one swarm a run.
        self._world_setters = self._setters() if worlds else None
        self.world_keys = list(self._world_setters) if self._world_setters is not None else None
        if streamed is None and self.world_keys is not None and context.device.type == DeviceType.CPU:
            self.streamed = False
        # Threads measuring the worlds' metrics on the host (streamed=False;
        # the C calls run without the GIL); fit() gives each MPI rank its
        # share of the cores.
        self.threads = os.cpu_count() or 1
        # How many swarms the last call stepped (worlds: one per group of
        # _world_groups; otherwise one a run).
        self.last_swarms = 0
        # Wall seconds of the worlds' runs summed over calls, to say where a
        # generation goes: "steps" (with the frames read back, or the
        # device's metrics where streamed) and "metrics" (the host's metrics
        # and the scores; streamed, reading each world's back and scoring it).
        self.stage_seconds = {"steps": 0.0, "metrics": 0.0}
        self._frames = None  # _frames_of

    #: The models whose swarms run worlds (the path model unless chasing with a baked noise:
    #: world_model above; the policy model with its followers' parameters, world_key).
    WORLD_MODELS = ("field", "force", "energy", "path", "policy")

    #: The force scenario's keys that stand for rows of its table
    #: (host/scenario/force_section.cpp); eta and rho set noise.scale = rho and
    #: noise.gain = eta / rho (Eq. 4), computed in float as the parser does.
    FORCE_ALIASES = {"model.noise_seed": "noise.seed", "model.noise_time_scale": "noise.time_scale"}

    def _setters(self) -> Optional[Dict[str, Callable[[dict], float]]]:
        """When the generation can run as worlds: each table key to set per
        world, with the function giving its value from an individual's
        {path: value}; None otherwise."""
        if not world_model(self.scenario):
            return None
        model = self.scenario["model"]
        force = model.get("type") == "force"
        paths = [p.path for p in self.params]
        setters = {}
        for path in paths:
            if is_domain_key(path):  # a world's own domain, given at creation
                continue
            if force and path in ("model.eta", "model.rho"):
                continue
            if force and path in self.FORCE_ALIASES:
                setters[self.FORCE_ALIASES[path]] = lambda v, path=path: v[path]
                continue
            key = world_key(self.scenario, path)
            if key is None:
                return None
            setters[key] = lambda v, path=path: v[path]
        if force and ("model.eta" in paths or "model.rho" in paths):
            eta0, rho0 = model.get("eta"), model.get("rho")
            if "noise" in model or ("model.eta" not in paths and eta0 is None) or \
                    ("model.rho" not in paths and rho0 is None):
                return None  # the value the parser would default to is not in the scenario

            def rho_of(v):
                return np.float32(v.get("model.rho", rho0))

            setters["noise.scale"] = lambda v: float(rho_of(v))
            setters["noise.gain"] = lambda v: float(np.float32(v.get("model.eta", eta0)) / rho_of(v))
        return setters

    def scenario_for(self, u, run: int = 0) -> dict:
        doc = _with_values(self.scenario, self.params, u)
        if self.seeds > 1 or self.base_seed != self.scenario_seed:
            doc["seed"] = self.base_seed + run
        return doc

    def _swarm(self, u, run: int = 0):
        try:
            return Scenario.parse(json.dumps(self.scenario_for(u, run))).create_swarm(self.context)
        except SwarmclError:
            self.refused += 1
            return None

    def _advance(self, swarms, sample) -> None:
        """The swarms advance side by side, `every` steps at a time, after the
        warm-up; sample(i) after each advance (and once before the first)."""
        for done in range(0, self.warmup, self.every):
            for s in swarms:
                s.step(min(self.every, self.warmup - done))
        for i in range(len(swarms)):
            sample(i)
        for _ in range(self.steps // self.every):
            for s in swarms:
                s.step(self.every)
            for i in range(len(swarms)):
                sample(i)

    def _all_terms(self, swarms) -> List[np.ndarray]:
        """The seven E_phi of each swarm's run."""
        sample_dt = self.every * self.dt
        if self.streamed:
            metrics = [Metrics.attach(s, sample_dt) for s in swarms]
            try:
                self._advance(swarms, lambda i: metrics[i].sample())
                # Pooled, a run's measure outlives its attachment (closed
                # below), so it is a copy; else its E_phi are read from it.
                return [self._measured(Metrics.merge([m]) if self.pool else m) for m in metrics]
            finally:
                for m in metrics:
                    m.close()
        frames = [[] for _ in swarms]
        self._advance(swarms, lambda i: frames[i].append(swarms[i].read_positions()))
        out = []
        for f in frames:
            out.append(self._measured(Metrics.from_frames(np.stack(f), sample_dt)))
        return out

    def _measured(self, sim: Metrics):
        """A run's measure, taking `sim` over: its E_phi (and W1) or the
        error that refuses it, sim closed; pooled, sim itself, closed when
        its individual is scored (_run_scores)."""
        if self.pool:
            return sim
        try:
            return self._terms_of(sim)
        except SwarmclError as e:
            return e
        finally:
            sim.close()

    def _run_scores(self, measured) -> List[float]:
        """The score of each run from its measure (_measured; None: refused
        when parsed).  Pooled, the S runs of an individual (consecutive)
        get the score of their samples merged; a refused run refuses them."""
        if not self.pool:
            return [self._score(t) for t in measured]
        out = []
        try:
            for i in range(0, len(measured), self.seeds):
                mine = measured[i:i + self.seeds]
                if any(m is None for m in mine):
                    s = REFUSED_SCORE
                elif any(isinstance(m, Exception) for m in mine):
                    self.refused += 1
                    s = REFUSED_SCORE
                else:
                    try:
                        with Metrics.merge(mine) as sim:
                            s = self._score(self._terms_of(sim))
                    except SwarmclError as e:
                        s = self._score(e)
                out.extend([s] * len(mine))
        finally:
            for m in measured:
                if isinstance(m, Metrics):
                    m.close()
        return out

    def _terms_of(self, sim: Metrics):
        """A run's seven E_phi and, with a scale penalty, its W1 per metric."""
        e = distances(self.real, sim, self.bins, self.half_width, self.robust)
        return e, (wasserstein(self.real, sim) if self.scale_penalty > 0.0 else None)

    def penalty(self, w1: dict) -> float:
        """P: the mean over the scale metrics with samples on both sides and a
        real spread > 0 of W1 / (1.4826 MAD of the real samples)."""
        ratios = [w1[name] / self.spread[k] for k, name in enumerate(METRICS)
                  if name in self.scale_metrics and w1[name] is not None and self.spread[k] > 0.0]
        return float(np.mean(ratios)) if ratios else 0.0

    def _score(self, terms_or_error) -> float:
        # A run that blew up (non-finite positions, so non-finite metrics)
        # scores as refused: never a NaN for the optimiser.  None: a scenario
        # refused when it was parsed (already counted).
        if terms_or_error is None:
            return REFUSED_SCORE
        if isinstance(terms_or_error, Exception):
            self.refused += 1
            return REFUSED_SCORE
        e, w1 = terms_or_error
        s = score(e, self.weights, self.p1, self.p2)
        return s - self.scale_penalty * self.penalty(w1) if w1 is not None else s

    def _world_swarm(self, runs, idx):
        """The runs idx as the worlds of one swarm, made from the first run's
        values (so parameters that select a kernel, such as the force
        model's noise time scale 0 or not, are the group's own) and set per
        world; None where the model refuses a value."""
        seeds = [self.base_seed + runs[i][1] if self.seeds > 1 else self.base_seed for i in idx]
        values = [{p.path: p.value(runs[i][0][k]) for k, p in enumerate(self.params)} for i in idx]
        try:
            with Scenario.parse(json.dumps(_with_values(self.scenario, self.params, runs[idx[0]][0]))) as scn:
                swarm = scn.create_world_swarm(self.context, len(idx), seeds, world_domains(self.scenario, values))
        except SwarmclError:
            return None
        try:
            for key, value_of in self._world_setters.items():
                swarm.set_world_param(key, [value_of(v) for v in values])
            return swarm
        except SwarmclError:
            swarm.close()
            return None

    def _world_groups(self, runs, idx) -> list:
        """The runs idx as few swarms of worlds as the model allows
        (world_groups)."""
        return world_groups(lambda part: self._world_swarm(runs, part), idx)

    def _parses(self, u) -> bool:
        """Whether the scenario parser takes an individual's values."""
        try:
            Scenario.parse(json.dumps(_with_values(self.scenario, self.params, u))).close()
            return True
        except SwarmclError:
            self.refused += 1
            return False

    def _world_terms(self, runs) -> list:
        """Every (individual, run) pair as a world: the seven E_phi of each,
        the error of a world that blew up, or None for a refused one.  One
        swarm for the generation where the model takes every value; else the
        runs the scenario parser refuses (a cross-parameter rule such as
        cruise_speed <= max_speed) are refused, and the rest grouped
        (_world_groups)."""
        out = [None] * len(runs)
        idx = list(range(len(runs)))
        swarm = self._world_swarm(runs, idx)
        if swarm is not None:
            groups = [(swarm, idx)]
        else:
            valid = [i for i in idx if self._parses(runs[i][0])]
            groups = self._world_groups(runs, valid) if valid else []
        self.last_swarms = len(groups)
        try:
            for swarm, group in groups:
                if swarm is None:
                    out[group[0]] = self._alone_terms(*runs[group[0]])
                else:
                    for i, t in zip(group, self._terms_of_worlds(swarm, len(group))):
                        out[i] = t
        finally:
            for swarm, _ in groups:
                if swarm is not None:
                    swarm.close()
        return out

    def _alone_terms(self, u, run: int):
        """One run as a swarm of its own: its E_phi, the error of a run that
        blew up, or None where the scenario was refused (counted by _swarm)."""
        swarm = self._swarm(u, run)
        if swarm is None:
            return None
        with swarm:
            try:
                return self._all_terms([swarm])[0]
            except SwarmclError as e:
                return e

    def _terms_of_worlds(self, swarm, worlds: int) -> list:
        """Each world's E_phi, streamed on the device or measured on the host."""
        if self.streamed:
            return self._streamed_world_terms(swarm, worlds)
        # The frames _advance would sample (after the warm-up, then every
        # `every` steps), gathered on the device without a wait after each.
        started = time.perf_counter()
        if self.warmup:
            swarm.step(self.warmup)
        # One array (frames, worlds, agents, 3) written in place; each
        # world's frames are measured where they lie (Metrics.from_frames
        # reads a strided world without copying it).
        n, sampled = swarm.agent_count, self.steps // self.every
        frames = self._frames_of((sampled + 1, worlds, n, 3))
        shape = (n, 3) if worlds == 1 else (worlds, n, 3)  # read_positions' shape
        swarm.read_positions(out=frames[0].reshape(shape))
        swarm.step_frames(sampled, self.every, out=frames[1:].reshape((sampled,) + shape))
        sample_dt = self.every * self.dt
        stepped = time.perf_counter()
        self.stage_seconds["steps"] += stepped - started

        def measure(k):
            try:
                sim = Metrics.from_frames(frames[:, k], sample_dt)
            except SwarmclError as e:
                return e
            return self._measured(sim)
        if self.threads > 1 and worlds > 1:
            with ThreadPoolExecutor(max_workers=min(self.threads, worlds)) as pool:
                out = list(pool.map(measure, range(worlds)))
        else:
            out = [measure(k) for k in range(worlds)]
        self.stage_seconds["metrics"] += time.perf_counter() - stepped
        return out

    def _frames_of(self, shape) -> np.ndarray:
        """The array a generation's frames are read into, kept from the last
        generation where the shape is the same: a fresh one of a fit's size
        (64 worlds x 300 agents x 501 frames, 115 MB) costs its first touch
        of every page, about 3 % of a generation."""
        if self._frames is None or self._frames.shape != shape:
            self._frames = np.empty(shape, dtype=np.float32)
        return self._frames

    def _streamed_world_terms(self, swarm, worlds: int) -> list:
        """Each world's E_phi from its metrics on the device (the error of
        a world whose metrics cannot be scored, e.g. one that blew up)."""
        with Metrics.attach(swarm, self.every * self.dt) as metrics:
            started = time.perf_counter()
            self._advance([swarm], lambda i: metrics.sample())
            stepped = time.perf_counter()
            self.stage_seconds["steps"] += stepped - started
            out = []
            for k in range(worlds):
                try:
                    sim = metrics.world(k)
                except SwarmclError as e:
                    out.append(e)
                    continue
                out.append(self._measured(sim))
            self.stage_seconds["metrics"] += time.perf_counter() - stepped
            return out

    def __call__(self, population, base_seed: Optional[int] = None) -> List[float]:
        """Each individual's score; ``base_seed``: its runs from that
        simulation seed on (a generation of fit(reseed=True)), else the
        last one given (first: the scenario's)."""
        if base_seed is not None:
            self.base_seed = int(base_seed)
        runs = [(u, r) for u in population for r in range(self.seeds)]
        if not runs:  # a rank's share of a small generation may be empty
            return []
        if self.world_keys is not None:
            per_run = self._run_scores(self._world_terms(runs))
            self.evaluations += len(population)
            return self._per_individual(population, per_run)
        # Every (individual, run) pair is one swarm, all stepped together.
        swarms = [self._swarm(u, r) for u, r in runs]
        live = [s for s in swarms if s is not None]
        self.last_swarms = len(live)
        try:
            try:
                terms = self._all_terms(live)
            except SwarmclError:
                # A run blew up: run each again alone, from a fresh swarm, so
                # only the one that fails is refused.
                terms = []
                for (u, r), s in zip(runs, swarms):
                    if s is None:
                        continue
                    with self._swarm(u, r) as fresh:
                        try:
                            terms.append(self._all_terms([fresh])[0])
                        except SwarmclError as e:
                            terms.append(e)
            measures = iter(terms)
            per_run = self._run_scores([next(measures) if s is not None else None for s in swarms])
        finally:
            for s in live:
                s.close()
        self.evaluations += len(population)
        return self._per_individual(population, per_run)

    def _per_individual(self, population, per_run) -> List[float]:
        """The mean over each individual's runs (refused if one is)."""
        out = []
        for i in range(len(population)):
            mine = per_run[i * self.seeds:(i + 1) * self.seeds]
            out.append(REFUSED_SCORE if REFUSED_SCORE in mine else float(np.mean(mine)))
        return out

    def terms(self, scenario: dict) -> np.ndarray:
        """The seven energy terms E_phi (Eq. 2) of one scenario, run as a
        population member is: one run (the scenario's seed); pooled, its S
        runs (seeds seed .. seed + S - 1) measured together."""
        if not self.pool:
            with Scenario.parse(json.dumps(scenario)).create_swarm(self.context) as s:
                t = self._all_terms([s])[0]
            if isinstance(t, Exception):
                raise t
            return t[0]
        base = int(scenario.get("seed", 0))
        runs = []
        try:
            for r in range(self.seeds):
                with Scenario.parse(json.dumps(dict(scenario, seed=base + r))).create_swarm(self.context) as s:
                    runs.append(self._all_terms([s])[0])
                if isinstance(runs[-1], Exception):
                    raise runs[-1]
            with Metrics.merge(runs) as sim:
                return self._terms_of(sim)[0]
        finally:
            for m in runs:
                if isinstance(m, Metrics):
                    m.close()


@dataclass
class _RankError:
    """What a serving rank sends rank 0 in place of its scores when its
    evaluation raised."""
    rank: int
    message: str


class _Ranks:
    """Spreads a population over MPI ranks (contiguous blocks, in order) and
    gathers the scores on rank 0; without MPI, evaluates in place.  Ranks
    other than 0 serve in serve() until rank 0 calls stop()."""

    def __init__(self, evaluate: Callable, comm=None):
        self.evaluate, self.comm = evaluate, comm
        self.rank = comm.Get_rank() if comm is not None else 0
        self.size = comm.Get_size() if comm is not None else 1

    def _share(self, population, rank):
        blocks = np.array_split(np.arange(len(population)), self.size)
        return [population[i] for i in blocks[rank]]

    def map(self, population, base_seed: Optional[int] = None) -> List[float]:
        """The scores of `population`; `base_seed`: the simulation seed its
        runs start from on every rank (None: as before)."""
        population = [np.asarray(u, dtype=np.float64) for u in population]
        if self.size == 1:
            return self._evaluate(population, base_seed)
        self.comm.bcast(("evaluate", population, base_seed), root=0)
        mine = self._evaluate(self._share(population, 0), base_seed)
        parts = self.comm.gather(mine, root=0)
        # A rank whose evaluation raised sends its error instead of scores:
        # the generation fails with it, never with a partial or shifted list.
        failed = [p for p in parts if isinstance(p, _RankError)]
        if failed:
            raise RuntimeError("; ".join(f"rank {e.rank} failed in a generation: {e.message}" for e in failed))
        return [x for part in parts for x in part]

    def serve(self) -> None:
        while True:
            command, population, base_seed = self.comm.bcast(None, root=0)
            if command == "stop":
                return
            try:
                scores = self._evaluate(self._share(population, self.rank), base_seed)
            except Exception as e:  # noqa: BLE001  sent to rank 0, which raises it
                scores = _RankError(self.rank, f"{type(e).__name__}: {e}")
            self.comm.gather(scores, root=0)

    def _evaluate(self, population, base_seed):
        return self.evaluate(population) if base_seed is None else self.evaluate(population, base_seed)

    def stop(self) -> None:
        if self.size > 1:
            self.comm.bcast(("stop", None, None), root=0)


# A search stops on tolerance: CMA-ES when cma's own tolerances say so
# (tolfun: the scores of recent generations within `tolerance`; tolx: the
# step size below `step_tolerance` of the unit box) or, with `patience`, when
# its best has gained no more than `tolerance` in that many generations (on
# a simulated swarm the score is rough at small scales, so cma's tolerances
# may never trigger; cma ends its restarts on such a stop, so the two are
# not combined); the GA on the latter.  `generations`
# is the budget per run (per restart for CMA-ES).  The result says whether
# it converged and why it stopped.
_CMA_CONVERGED = ("tolfun", "tolfunhist", "tolx", "tolstagnation", "tolflatfitness", "tolupsigma")


def _start_entry(ranks: _Ranks, start, report, base_seed: Optional[int] = None) -> tuple:
    """Scores the start point alone (history's generation 0), so a search
    from it never ends below it: a nested model fitted from the smaller
    model's optimum scores at least as well as that model."""
    s = ranks.map([start], base_seed)[0]
    entry = {"generation": 0, "individuals": 1, "best": s, "mean": s, "best_so_far": s}
    report(entry)
    return s, entry


def _cmaes(ranks: _Ranks, dim: int, generations: int, population: int, seed: int, report, *,
           restarts: int = 0, tolerance: float = 1e-3, step_tolerance: float = 1e-3, start=None,
           patience: Optional[int] = None, seed_of: Optional[Callable[[int], int]] = None) -> tuple:
    # seed_of: generation -> the simulation seed its runs start from
    # (fit(reseed=True)); None: every generation on the scenario's seeds.
    import cma
    history = []
    best = {"u": None, "score": -math.inf}
    generation = [0]
    if start is not None:
        best["score"], entry = _start_entry(ranks, start, report, None if seed_of is None else seed_of(0))
        best["u"] = np.array(start, dtype=np.float64)
        history.append(entry)

    def objective(xs):
        generation[0] += 1
        scores = ranks.map(xs, None if seed_of is None else seed_of(generation[0]))
        for x, s in zip(xs, scores):
            if s > best["score"]:
                best["u"], best["score"] = np.array(x, dtype=np.float64), s
        # cma ends by scoring its final mean alone: an entry of 1 individual.
        history.append({"generation": len(history) + 1, "individuals": len(xs), "best": max(scores),
                        "mean": float(np.mean(scores)), "best_so_far": best["score"]})
        report(history[-1])
        return [-s for s in scores]  # cma minimises

    def stalled(es) -> bool:
        bests = [h["best_so_far"] for h in history if h["generation"] > 0]  # the start point's entry is 0
        return patience is not None and len(bests) > patience and bests[-1] - bests[-1 - patience] <= tolerance

    # cma takes seed 0 as "from the clock": shift so every seed is fixed.
    # restarts > 0: BIPOP-CMA-ES (restarts with growing and small
    # populations, Hansen 2009), pycma's own.
    options = {"bounds": [0.0, 1.0], "popsize": int(population), "maxiter": int(generations),
               "seed": int(seed) + 1, "verbose": -9, "tolfun": float(tolerance), "tolfunhist": float(tolerance),
               "tolx": float(step_tolerance), "termination_callback": [stalled]}
    es = cma.fmin2(None, list(start) if start is not None else [0.5] * dim, 0.3, options=options,
                   parallel_objective=objective,
                   restarts=int(restarts), bipop=bool(restarts))[1]
    stop = sorted(es.stop().keys())
    if "callback" in stop:
        stop[stop.index("callback")] = f"no gain above {tolerance} in {patience} generations"
    converged = any(k in _CMA_CONVERGED or k.startswith("no gain") for k in stop)
    if seed_of is not None:
        # Reseeded, the best score seen is the luckiest draw of many; the
        # search's final mean is its estimate of the optimum (pycma's
        # xfavorite), scored on generation 0's seeds (the scenario's).
        u = np.clip(np.asarray(es.result.xfavorite, dtype=np.float64), 0.0, 1.0)
        return u, ranks.map([u], seed_of(0))[0], history, {"converged": converged, "stop": stop}
    return best["u"], best["score"], history, {"converged": converged, "stop": stop}


def _ga(ranks: _Ranks, dim: int, generations: int, population: int, seed: int, report, *,
        tolerance: float = 1e-3, patience: int = 5, start=None) -> tuple:
    # The paper's genetic algorithm (§3.3; its operators are not given), as
    # DEAP's (mu + lambda) loop (algorithms.varOr, then the best mu of
    # parents and offspring): real genes in [0, 1], simulated binary
    # crossover (eta 20, p 0.6), polynomial mutation (eta 20, 1/d per gene,
    # p 0.3), else a copy; only individuals without a fitness are scored
    # (copies keep theirs); a hall of fame keeps the best ever.
    from deap import algorithms, base, tools

    class Fitness(base.Fitness):
        weights = (1.0,)

    class Individual(list):
        def __init__(self, genes):
            super().__init__(genes)
            self.fitness = Fitness()

    toolbox = base.Toolbox()
    toolbox.register("mate", tools.cxSimulatedBinaryBounded, eta=20.0, low=0.0, up=1.0)
    toolbox.register("mutate", tools.mutPolynomialBounded, eta=20.0, low=0.0, up=1.0, indpb=1.0 / dim)
    toolbox.register("select", tools.selBest)

    saved = random.getstate()
    random.seed(int(seed))
    try:
        hof = tools.HallOfFame(1)

        def evaluate(individuals):
            fresh = [i for i in individuals if not i.fitness.valid]
            scores = ranks.map([list(i) for i in fresh]) if fresh else []
            for ind, s in zip(fresh, scores):
                ind.fitness.values = (s,)
            hof.update(individuals)

        pop = [Individual([random.random() for _ in range(dim)]) for _ in range(int(population))]
        history, stalled, converged = [], 0, False
        if start is not None:  # the start point joins the first population, scored alone first
            pop[0] = Individual(list(start))
            s0, entry = _start_entry(ranks, start, report)
            pop[0].fitness.values = (s0,)
            history.append(entry)
        evaluate(pop)
        for g in range(int(generations)):
            before = hof[0].fitness.values[0]
            offspring = algorithms.varOr(pop, toolbox, int(population), cxpb=0.6, mutpb=0.3)
            scored = sum(1 for i in offspring if not i.fitness.valid)
            evaluate(offspring)
            pop = toolbox.select(pop + offspring, int(population))
            scores = [i.fitness.values[0] for i in pop]
            history.append({"generation": g + 1, "individuals": scored,
                            "best": max(scores), "mean": float(np.mean(scores)),
                            "best_so_far": hof[0].fitness.values[0]})
            report(history[-1])
            stalled = stalled + 1 if hof[0].fitness.values[0] - before <= tolerance else 0
            if stalled >= patience:
                converged = True
                break
        stop = [f"no gain above {tolerance} in {patience} generations"] if converged else ["generations"]
        return (np.array(hof[0], dtype=np.float64), hof[0].fitness.values[0], history,
                {"converged": converged, "stop": stop})
    finally:
        random.setstate(saved)


def _start_point(params: Sequence[Parameter], start: Dict[str, float]) -> List[float]:
    """The point in [0, 1]^d of {path: value}; a path not given: 0.5."""
    known = {p.path for p in params}
    unknown = sorted(set(start) - known)
    if unknown:
        raise ValueError(f"start: {', '.join(unknown)} not among the fitted parameters ({', '.join(sorted(known))})")
    u = []
    for p in params:
        if p.path not in start:
            u.append(0.5)
            continue
        v = float(start[p.path])
        if not (p.low <= v <= p.high):
            raise ValueError(f"start: {p.path} = {v} is outside its range [{p.low}, {p.high}]")
        u.append((v - p.low) / (p.high - p.low) if p.high > p.low else 0.0)
    return u


def _context_for_rank(rank: int, device=None) -> Context:
    # SWARMCL_DEVICE (or `device`) chooses one device for every rank;
    # otherwise ranks take the devices round-robin.
    if device is not None or os.environ.get("SWARMCL_DEVICE"):
        return Context(device)
    return Context(rank % max(1, len(devices())))


def fit(scenario, tracks: Metrics, ranges, *, method: str = "cmaes", generations: int = 10, population: int = 8,
        seed: int = 1, steps: Optional[int] = None, every: Optional[int] = None, warmup: int = 0, bins: int = 50,
        half_width: float = 4.0, weights=None, p1=None, p2=None, comm=None, context: Optional[Context] = None,
        progress: Optional[Callable[[dict], None]] = None, streamed: Optional[bool] = None, robust: bool = False,
        scale_penalty: float = 0.0, seeds: int = 1, restarts: int = 0, tolerance: float = 1e-3,
        step_tolerance: float = 1e-3, patience: Optional[int] = None,
        start: Optional[Dict[str, float]] = None, scale_metrics: Optional[Sequence[str]] = None,
        pool: bool = False, reseed: bool = False) -> Optional[dict]:
    """Fits the ranged parameters of ``scenario`` (a path or a dict) to
    ``tracks`` (a Metrics) by maximising E.  ``method``: "cmaes" or "ga".
    With ``comm`` (an mpi4py communicator of R ranks), every rank must call
    fit() with the same arguments: rank 0 returns the result, the others
    serve evaluations and return None.  The same seed gives the same result
    for any R.  A generation's runs are the worlds of one swarm where the
    model runs worlds (the field, force, energy, path and policy models: world_model) and every ranged
    parameter may differ between worlds (world_key), else each run is a swarm
    of its own.  ``streamed`` True: each run's metrics on the device (fine
    histograms, per world); False reads positions back and measures them on
    the host (exact PDFs); None (the default): the host for worlds on a CPU
    device (the faster there), else the device.  ``robust``: PDFs z-scored with median
    and MAD; ``scale_penalty`` λ > 0 maximises E - λ P instead, P the mean
    (over ``scale_metrics``, default all seven)
    Wasserstein-1 distance in units of the real data's spread
    (PopulationEvaluator, docs/evaluation.md).  ``seeds``: each individual
    scored as the mean of that many runs with consecutive scenario seeds (the
    same for all: common random numbers); ``pool``: scored once from those
    runs' samples together (Metrics.merge) instead.  Stopping: ``generations`` is the
    budget (per restart); CMA-ES stops earlier on its tolerances (scores
    within ``tolerance``, or steps below ``step_tolerance`` of each range:
    the search has narrowed to that fraction), with ``restarts`` BIPOP restarts;
    the GA when its best gains at most ``tolerance`` in ``patience``
    generations (default 5), and so CMA-ES when ``patience`` is given
    (not with ``restarts``).  The result's ``converged`` and ``stop`` say which.
    ``start``: {path: value} to search from (CMA-ES's first mean, one of the
    GA's first individuals; other parameters at their range's centre),
    scored first, so the result is never below it: fit a model whose ranges
    contain another's from that one's best, and it scores at least as well.
    ``reseed`` (CMA-ES, without restarts): each generation runs on simulation
    seeds of its own (common random numbers within it, fresh ones across
    generations: seeds scenario seed + g * ``seeds`` on), so the search cannot
    tune itself to one set of runs; the result is the search's final mean,
    scored on the scenario's seeds, and need not score above ``start``."""
    if method not in ("cmaes", "ga"):
        raise ValueError(f"method: 'cmaes' or 'ga', got {method!r}")
    if int(generations) < 1 or int(population) < 2:
        raise ValueError("generations must be >= 1 and population >= 2")
    if method == "ga" and patience is None:
        patience = 5
    if reseed and (method != "cmaes" or int(restarts) > 0):
        raise ValueError("reseed: CMA-ES without restarts only (its result is the search's final mean; the GA "
                         "keeps its individuals' scores across generations)")
    if method == "cmaes" and patience is not None and int(restarts) > 0:
        raise ValueError("patience and restarts cannot be combined with CMA-ES (cma ends its restarts on a "
                         "patience stop); give one of them")
    if int(restarts) < 0 or not (float(tolerance) >= 0.0) or (patience is not None and int(patience) < 1) or \
            not (0.0 < float(step_tolerance) < 1.0):
        raise ValueError("restarts must be >= 0, tolerance >= 0, step_tolerance in (0, 1) and patience >= 1")
    if isinstance(scenario, (str, os.PathLike)):
        with open(scenario, encoding="utf-8") as f:
            scenario = json.load(f)
    params = load_ranges(ranges, scenario)
    if method == "cmaes" and len(params) < 2:
        raise ValueError("cmaes needs at least two parameters (cma does not run in one dimension); use method='ga'")
    rank = comm.Get_rank() if comm is not None else 0
    own = context is None
    ctx = _context_for_rank(rank) if own else context
    try:
        evaluator = PopulationEvaluator(scenario, params, tracks, ctx, steps=steps, every=every, warmup=warmup,
                                        bins=bins, half_width=half_width, weights=weights, p1=p1, p2=p2,
                                        streamed=streamed, robust=robust, scale_penalty=scale_penalty,
                                        seeds=seeds, scale_metrics=scale_metrics, pool=pool)
        if comm is not None:
            evaluator.threads = max(1, (os.cpu_count() or 1) // comm.Get_size())
        ranks = _Ranks(evaluator, comm)
        if rank != 0:
            ranks.serve()
            return None
        began = time.perf_counter()
        report = progress or (lambda entry: None)
        try:
            u0 = _start_point(params, start) if start is not None else None
            if method == "cmaes":
                seed_of = (lambda g: evaluator.scenario_seed + g * evaluator.seeds) if reseed else None
                u, best, history, end = _cmaes(ranks, len(params), generations, population, seed, report,
                                               restarts=restarts, tolerance=tolerance,
                                               step_tolerance=step_tolerance, start=u0,
                                               patience=None if patience is None else int(patience),
                                               seed_of=seed_of)
            else:
                u, best, history, end = _ga(ranks, len(params), generations, population, seed, report,
                                            tolerance=tolerance, patience=patience, start=u0)
        finally:
            ranks.stop()
        return {
            "method": method, "seed": int(seed), "generations": int(generations), "population": int(population),
            "ranks": ranks.size, "steps": evaluator.steps, "every": evaluator.every, "warmup": evaluator.warmup,
            "pdf": {"bins": evaluator.bins, "half_width": evaluator.half_width,
                    "standardise": "median_mad" if evaluator.robust else "mean_sigma"},
            "scale_penalty": evaluator.scale_penalty, "scale_metrics": evaluator.scale_metrics,
            "seeds": evaluator.seeds, "pool": evaluator.pool, "reseed": bool(reseed),
            "restarts": int(restarts) if method == "cmaes" else 0, "tolerance": float(tolerance),
            "step_tolerance": float(step_tolerance) if method == "cmaes" else None,
            "patience": None if patience is None else int(patience),
            "converged": bool(end["converged"]), "stop": end["stop"],
            "parameters": {p.path: {"low": p.low, "high": p.high} for p in params},
            "best": {p.path: p.value(x) for p, x in zip(params, u)},
            "best_score": float(best), "history": history,
            "evaluations": evaluator.evaluations, "refused_on_rank0": evaluator.refused,
            "seconds": time.perf_counter() - began,
            "scenario": _with_values(scenario, params, u),
        }
    finally:
        if own:
            ctx.close()


def compare(models: Dict[str, tuple], tracks: Metrics, *, max_iterations: int = 5, tolerance: float = 0.01,
            context: Optional[Context] = None, progress: Optional[Callable[[str, dict], None]] = None,
            **fit_options) -> dict:
    """The evaluation algorithm of §3.3 (Steps 1-5) over several models:
    ``models`` maps a name to ``(scenario, ranges)``.  Step 1: equal weights,
    p1 = 0, p2 = 1.  Step 2: fit every model (fit() with ``fit_options``)
    under the current weights; its seven energy terms E_phi form a row of X.
    Step 3: entropy weights and p1, p2 from X (Eq. 4).  Step 4: stop when no
    weight moved more than ``tolerance`` or after ``max_iterations``; else
    back to Step 2.  Step 5: the weights, p1, p2, every model's parameters,
    terms and final score E (Eq. 1 with Eq. 3), ranked."""
    if len(models) < 2:
        raise ValueError("compare: the entropy weights need at least two models")
    if int(max_iterations) < 1 or not tolerance > 0:
        raise ValueError("compare: max_iterations >= 1 and tolerance > 0")
    own = context is None
    ctx = Context() if own else context
    try:
        n = len(METRICS)
        w, p1, p2 = np.full(n, 1.0 / n), np.zeros(n), np.ones(n)
        iterations = []
        for it in range(int(max_iterations)):
            fitted = {}
            for name, (scenario, ranges) in models.items():
                r = fit(scenario, tracks, ranges, context=ctx, weights=w, p1=p1, p2=p2,
                        progress=(lambda e, name=name: progress(name, e)) if progress else None, **fit_options)
                ev = PopulationEvaluator(r["scenario"], [], tracks, ctx, steps=r["steps"], every=r["every"],
                                         warmup=r["warmup"], bins=r["pdf"]["bins"], half_width=r["pdf"]["half_width"])
                fitted[name] = (r, ev.terms(r["scenario"]))
            x = np.array([terms for _, terms in fitted.values()])
            w_new, p1, p2 = entropy_weights(x)
            moved = float(np.max(np.abs(w_new - w)))
            w = w_new
            iterations.append({"iteration": it + 1, "weights": w.tolist(), "p1": p1.tolist(), "p2": p2.tolist(),
                               "largest_weight_change": moved})
            if moved <= tolerance:
                break
        result = {"weights": w.tolist(), "p1": p1.tolist(), "p2": p2.tolist(), "iterations": iterations,
                  "models": {}}
        for name, (r, terms) in fitted.items():
            result["models"][name] = {"best": r["best"], "terms": dict(zip(METRICS, map(float, terms))),
                                      "score": score(terms, w, p1, p2), "scenario": r["scenario"]}
        result["ranking"] = sorted(result["models"], key=lambda k: -result["models"][k]["score"])
        return result
    finally:
        if own:
            ctx.close()


def _bar(entry: dict, total: int) -> None:
    done = min(entry["generation"], total)
    width = 30
    filled = int(width * done / total) if total else width
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] generation {done}/{total}  "
                     f"best E {entry['best_so_far']:.4f}  mean {entry['mean']:.4f}")
    if done >= total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def add_track_options(p: argparse.ArgumentParser, tracks_required: bool) -> None:
    """The options of the commands that score runs against tracks (fit,
    sweep): the track file and how to read it, the run's sampling, the PDFs."""
    p.add_argument("--tracks", required=tracks_required, help="track CSV")
    p.add_argument("--columns", default="id,time,x,y,z", help="id,time,x,y,z column names (default %(default)s)")
    p.add_argument("--delimiter", default=",", help="the tracks' field separator: one character, or tab "
                   "(default %(default)s)")
    p.add_argument("--unit-scale", type=float, default=1.0, help="track position unit in metres (0.01: cm)")
    p.add_argument("--window", default="0,1", help="FROM,TO fractions of the samples by time (default all)")
    p.add_argument("--steps", type=int)
    p.add_argument("--every", type=int)
    p.add_argument("--warmup", type=int, default=0)
    p.add_argument("--bins", type=int, default=50)
    p.add_argument("--half-width", type=float, default=4.0)
    p.add_argument("--robust", action="store_true", help="z-score the PDFs with median and MAD")


def mpi_comm():
    """MPI.COMM_WORLD when started by mpirun with several ranks, else None."""
    if int(os.environ.get("OMPI_COMM_WORLD_SIZE", os.environ.get("PMI_SIZE", "1"))) > 1:
        from mpi4py import MPI  # started by mpirun: spread over its ranks
        return MPI.COMM_WORLD
    return None


def track_window(text: str) -> tuple:
    """--window FROM,TO as two floats."""
    window = tuple(float(x) for x in text.split(","))
    if len(window) != 2:
        raise ValueError("--window: expected FROM,TO")
    return window


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="swarmcl fit", description="Fit a scenario's parameters to real tracks "
                                "(the noise paper's Par-Est); under mpirun the individuals are spread over ranks.")
    p.add_argument("scenario")
    p.add_argument("--ranges", required=True, help="JSON {\"scenario.path\": [low, high], ...}")
    p.add_argument("--method", choices=("cmaes", "ga"), default="cmaes")
    p.add_argument("--generations", type=int, default=10)
    p.add_argument("--population", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    add_track_options(p, tracks_required=True)
    p.add_argument("--seeds", type=int, default=1, help="runs per individual, consecutive scenario seeds "
                   "(common random numbers); default 1")
    p.add_argument("--pool", action="store_true", help="score an individual's --seeds runs once, from their "
                   "samples together, instead of the mean of their scores")
    p.add_argument("--restarts", type=int, default=0, help="CMA-ES: BIPOP restarts (default 0)")
    p.add_argument("--reseed", action="store_true", help="CMA-ES without restarts: each generation on simulation "
                   "seeds of its own, the result the search's final mean (fit(reseed=True))")
    p.add_argument("--tolerance", type=float, default=1e-3, help="stop when the best gains no more (default 1e-3)")
    p.add_argument("--step-tolerance", type=float, default=1e-3,
                   help="CMA-ES: stop when its steps are below this fraction of every range (default 1e-3)")
    p.add_argument("--patience", type=int,
                   help="stop when the best gains no more than --tolerance in this many generations "
                        "(GA: default 5; CMA-ES: only when given)")
    p.add_argument("--scale-penalty", type=float, default=0.0,
                   help="maximise E - X * (mean Wasserstein-1 distance in the real data's spreads); default 0")
    p.add_argument("--scale-metrics", type=lambda s: s.split(","),
                   help="the metrics that mean is over, comma-separated (default all seven), "
                        "e.g. speed,nearest_distance")
    p.add_argument("--spread", metavar="FITS,RESAMPLES",
                   help="how sure the fit is: fit FITS times (optimiser seeds from --seed) and once to each of "
                        "RESAMPLES block resamples of the tracks, and report every parameter's spread "
                        "(swarmcl.fit_spread; one process)")
    p.add_argument("--blocks", type=int, default=10, help="--spread: spans of time a resample draws (default 10)")
    p.add_argument("--out", default="fit.json", help="result JSON (default %(default)s)")
    p.add_argument("--device", help="device index or name part (default: SWARMCL_DEVICE, or round-robin by rank)")
    p.add_argument("--plot", action="store_true", help="draw the history beside the JSON (FILE.png; matplotlib)")
    p.add_argument("--quiet", action="store_true")
    return p


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    comm = mpi_comm()
    rank = comm.Get_rank() if comm is not None else 0
    try:
        window = track_window(args.window)
        device = int(args.device) if args.device and args.device.isdigit() else args.device
        if args.spread:
            return _spread_main(args, window, device, comm)
        ctx = _context_for_rank(rank, device)
        with ctx, Metrics.from_csv(args.tracks, window=window, unit_scale=args.unit_scale, columns=args.columns,
                                   delimiter=args.delimiter) as real:
            total = args.generations
            show = (not args.quiet) and rank == 0 and sys.stderr.isatty()
            result = fit(args.scenario, real, args.ranges, method=args.method, generations=args.generations,
                         population=args.population, seed=args.seed, steps=args.steps, every=args.every,
                         warmup=args.warmup, bins=args.bins, half_width=args.half_width, comm=comm, context=ctx,
                         robust=args.robust, scale_penalty=args.scale_penalty, seeds=args.seeds, pool=args.pool,
                         reseed=args.reseed, restarts=args.restarts, tolerance=args.tolerance,
                         step_tolerance=args.step_tolerance,
                         patience=args.patience, scale_metrics=args.scale_metrics,
                         progress=(lambda e: _bar(e, total)) if show else None)
    except (ValueError, OSError, RuntimeError, SwarmclError) as e:
        print(f"swarmcl fit: {e}", file=sys.stderr)
        if comm is not None:
            comm.Abort(1)
        return 1
    if rank == 0:
        _write_json(result, args.out)
        if not args.quiet:
            best = ", ".join(f"{k} = {v:.6g}" for k, v in result["best"].items())
            state = "converged" if result["converged"] else "did not converge"
            print(f"best E = {result['best_score']:.4f} after {result['evaluations']} evaluations on "
                  f"{result['ranks']} rank(s) in {result['seconds']:.1f} s ({state}: {', '.join(result['stop'])}): "
                  f"{best}\nwritten to {args.out}")
        if args.plot:
            png = os.path.splitext(args.out)[0] + ".png"
            try:
                plot_history(result, png)
            except ImportError:
                print("swarmcl fit: --plot needs matplotlib (pip install 'swarmcl[plot]'); "
                      f"{args.out} is complete", file=sys.stderr)
                return 1
            if not args.quiet:
                print(f"plot: {png}")
    return 0


def _write_json(result: dict, path: str) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def _spread_main(args, window, device, comm) -> int:
    """swarmcl fit --spread FITS,RESAMPLES: fit_spread, its table printed."""
    from .evaluation import read_tracks
    from .spread import fit_spread
    if comm is not None:
        raise ValueError("--spread runs in one process (not under mpirun)")
    parts = args.spread.split(",")
    if len(parts) != 2 or not all(x.strip().isdigit() for x in parts):
        raise ValueError("--spread: expected FITS,RESAMPLES (two integers)")
    fits, resamples = (int(x) for x in parts)
    tracks = read_tracks(args.tracks, window=window, unit_scale=args.unit_scale, columns=args.columns,
                         delimiter=args.delimiter)
    with Context(device) as ctx:
        result = fit_spread(args.scenario, tracks, args.ranges, fits=fits, bootstrap=resamples, blocks=args.blocks,
                            seed=args.seed, method=args.method, generations=args.generations,
                            population=args.population, steps=args.steps, every=args.every, warmup=args.warmup,
                            bins=args.bins, half_width=args.half_width, context=ctx, robust=args.robust,
                            scale_penalty=args.scale_penalty, seeds=args.seeds, pool=args.pool,
                            reseed=args.reseed, restarts=args.restarts,
                            tolerance=args.tolerance, step_tolerance=args.step_tolerance, patience=args.patience,
                            scale_metrics=args.scale_metrics)
    _write_json(result, args.out)
    if not args.quiet:
        for path, q in result["parameters"].items():
            boot = (f"resamples {q['bootstrap_mean']:.4g} ± {q['bootstrap_sd']:.2g}"
                    if q["bootstrap_mean"] is not None else "no resamples")
            print(f"{path}: seeds {q['seed_mean']:.4g} ± {q['seed_sd']:.2g}, {boot} "
                  f"({'pinned down' if q['pinned'] else 'loose'}; range [{q['low']:.4g}, {q['high']:.4g}])")
        print(f"written to {args.out}")
    return 0


def plot_history(result: dict, path) -> None:
    """A fit's history as one PNG: each generation's best and mean score and
    the best so far, with whether it converged and why it stopped.  Needs
    matplotlib."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = result["history"]
    g = [e["generation"] for e in h]
    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    ax.plot(g, [e["mean"] for e in h], color="0.6", label="generation mean")
    ax.plot(g, [e["best"] for e in h], color="tab:blue", marker=".", lw=0.8, label="generation best")
    ax.plot(g, [e["best_so_far"] for e in h], color="k", label="best so far")
    ax.set_xlabel("generation (cma: one per call, restarts continue the count)")
    ax.set_ylabel("objective (E, minus the scale penalty if any)")
    state = "converged" if result.get("converged") else "did not converge"
    ax.set_title(f"{result['method']}: {state} ({', '.join(result.get('stop', []))}), "
                 f"{result['evaluations']} evaluations", fontsize=9)
    ax.legend(fontsize=8)
    tmp = str(path) + ".tmp.png"
    fig.savefig(tmp, dpi=80)
    plt.close(fig)
    os.replace(tmp, path)


"""The evaluation against real insects (noise paper §3; docs/evaluation.md).

Seven time-varying metrics -- speed, acceleration, angular velocity, angular
acceleration, Cartesian jerk, nearest-neighbour distance, velocity difference
-- sampled from real tracks or simulated frames, compared as z-scored
discrete PDFs (Eq. 2-3) and scored E = 1 - sum w E_phi (Eq. 1); entropy
weights (Eq. 4) over several models.

>>> real = swarmcl.Metrics.from_csv("tracks.csv", columns={"time": "datetime", "x": "x_cm",
...                                  "y": "y_cm", "z": "z_cm"}, unit_scale=0.01)
>>> result = swarmcl.evaluate("examples/scenarios/path_aggregation.json", real, out_dir="out/eval")
>>> result["score"]
"""
from __future__ import annotations

import json
import os
import time
from typing import Optional, Sequence, Tuple

import numpy as np

from ._core import Context, Scenario, _Handle
from ._native import ffi, lib
from .energy import _METRIC_TRACK_OPTIONS, _track_arrays, _track_desc, _track_pointers
from .errors import check

__all__ = ["METRICS", "METRIC_UNITS", "Metrics", "distances", "wasserstein", "score", "entropy_weights", "evaluate",
           "plot_pdfs"]

#: The metric names, in the order of the C enum swcl_metric (and of every array here): the
#: library's metric table (swcl_metric_name; host/eval/metric_table.hpp), not written again here.
METRICS: Tuple[str, ...] = tuple(ffi.string(lib.swcl_metric_name(k)).decode()
                                 for k in range(lib.SWCL_METRIC_COUNT))
#: Each metric's SI unit ("m/s", ..., "m", "1/s"), from the same table (swcl_metric_unit).
METRIC_UNITS: Tuple[str, ...] = tuple(ffi.string(lib.swcl_metric_unit(k)).decode()
                                      for k in range(lib.SWCL_METRIC_COUNT))

_STANDARDISE = {"mean_sigma": lib.SWCL_STANDARDISE_MEAN_SIGMA, "median_mad": lib.SWCL_STANDARDISE_MEDIAN_MAD}


def _metric_index(metric) -> int:
    if isinstance(metric, str):
        try:
            return METRICS.index(metric)
        except ValueError:
            raise ValueError(f"metric: one of {', '.join(METRICS)}, got {metric!r}") from None
    i = int(metric)
    if not 0 <= i < len(METRICS):
        raise ValueError(f"metric: an index 0..{len(METRICS) - 1}, got {i}")
    return i


def _pdf_options(bins: int, half_width: float, robust: bool = False):
    o = ffi.new("swcl_pdf_options*", lib.swcl_pdf_options_default())
    o.bins = int(bins)
    o.half_width = float(half_width)
    o.standardise = _STANDARDISE["median_mad" if robust else "mean_sigma"]
    return o


class Metrics(_Handle):
    """Samples of the seven metrics from tracks or simulated frames (held by
    the library; read them as moments and PDFs)."""

    _kind = "metrics"

    def __init__(self, _handle_ptr):
        """Use Metrics.from_csv / from_tracks / from_frames."""
        self._adopt(_handle_ptr, lib.swcl_metrics_destroy, "swcl_metrics*")

    @classmethod
    def _make(cls, fn) -> "Metrics":
        h = ffi.new("swcl_metrics*")
        check(fn(h))
        return cls(h)

    @classmethod
    def from_csv(cls, path, window: Tuple[float, float] = (0.0, 1.0), **options) -> "Metrics":
        """From a track CSV (``columns``, ``delimiter``, ``time_format``,
        ``frame_time``, ``unit_scale``, ``gap_factor``, ``smoothing`` as for
        Dataset.from_csv; ``columns`` also as "id,time,x,y,z"), keeping the
        samples in ``window``: fractions of all samples ordered by time, e.g.
        ``(0, 0.5)`` for the first half of the data by time."""
        d, _keep = _track_desc("Metrics.from_csv", options, _METRIC_TRACK_OPTIONS)
        lo, hi = window
        return cls._make(lambda h: lib.swcl_metrics_from_csv(os.fsencode(path), d, float(lo), float(hi), h))

    @classmethod
    def from_tracks(cls, tracks, window: Tuple[float, float] = (0.0, 1.0), **options) -> "Metrics":
        """From tracks given as ``[(times, positions), ...]`` (as Dataset.from_tracks)."""
        c, t, p = _track_arrays(tracks, "from_tracks")
        d, _keep = _track_desc("Metrics.from_tracks", options, _METRIC_TRACK_OPTIONS)
        lo, hi = window
        return cls._make(lambda h: lib.swcl_metrics_from_tracks(*_track_pointers(c, t, p), d, float(lo), float(hi), h))

    @classmethod
    def from_frames(cls, frames, dt: float) -> "Metrics":
        """From simulated frames, an array (frames, agents, 3), dt seconds apart.
        float32 frames whose agents are packed are read in place whatever the
        step between frames (e.g. ``frames[:, k]`` of a swarm of worlds'
        (frames, W, N, 3)); anything else is copied first."""
        a = np.asarray(frames)
        if (a.dtype == np.float32 and a.ndim == 3 and a.shape[2] == 3 and a.size and a.strides[2] == 4
                and a.strides[1] == 12 and a.strides[0] % 4 == 0 and a.strides[0] >= 12 * a.shape[1]):
            ptr = ffi.cast("float*", a.ctypes.data)
            return cls._make(lambda h: lib.swcl_metrics_from_frames_strided(ptr, a.shape[0], a.shape[1],
                                                                            a.strides[0] // 4, float(dt), h))
        a = np.ascontiguousarray(a, dtype=np.float32)
        if a.ndim != 3 or a.shape[2] != 3:
            raise ValueError(f"from_frames: expected shape (frames, agents, 3), got {a.shape}")
        ptr = ffi.from_buffer("float[]", a) if a.size else ffi.NULL
        return cls._make(lambda h: lib.swcl_metrics_from_frames(ptr, a.shape[0], a.shape[1], float(dt), h))

    @classmethod
    def attach(cls, swarm, sample_dt: float) -> "Metrics":
        """Metrics of a running swarm, computed on the device and streamed into
        fixed-size histograms: step the swarm K steps, ``sample()``, repeat;
        ``sample_dt`` is K times the swarm's dt.  Keeps the swarm alive.  On
        a swarm of several worlds every world is measured on its own (read
        them with ``world(k)``)."""
        m = cls._make(lambda h: lib.swcl_metrics_attach(swarm._h, float(sample_dt), h))
        m._swarm = swarm
        return m

    @classmethod
    def merge(cls, parts) -> "Metrics":
        """Several metrics pooled as one sample set (swcl_metrics_merge): the
        parts' samples one after the other, nearest neighbours each part's
        own, e.g. one model's runs under several seeds scored as one
        distribution.  The parts stay open and unchanged; all must share a
        frame time."""
        parts = list(parts)
        if not parts or not all(isinstance(m, Metrics) for m in parts):
            raise TypeError("merge: a non-empty sequence of swarmcl.Metrics")
        handles = ffi.new("swcl_metrics[]", [m._h for m in parts])
        return cls._make(lambda h: lib.swcl_metrics_merge(handles, len(parts), h))

    def world(self, k: int) -> "Metrics":
        """World k's metrics sampled so far (Metrics.attach only), as metrics
        of their own that do not change when sampling goes on: bitwise those
        of the world's swarm run alone."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= int(k) < 2**32:
            raise ValueError(f"world: an integer >= 0, got {k!r}")
        return self._make(lambda h: lib.swcl_metrics_world(self._h, int(k), h))

    def sample(self) -> None:
        """Samples the attached swarm's positions now (Metrics.attach only)."""
        check(lib.swcl_metrics_sample(self._h))

    @property
    def frame_time(self) -> float:
        """Seconds between the frames the samples came from."""
        out = ffi.new("double*")
        check(lib.swcl_metrics_frame_time(self._h, out))
        return float(out[0])

    def info(self, metric) -> dict:
        """count, mean, sigma, median and MAD (unscaled) of one metric's
        samples, in the metric's unit (METRIC_UNITS)."""
        out = ffi.new("swcl_metric_info*")
        out.struct_size = ffi.sizeof("swcl_metric_info")
        check(lib.swcl_metrics_get_info(self._h, _metric_index(metric), out))
        return {"count": int(out.count), "mean": float(out.mean), "sigma": float(out.sigma),
                "median": float(out.median), "mad": float(out.mad)}

    def pdf(self, metric, bins: int = 50, half_width: float = 4.0, robust: bool = False) -> np.ndarray:
        """The discrete PDF Q (bins,) of the z-scored samples over
        [-half_width, half_width] sigma (Step 3 of §3.1); ``robust``:
        z-scored with the median and 1.4826 MAD instead of mean and sigma."""
        q = np.empty(int(bins), dtype=np.float64)
        check(lib.swcl_metrics_pdf(self._h, _metric_index(metric), _pdf_options(bins, half_width, robust),
                                   ffi.from_buffer("double[]", q), q.size))
        return q


class Tracks:
    """Gap-free track segments in seconds and metres as the metrics see
    them (read_tracks): ``segments`` a list of (times, positions (n, 3)),
    ``insects`` the insect of each segment, ``frame_time`` in seconds."""

    def __init__(self, segments, insects, frame_time: float):
        self.segments, self.insects, self.frame_time = list(segments), np.asarray(insects), float(frame_time)

    def __len__(self) -> int:
        return len(self.segments)

    def time_range(self) -> Tuple[float, float]:
        return (min(float(t[0]) for t, _ in self.segments), max(float(t[-1]) for t, _ in self.segments))

    def metrics(self) -> Metrics:
        """The seven metrics of these segments (as taken, nothing scaled,
        smoothed or cut again)."""
        return Metrics.from_tracks(self.segments, frame_time=self.frame_time, unit_scale=1.0, smoothing=0)


def read_tracks(path, window: Tuple[float, float] = (0.0, 1.0), **options) -> Tracks:
    """The tracks of a CSV file (options as for Metrics.from_csv) split,
    smoothed, scaled and cut to ``window`` exactly as Metrics.from_csv takes
    them, so a caller can lay them out again (a bootstrap, a subset)."""
    d, _keep = _track_desc("read_tracks", options, _METRIC_TRACK_OPTIONS)
    lo, hi = window
    p = os.fsencode(path)
    nseg, nsam, ft = ffi.new("size_t*"), ffi.new("size_t*"), ffi.new("double*")
    check(lib.swcl_tracks_read_csv(p, d, float(lo), float(hi), ffi.NULL, ffi.NULL, 0, ffi.NULL, ffi.NULL, 0,
                                   nseg, nsam, ft))
    counts = np.zeros(nseg[0], dtype=np.uint32)
    insects = np.zeros(nseg[0], dtype=np.uint32)
    times = np.zeros(nsam[0], dtype=np.float64)
    xyz = np.zeros((nsam[0], 3), dtype=np.float32)
    check(lib.swcl_tracks_read_csv(p, d, float(lo), float(hi), ffi.from_buffer("uint32_t[]", counts),
                                   ffi.from_buffer("uint32_t[]", insects), len(counts),
                                   ffi.from_buffer("double[]", times), ffi.from_buffer("float[]", xyz), len(times),
                                   nseg, nsam, ft))
    ends = np.cumsum(counts)
    segments = [(times[e - c:e], xyz[e - c:e]) for c, e in zip(counts, ends)]
    return Tracks(segments, insects, ft[0])


def distances(real: Metrics, sim: Metrics, bins: int = 50, half_width: float = 4.0,
              robust: bool = False) -> np.ndarray:
    """E_phi = sum_i |Q_real,i - Q_sim,i| of every metric (Eq. 2), shape (7,);
    ``robust``: each side z-scored with its median and 1.4826 MAD."""
    e = np.empty(len(METRICS), dtype=np.float64)
    check(lib.swcl_metrics_distances(real._h, sim._h, _pdf_options(bins, half_width, robust),
                                     ffi.from_buffer("double[]", e), e.size))
    return e


def wasserstein(real: Metrics, sim: Metrics) -> dict:
    """The Wasserstein-1 distance of every metric in its own unit
    (METRIC_UNITS): {name: distance}, None for a metric without samples on a
    side (e.g. nearest distances with one insect in view).  Unlike E_phi it
    sees scale: a swarm twice as fast is its mean speed away."""
    out = {}
    d = ffi.new("double*")
    for k, name in enumerate(METRICS):
        status = lib.swcl_metrics_wasserstein(real._h, sim._h, k, d)
        if status == lib.SWCL_OK:
            out[name] = float(d[0])
        elif status == lib.SWCL_ERROR_INVALID_ARGUMENT and real.info(k)["count"] * sim.info(k)["count"] == 0:
            out[name] = None
        else:
            check(status)
    return out


def score(distances_, weights: Optional[Sequence[float]] = None, p1: Optional[Sequence[float]] = None,
          p2: Optional[Sequence[float]] = None) -> float:
    """E = 1 - sum w (E_phi - p1) / p2 (Eq. 3 and 1); defaults w = 1/7, p1 = 0, p2 = 1."""
    e = np.ascontiguousarray(distances_, dtype=np.float64)
    if e.shape != (len(METRICS),):
        raise ValueError(f"distances: expected shape (7,), got {e.shape}")
    w = ffi.new("swcl_score_weights*", lib.swcl_score_weights_default())
    for name, values in (("w", weights), ("p1", p1), ("p2", p2)):
        if values is not None:
            v = np.asarray(values, dtype=np.float64)
            if v.shape != (len(METRICS),):
                raise ValueError(f"{name}: expected 7 values, got shape {v.shape}")
            for k in range(len(METRICS)):
                getattr(w, name)[k] = float(v[k])
    out = ffi.new("double*")
    check(lib.swcl_score(ffi.from_buffer("double[]", e), e.size, w, out))
    return float(out[0])


def entropy_weights(x) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Entropy weights (Eq. 4) of an energy-term matrix x (models, terms):
    (w, p1, p2), each (terms,)."""
    a = np.ascontiguousarray(x, dtype=np.float64)
    if a.ndim != 2:
        raise ValueError(f"x: expected a 2-D array (models, terms), got shape {a.shape}")
    m, n = a.shape
    w, p1, p2 = (np.empty(n, dtype=np.float64) for _ in range(3))
    check(lib.swcl_entropy_weights(ffi.from_buffer("double[]", a) if a.size else ffi.NULL, m, n,
                                   ffi.from_buffer("double[]", w), ffi.from_buffer("double[]", p1),
                                   ffi.from_buffer("double[]", p2)))
    return w, p1, p2


def _simulate_frames(scenario: Scenario, context: Context, steps: int, every: int, warmup: int) -> np.ndarray:
    """Positions (frames, agents, 3) every `every` steps after `warmup` steps."""
    with scenario.create_swarm(context) as swarm:
        done = 0
        while done < warmup:
            k = min(every, warmup - done)
            swarm.step(k)
            done += k
        frames = [swarm.read_positions()]
        for _ in range(steps // every):
            swarm.step(every)
            frames.append(swarm.read_positions())
    return np.stack(frames)


def _simulate_runs(scenario: Scenario, context: Context, steps: int, every: int, warmup: int, seeds) -> np.ndarray:
    """Positions (frames, runs, agents, 3) of the scenario run with each of
    `seeds`, as the worlds of one swarm (world k: the scenario alone with
    seed seeds[k])."""
    runs, n, sampled = len(seeds), scenario.info["agents"], steps // every
    with scenario.create_world_swarm(context, runs, seeds) as swarm:
        done = 0
        while done < warmup:
            k = min(every, warmup - done)
            swarm.step(k)
            done += k
        frames = np.empty((sampled + 1, runs, n, 3), dtype=np.float32)
        shape = (n, 3) if runs == 1 else (runs, n, 3)  # read_positions' shape
        swarm.read_positions(out=frames[0].reshape(shape))
        swarm.step_frames(sampled, every, out=frames[1:].reshape((sampled,) + shape))
    return frames


def evaluate(scenario, tracks, *, steps: Optional[int] = None, every: Optional[int] = None, warmup: int = 0,
             bins: int = 50, half_width: float = 4.0, robust: bool = False, runs: int = 1,
             seed: Optional[int] = None,
             weights: Optional[Sequence[float]] = None,
             p1: Optional[Sequence[float]] = None, p2: Optional[Sequence[float]] = None,
             context: Optional[Context] = None, out_dir=None, plots: bool = True,
             floor: Optional[Tuple[Metrics, Metrics]] = None) -> dict:
    """Runs ``scenario`` (a path, or a Scenario) and scores it against
    ``tracks`` (a Metrics, e.g. Metrics.from_csv(...)), as ``swarmcl
    evaluate`` does: samples every ``every`` steps (default: the tracks' frame
    time over the scenario's dt) after ``warmup`` steps; ``robust``: the PDFs
    z-scored with median and MAD (``--robust``).  ``runs``, ``seed``
    (``--runs``, ``--seed``): that many runs, simulation seeds seed, seed + 1,
    ... (default: the scenario's seed on), as the worlds of one swarm, their
    samples pooled (Metrics.merge); e.g. a fitted scenario on seeds its fit
    did not use.  ``floor``: the tracks'
    two halves (Metrics of each), scored against each other into
    ``data_floor`` as the CLI does from its file.  Returns the same
    dictionary the CLI writes; with ``out_dir`` writes ``evaluation.json``
    there, and ``evaluation.png`` (the seven PDFs, real vs simulated) when
    ``plots`` and matplotlib is installed."""
    scn = scenario if isinstance(scenario, Scenario) else Scenario.load(scenario)
    if not isinstance(tracks, Metrics):
        raise TypeError(f"tracks must be a swarmcl.Metrics (Metrics.from_csv), got {type(tracks).__name__}")
    info = scn.info
    steps = info["steps"] if steps is None else int(steps)
    every = max(1, round(tracks.frame_time / info["dt"])) if every is None else int(every)
    if steps < 1 or every < 1 or warmup < 0:
        raise ValueError("steps and every must be >= 1, warmup >= 0")
    if info["agents"] < 2:
        raise ValueError("evaluate: the scenario needs at least two agents (nearest distances)")
    if isinstance(runs, bool) or not isinstance(runs, (int, np.integer)) or runs < 1 or \
            (seed is not None and (isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or
                                   not 0 <= seed < 2**64)):
        raise ValueError(f"evaluate: runs must be an integer >= 1 and seed None or an integer >= 0, "
                         f"got runs={runs!r}, seed={seed!r}")
    first_seed = info["seed"] if seed is None else int(seed)
    start = time.perf_counter()
    own = context is None
    ctx = Context() if own else context
    sample_dt = every * info["dt"]
    try:
        if runs == 1 and seed is None:
            sim = Metrics.from_frames(_simulate_frames(scn, ctx, steps, every, int(warmup)), sample_dt)
        else:  # as `swarmcl evaluate --runs --seed`: worlds, each run's frames measured where they lie, pooled
            frames = _simulate_runs(scn, ctx, steps, every, int(warmup), [first_seed + k for k in range(runs)])
            parts = [Metrics.from_frames(frames[:, k], sample_dt) for k in range(runs)]
            try:
                sim = Metrics.merge(parts)  # of one run: a copy of its samples
            finally:
                for p in parts:
                    p.close()
    finally:
        if own:
            ctx.close()
    with sim:
        e = distances(tracks, sim, bins, half_width, robust)
        w1 = wasserstein(tracks, sim)
        w = ffi.new("swcl_score_weights*", lib.swcl_score_weights_default())
        result = {
            "scenario": info["name"], "agents": info["agents"], "dt": info["dt"], "warmup_steps": int(warmup),
            "steps": steps, "every": every, "frames": steps // every + 1, "runs": int(runs), "first_seed": first_seed,
            "tracks_frame_time": tracks.frame_time, "pdf": {"bins": int(bins), "half_width": float(half_width),
                                                       "standardise": "median_mad" if robust else "mean_sigma"},
            "weights": {"w": list(weights) if weights is not None else list(w.w),
                        "p1": list(p1) if p1 is not None else list(w.p1),
                        "p2": list(p2) if p2 is not None else list(w.p2)},
            "metrics": {}, "score": score(e, weights, p1, p2),
        }
        for k, name in enumerate(METRICS):
            result["metrics"][name] = {
                "distance": float(e[k]), "wasserstein": w1[name], "unit": METRIC_UNITS[k],
                "real": dict(tracks.info(k), pdf=tracks.pdf(k, bins, half_width, robust).tolist()),
                "sim": dict(sim.info(k), pdf=sim.pdf(k, bins, half_width, robust).tolist()),
            }
    if floor is not None:
        ef = distances(floor[0], floor[1], bins, half_width, robust)
        result["data_floor"] = {"score": score(ef, weights, p1, p2), "distances": ef.tolist()}
    result["seconds"] = time.perf_counter() - start
    if out_dir is not None:
        os.makedirs(out_dir, exist_ok=True)
        tmp = os.path.join(out_dir, ".evaluation.json.tmp")
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(result, f, indent=2)
            f.write("\n")
        os.replace(tmp, os.path.join(out_dir, "evaluation.json"))
        if plots:
            try:
                plot_pdfs(result, os.path.join(out_dir, "evaluation.png"))
            except ImportError:
                pass  # matplotlib is optional (swarmcl[plot])
    return result


def plot_pdfs(result: dict, path) -> None:
    """The seven PDFs, real vs simulated, of an evaluation result (the
    dictionary evaluate() returns or the JSON ``swarmcl evaluate`` writes),
    as one PNG.  Needs matplotlib."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    bins = result["pdf"]["bins"]
    h = result["pdf"]["half_width"]
    centres = -h + (np.arange(bins) + 0.5) * (2 * h / bins)
    fig, axes = plt.subplots(2, 4, figsize=(14, 6), constrained_layout=True)
    for ax, name in zip(axes.flat, METRICS):
        m = result["metrics"][name]
        ax.step(centres, m["real"]["pdf"], where="mid", label="real", color="k")
        ax.step(centres, m["sim"]["pdf"], where="mid", label="simulated", color="tab:orange")
        ax.set_title(f"{name}  E={m['distance']:.3f}", fontsize=9)
        ax.set_xlabel("z-score")
    axes.flat[0].legend(fontsize=8)
    ax = axes.flat[-1]
    ax.axis("off")
    ax.text(0.0, 0.5, f"{result.get('scenario', '')}\nscore E = {result['score']:.4f}", fontsize=11)
    tmp = str(path) + ".tmp.png"
    fig.savefig(tmp, dpi=80)
    plt.close(fig)
    os.replace(tmp, path)


def _main(argv=None) -> int:
    """python -m swarmcl.evaluation plot EVALUATION.json [OUT.png]: draws the PDFs of a CLI result."""
    import sys
    args = sys.argv[1:] if argv is None else argv
    if len(args) not in (2, 3) or args[0] != "plot":
        print("usage: python -m swarmcl.evaluation plot EVALUATION.json [OUT.png]", file=sys.stderr)
        return 2
    with open(args[1], encoding="utf-8") as f:
        result = json.load(f)
    out = args[2] if len(args) == 3 else os.path.splitext(args[1])[0] + ".png"
    plot_pdfs(result, out)
    print(out)
    return 0


if __name__ == "__main__":
    raise SystemExit(_main())

"""How sure a fit is (issue 26, item 7): every fitted parameter with its
spread over fits of different optimiser seeds and over fits to bootstrap
resamples of the tracks, so a user sees which parameters the data pins down
and which it leaves loose.

The resample is a block bootstrap in time: the recording (the window's
tracks) is cut into ``blocks`` equal spans of time, ``blocks`` spans are
drawn with replacement and laid end to end, far enough apart in time that no
difference crosses from one to the next.  Resampling insects instead would
put an insect beside its own copy in a frame (nearest distance 0), which the
neighbour metrics d and eta cannot take; a span keeps every insect in view
with its neighbours, and which insects and which moments the fit sees varies
as a resample of the data should.
"""
from __future__ import annotations

import json

import numpy as np

from .evaluation import Tracks
from .fitting import fit, load_ranges

#: A parameter counts as pinned down when both its spreads (sample standard
#: deviation over seeds and over resamples) are below this fraction of its
#: range's width.
PINNED_FRACTION = 0.1


def block_resample(tracks: Tracks, blocks: int, rng: np.random.Generator) -> Tracks:
    """``blocks`` spans of time drawn with replacement from ``tracks`` (cut
    into ``blocks`` equal spans), laid end to end with a gap of 100 frames
    between them; segments left with fewer than 3 samples in a span are
    dropped, as the loader drops them."""
    if int(blocks) < 1:
        raise ValueError(f"blocks: an integer >= 1, got {blocks!r}")
    if len(tracks) == 0:
        raise ValueError("block_resample: no track segments")
    t0, t1 = tracks.time_range()
    span = (t1 - t0) / blocks
    edges = t0 + span * np.arange(blocks + 1)
    edges[-1] = np.nextafter(t1, np.inf)  # the last sample falls in the last span
    stride = (t1 - t0) + 100.0 * tracks.frame_time
    segments, insects = [], []
    for slot, b in enumerate(rng.integers(0, blocks, size=blocks)):
        lo, hi = edges[b], edges[b + 1]
        for (t, p), insect in zip(tracks.segments, tracks.insects):
            keep = (t >= lo) & (t < hi)
            if np.count_nonzero(keep) >= 3:
                segments.append((t[keep] - lo + slot * stride, p[keep]))
                insects.append(insect)
    if not segments:
        raise ValueError("block_resample: no span holds a segment of 3 samples; use fewer blocks")
    return Tracks(segments, insects, tracks.frame_time)


def _sample_sd(x) -> float:
    return float(np.std(x, ddof=1)) if len(x) > 1 else 0.0


def fit_spread(scenario, tracks: Tracks, ranges, *, fits: int = 3, bootstrap: int = 5, blocks: int = 10,
               seed: int = 1, progress=None, **fit_options) -> dict:
    """Fits ``scenario`` to ``tracks`` (read_tracks) ``fits`` times with
    optimiser seeds seed, seed + 1, ..., and once to each of ``bootstrap``
    block resamples of the tracks (block_resample; optimiser seed ``seed``),
    with ``fit_options`` as for fit().  Returns the fits' results and, per
    parameter: its best value in every fit, the mean and sample standard
    deviation over seeds and over resamples, each deviation as a fraction of
    the range, and ``pinned`` (both fractions below PINNED_FRACTION)."""
    if int(fits) < 1 or int(bootstrap) < 0 or (int(fits) < 2 and int(bootstrap) < 2):
        raise ValueError("fit_spread: fits >= 1, bootstrap >= 0, and at least 2 fits of one kind to spread")
    if "comm" in fit_options:
        raise ValueError("fit_spread runs in one process (fit each on its own ranks with fit())")
    report = progress or (lambda entry: None)
    params = load_ranges(ranges, scenario if isinstance(scenario, dict) else _load(scenario))
    by_seed, by_resample = [], []
    with tracks.metrics() as real:
        for k in range(int(fits)):
            by_seed.append(fit(scenario, real, ranges, seed=seed + k, **fit_options))
            report({"kind": "seed", "index": k, "best_score": by_seed[-1]["best_score"]})
    rng = np.random.default_rng(seed)
    for b in range(int(bootstrap)):
        with block_resample(tracks, blocks, rng).metrics() as real:
            by_resample.append(fit(scenario, real, ranges, seed=seed, **fit_options))
        report({"kind": "bootstrap", "index": b, "best_score": by_resample[-1]["best_score"]})
    out = {}
    for p in params:
        s = [r["best"][p.path] for r in by_seed]
        b = [r["best"][p.path] for r in by_resample]
        width = p.high - p.low
        sd_s, sd_b = _sample_sd(s), _sample_sd(b)
        frac_s = sd_s / width if width > 0 else 0.0
        frac_b = sd_b / width if width > 0 else 0.0
        spreads = ([frac_s] if len(s) > 1 else []) + ([frac_b] if len(b) > 1 else [])
        out[p.path] = {
            "low": p.low, "high": p.high,
            "seeds": s, "seed_mean": float(np.mean(s)), "seed_sd": sd_s, "seed_sd_of_range": frac_s,
            "bootstrap": b, "bootstrap_mean": float(np.mean(b)) if b else None,
            "bootstrap_sd": sd_b if b else None, "bootstrap_sd_of_range": frac_b if b else None,
            "pinned": bool(all(f < PINNED_FRACTION for f in spreads)),
        }
    return {"parameters": out, "fits": int(fits), "bootstrap": int(bootstrap), "blocks": int(blocks),
            "seed": int(seed), "pinned_fraction": PINNED_FRACTION,
            "fits_by_seed": by_seed, "fits_by_resample": by_resample}


def _load(path) -> dict:
    with open(path, encoding="utf-8") as f:
        return json.load(f)

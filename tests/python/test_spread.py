"""How sure a fit is (issue 26, item 7): tracks read as the metrics see
them, block resamples of them in time, and every fitted parameter's spread
over optimiser seeds and over resamples."""
import json

import numpy as np
import pytest

import swarmcl
from swarmcl.spread import block_resample

pytest.importorskip("cma")

SCENARIO = {
    "name": "spread_tiny", "seed": 9, "dt": 0.02, "steps": 30,
    "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
    "agents": {"count": 12, "velocity": [0.1, 0, 0],
               "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
    "model": {"type": "field", "noise": {"type": "curl", "scale": 0.5, "gain": 0.6, "seed": 1, "domain_walls": True},
              "goal": {"center": [1, 1, 1.5], "speed": 0.9}, "min_distance": 0.02},
    "output": {"dir": "results", "formats": ["npy"], "every": 5},
}
RANGES = {"model.noise.gain": [0.05, 1.0], "model.goal.speed": [0.1, 1.5]}


@pytest.fixture(scope="module")
def track_csv(tmp_path_factory):
    """The scenario's run written as a track CSV (cm, ';' separated): 12
    insects x 61 frames 0.02 s apart."""
    with swarmcl.Context() as c, swarmcl.Scenario.parse(json.dumps(SCENARIO)).create_swarm(c) as s:
        frames = [s.read_positions()]
        for _ in range(60):
            s.step(1)
            frames.append(s.read_positions())
    path = tmp_path_factory.mktemp("spread") / "tracks.csv"
    with open(path, "w", encoding="utf-8") as f:
        f.write("insect;t;x;y;z\n")
        for k, p in enumerate(frames):
            for i, q in enumerate(p):
                f.write(f"m{i};{k * 0.02:.4f};{q[0] * 100:.6f};{q[1] * 100:.6f};{q[2] * 100:.6f}\n")
    return str(path)


OPTIONS = {"columns": "insect,t,x,y,z", "delimiter": ";", "unit_scale": 0.01}


def test_read_tracks_gives_the_samples_the_metrics_take(track_csv):
    tracks = swarmcl.read_tracks(track_csv, window=(0.0, 0.5), **OPTIONS)
    assert len(tracks) == 12 and sorted(set(tracks.insects.tolist())) == list(range(12))
    assert tracks.frame_time == pytest.approx(0.02)
    t, p = tracks.segments[0]
    assert p.shape == (len(t), 3) and np.all(np.diff(t) > 0)
    assert np.all(np.abs(p) < 3.0)  # metres, not centimetres
    with tracks.metrics() as a, swarmcl.Metrics.from_csv(track_csv, window=(0.0, 0.5), **OPTIONS) as b:
        for name in swarmcl.METRICS:
            ia, ib = a.info(name), b.info(name)
            assert ia["count"] == ib["count"] > 0, name
            # xyz passes through float: the same samples to float rounding.
            assert ia["mean"] == pytest.approx(ib["mean"], rel=1e-3), name
    with pytest.raises(TypeError, match="unknown option colums"):
        swarmcl.read_tracks(track_csv, colums="a,b,c,d,e")
    with pytest.raises(swarmcl.SwarmclError):
        swarmcl.read_tracks(track_csv + ".missing", **OPTIONS)


def test_block_resamples_keep_whole_spans_apart_in_time(track_csv):
    tracks = swarmcl.read_tracks(track_csv, **OPTIONS)
    # One block: every sample once, times shifted to start at 0.
    one = block_resample(tracks, 1, np.random.default_rng(0))
    assert sum(len(t) for t, _ in one.segments) == sum(len(t) for t, _ in tracks.segments)
    with one.metrics() as a, tracks.metrics() as b:
        assert a.info("speed")["count"] == b.info("speed")["count"]
        assert a.info("nearest_distance")["mean"] == pytest.approx(b.info("nearest_distance")["mean"], rel=1e-6)
    # Four blocks: spans far apart (no difference crosses them), drawn with
    # replacement, reproducible for a seed.
    a = block_resample(tracks, 4, np.random.default_rng(5))
    b = block_resample(tracks, 4, np.random.default_rng(5))
    assert all(np.array_equal(x[0], y[0]) for x, y in zip(a.segments, b.segments))
    starts = sorted({round(float(t[0]), 6) for t, _ in a.segments})
    assert len(starts) >= 2 and np.diff(starts).min() > 1.0
    with a.metrics() as m:
        assert m.info("nearest_distance")["count"] > 0 and m.info("nearest_distance")["mean"] > 0
    with pytest.raises(ValueError, match="blocks"):
        block_resample(tracks, 0, np.random.default_rng(0))


def test_every_parameter_gets_its_spread_over_seeds_and_resamples(track_csv, ctx):
    tracks = swarmcl.read_tracks(track_csv, **OPTIONS)
    r = swarmcl.fit_spread(SCENARIO, tracks, RANGES, fits=2, bootstrap=2, blocks=3, seed=4, generations=2,
                           population=4, steps=30, context=ctx)
    assert set(r["parameters"]) == set(RANGES)
    assert len(r["fits_by_seed"]) == 2 and len(r["fits_by_resample"]) == 2
    for path, q in r["parameters"].items():
        lo, hi = RANGES[path]
        assert q["seeds"] == [f["best"][path] for f in r["fits_by_seed"]]
        assert q["bootstrap"] == [f["best"][path] for f in r["fits_by_resample"]]
        assert all(lo <= v <= hi for v in q["seeds"] + q["bootstrap"])
        assert q["seed_sd"] == pytest.approx(np.std(q["seeds"], ddof=1))
        assert q["bootstrap_sd_of_range"] == pytest.approx(np.std(q["bootstrap"], ddof=1) / (hi - lo))
        assert q["pinned"] == (q["seed_sd_of_range"] < 0.1 and q["bootstrap_sd_of_range"] < 0.1)
    # The optimiser seeds differ, and the resamples are other data.
    assert r["fits_by_seed"][0]["seed"] == 4 and r["fits_by_seed"][1]["seed"] == 5
    assert r["fits_by_resample"][0]["best_score"] != r["fits_by_seed"][0]["best_score"]
    for bad in ({"fits": 1, "bootstrap": 1}, {"fits": 0}, {"bootstrap": -1}):
        with pytest.raises(ValueError, match="fit_spread"):
            swarmcl.fit_spread(SCENARIO, tracks, RANGES, **bad)


def test_the_cli_reports_each_parameters_spread(track_csv, tmp_path):
    scenario, ranges, out = tmp_path / "s.json", tmp_path / "r.json", tmp_path / "spread.json"
    scenario.write_text(json.dumps(SCENARIO))
    ranges.write_text(json.dumps(RANGES))
    args = [str(scenario), "--ranges", str(ranges), "--tracks", track_csv, "--columns", "insect,t,x,y,z",
            "--delimiter", ";", "--unit-scale", "0.01", "--generations", "2", "--population", "4",
            "--out", str(out), "--spread", "2,2", "--blocks", "3"]
    assert swarmcl.fitting.main(args) == 0
    r = json.loads(out.read_text())
    assert set(r["parameters"]) == set(RANGES) and r["fits"] == 2 and r["bootstrap"] == 2
    assert swarmcl.fitting.main(args[:-4] + ["--spread", "2"]) == 1  # not FITS,RESAMPLES

"""The evaluation against real insects from Python (issue 14): metric sets,
PDFs, distances, scores, entropy weights, and evaluate() end to end."""
import json
import os
import subprocess

import numpy as np
import pytest

import swarmcl

TINY = """{
  "name": "tiny_eval", "seed": 9, "dt": 0.02, "steps": 40,
  "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
  "agents": {"count": 20, "velocity": [0.1, 0, 0],
             "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
  "model": {"type": "field", "noise": {"type": "curl", "scale": 0.5, "gain": 0.2, "seed": 1, "domain_walls": true},
            "goal": {"center": [1, 1, 1.5], "speed": 0.5}, "min_distance": 0.02},
  "output": {"dir": "results", "formats": ["npy"], "every": 5}
}"""


def random_walk(rng, frames, agents, step=0.01):
    p = rng.uniform(-1, 1, size=(1, agents, 3)) + np.cumsum(rng.normal(0, step, size=(frames, agents, 3)), axis=0)
    return p.astype(np.float32)


def test_a_set_against_itself_has_zero_distance_and_score_one(rng):
    frames = random_walk(rng, 30, 12)
    with swarmcl.Metrics.from_frames(frames, 0.05) as a, swarmcl.Metrics.from_frames(frames, 0.05) as b:
        e = swarmcl.distances(a, b)
        assert e.shape == (7,) and np.all(e == 0.0)
        assert swarmcl.score(e) == 1.0
        assert a.frame_time == 0.05
        info = a.info("speed")
        assert info["count"] == 29 * 12
        q = a.pdf("nearest_distance", bins=20, half_width=3.0)
        assert q.shape == (20,)
        assert abs(q.sum() * 6.0 / 20 - 1.0) < 1e-12  # a density: integrates to 1


def test_wasserstein_sees_the_scale_that_z_scores_do_not(rng):
    # The same walk twice as large: every z-scored PDF is the same (E_phi 0),
    # while W1 of the speeds is their mean and of the distances the mean
    # nearest distance, in m/s and m.
    frames = random_walk(rng, 40, 15)
    with swarmcl.Metrics.from_frames(frames, 0.05) as a, swarmcl.Metrics.from_frames(2 * frames, 0.05) as b:
        assert np.all(swarmcl.distances(a, b) < 1e-9)
        w = swarmcl.wasserstein(a, b)
        assert set(w) == set(swarmcl.METRICS)
        assert w["speed"] == pytest.approx(a.info("speed")["mean"], rel=1e-5)
        assert w["nearest_distance"] == pytest.approx(a.info("nearest_distance")["mean"], rel=1e-5)
        assert w["angular_velocity"] < 1e-9  # turning does not change with size
        assert dict(zip(swarmcl.METRICS, swarmcl.METRIC_UNITS))["speed"] == "m/s"
        info = a.info("speed")
        assert info["median"] > 0 and info["mad"] > 0
        assert b.info("speed")["median"] == pytest.approx(2 * info["median"], rel=1e-5)
        # The robust standardisation: a distinct PDF, still zero against itself.
        assert not np.array_equal(a.pdf("speed", robust=True), a.pdf("speed"))
        assert np.all(swarmcl.distances(a, a, robust=True) == 0.0)
    # One agent: no nearest distances, so no W1 for them (None), the rest there.
    with swarmcl.Metrics.from_frames(frames[:, :1], 0.05) as one, swarmcl.Metrics.from_frames(frames, 0.05) as a:
        w = swarmcl.wasserstein(a, one)
        assert w["nearest_distance"] is None and w["velocity_difference"] is None
        assert w["speed"] is not None and np.isfinite(w["speed"])


def test_tracks_and_windows(rng):
    tracks = [(np.arange(100) * 0.01, random_walk(rng, 100, 1)[:, 0, :]) for _ in range(5)]
    with swarmcl.Metrics.from_tracks(tracks, frame_time=0.01) as whole, \
            swarmcl.Metrics.from_tracks(tracks, window=(0, 0.5), frame_time=0.01) as first:
        assert whole.info(0)["count"] == 5 * 99
        assert 0 < first.info(0)["count"] < whole.info(0)["count"]
    with pytest.raises(swarmcl.InvalidArgumentError, match="from < to"):
        swarmcl.Metrics.from_tracks(tracks, window=(0.8, 0.2), frame_time=0.01)


def test_entropy_weights_match_equation_4():
    x = np.array([[0.0, 5.0], [1.0, 5.0], [2.0, 5.0]])
    w, p1, p2 = swarmcl.entropy_weights(x)
    assert w.tolist() == [1.0, 0.0]
    assert p1.tolist() == [0.0, 5.0] and p2[0] == 2.0
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.entropy_weights(np.zeros((1, 3)))


def test_bad_arguments_raise_clear_errors(rng):
    with swarmcl.Metrics.from_frames(random_walk(rng, 5, 3), 0.1) as m:
        with pytest.raises(ValueError, match="metric"):
            m.info("wingbeat")
        with pytest.raises(swarmcl.InvalidArgumentError):
            m.pdf(0, bins=0)
    with pytest.raises(ValueError, match="frames, agents, 3"):
        swarmcl.Metrics.from_frames(np.zeros((4, 3)), 0.1)
    with pytest.raises(swarmcl.InvalidArgumentError, match="dt"):
        swarmcl.Metrics.from_frames(np.zeros((4, 2, 3)), 0.0)
    with pytest.raises(ValueError):
        swarmcl.score(np.zeros(6))


def test_evaluate_writes_json_and_the_pdf_plot_and_is_deterministic(tmp_path, rng, ctx):
    scenario = tmp_path / "tiny.json"
    scenario.write_text(TINY)
    tracks = [(np.arange(60) * 0.02, random_walk(rng, 60, 1, 0.02)[:, 0, :]) for _ in range(6)]
    with swarmcl.Metrics.from_tracks(tracks, frame_time=0.02) as real:
        a = swarmcl.evaluate(str(scenario), real, warmup=5, out_dir=tmp_path / "out", context=ctx)
        b = swarmcl.evaluate(str(scenario), real, warmup=5, context=ctx)
    assert a["every"] == 1 and a["frames"] == 41
    a.pop("seconds"), b.pop("seconds")
    assert a == b
    assert set(a["metrics"]) == set(swarmcl.METRICS)
    assert np.isfinite(a["score"]) and a["score"] < 1.0
    written = json.loads((tmp_path / "out" / "evaluation.json").read_text())
    written.pop("seconds")
    assert written == json.loads(json.dumps(a))
    assert "data_floor" not in a
    # The data's floor: the tracks' halves given, scored against each other.
    with swarmcl.Metrics.from_tracks(tracks, window=(0, 0.5), frame_time=0.02) as h1, \
            swarmcl.Metrics.from_tracks(tracks, window=(0.5, 1), frame_time=0.02) as h2, \
            swarmcl.Metrics.from_tracks(tracks, frame_time=0.02) as real:
        c = swarmcl.evaluate(str(scenario), real, warmup=5, context=ctx, floor=(h1, h2), plots=False)
        assert c["data_floor"]["score"] == swarmcl.score(swarmcl.distances(h1, h2))
        assert c["score"] == a["score"]
    pytest.importorskip("matplotlib")
    png = (tmp_path / "out" / "evaluation.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_evaluate_pools_runs_from_a_given_seed(tmp_path, rng, ctx):
    # runs=N, seed=S: the scenario run with seeds S..S+N-1 (worlds of one
    # swarm), samples pooled; one run on the scenario's own seed (9) is its
    # plain run, and the pooled result is the merge of the runs alone.
    tracks = [(np.arange(60) * 0.02, random_walk(rng, 60, 1, 0.02)[:, 0, :]) for _ in range(6)]
    scn = swarmcl.Scenario.parse(TINY)
    with swarmcl.Metrics.from_tracks(tracks, frame_time=0.02) as real:
        own = swarmcl.evaluate(scn, real, warmup=5, context=ctx, plots=False)
        nine = swarmcl.evaluate(scn, real, warmup=5, context=ctx, plots=False, seed=9)
        three = swarmcl.evaluate(scn, real, warmup=5, context=ctx, plots=False, runs=3, seed=11)
        assert own["runs"] == 1 and own["first_seed"] == 9 and nine["metrics"] == own["metrics"]
        assert three["runs"] == 3 and three["first_seed"] == 11 and three["frames"] == own["frames"]
        parts = []
        for s in (11, 12, 13):
            doc = json.loads(TINY)
            doc["seed"] = s
            with swarmcl.Scenario.parse(json.dumps(doc)) as one, one.create_swarm(ctx) as swarm:
                swarm.step(5)
                frames = [swarm.read_positions()]
                for _ in range(40):
                    swarm.step(1)
                    frames.append(swarm.read_positions())
            parts.append(swarmcl.Metrics.from_frames(np.stack(frames), 0.02))
        with swarmcl.Metrics.merge(parts) as pooled:
            assert three["score"] == swarmcl.score(swarmcl.distances(real, pooled))
        for p in parts:
            p.close()
        for bad in (dict(runs=0), dict(runs=1.5), dict(seed=-1), dict(seed=True)):
            with pytest.raises(ValueError, match="runs must be an integer"):
                swarmcl.evaluate(scn, real, context=ctx, plots=False, **bad)
    cli = os.environ.get("SWARMCL_CLI")
    if cli:  # the program gives the same pooled score
        (tmp_path / "tiny.json").write_text(TINY)
        rows = ["id,time,x,y,z"] + [f"{i},{t:.6f},{x:.9g},{y:.9g},{z:.9g}" for i, (ts, p) in enumerate(tracks)
                                    for t, (x, y, z) in zip(ts, p.tolist())]
        (tmp_path / "tracks.csv").write_text("\n".join(rows) + "\n")
        p = subprocess.run([cli, "evaluate", "tiny.json", "--tracks", "tracks.csv", "--warmup", "5", "--runs", "3",
                            "--seed", "11", "--out", "ev.json", "--quiet"], cwd=tmp_path, capture_output=True,
                           text=True, timeout=300)
        assert p.returncode == 0, p.stderr
        j = json.loads((tmp_path / "ev.json").read_text())
        assert j["runs"] == 3 and j["first_seed"] == 11
        assert j["score"] == pytest.approx(three["score"], abs=1e-6)  # tracks through the CSV's digits


def test_the_swarmcl_program_evaluates_and_plots_beside_its_json(tmp_path, rng):
    import os
    import subprocess
    import sys
    cli = os.environ.get("SWARMCL_CLI")
    if not cli:
        pytest.skip("SWARMCL_CLI not set (scripts/test.sh sets it)")
    pytest.importorskip("matplotlib")
    (tmp_path / "tiny.json").write_text(TINY)
    rows = ["id,time,x,y,z"]
    for i in range(5):
        p = random_walk(rng, 50, 1, 0.02)[:, 0, :]
        rows += [f"{i},{k * 0.02:.3f},{x},{y},{z}" for k, (x, y, z) in enumerate(p.tolist())]
    (tmp_path / "tracks.csv").write_text("\n".join(rows) + "\n")
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(swarmcl.__file__)))
    env = dict(os.environ, SWARMCL_PYTHON=sys.executable,
               PYTHONPATH=os.pathsep.join(x for x in (package_root, os.environ.get("PYTHONPATH", "")) if x))
    p = subprocess.run([cli, "evaluate", "tiny.json", "--tracks", "tracks.csv", "--out", "ev.json", "--plot"],
                       cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "plot: ev.png" in p.stdout
    assert (tmp_path / "ev.png").read_bytes()[:4] == b"\x89PNG"
    assert json.loads((tmp_path / "ev.json").read_text())["metrics"].keys() == set(swarmcl.METRICS)


def test_attached_metrics_stream_a_running_swarm(ctx):
    scenario = swarmcl.Scenario.parse(TINY)
    frames = []
    with scenario.create_swarm(ctx) as swarm, swarmcl.Metrics.attach(swarm, 0.04) as live:
        for f in range(30):
            if f:
                swarm.step(2)
            live.sample()
            frames.append(swarm.read_positions())
        with swarmcl.Metrics.from_frames(np.stack(frames), 0.04) as host:
            assert live.info("speed")["count"] == host.info("speed")["count"] == 29 * 20
            assert np.all(swarmcl.distances(live, host) < 0.2)
    with swarmcl.Metrics.from_frames(np.stack(frames), 0.04) as host, pytest.raises(swarmcl.InvalidArgumentError):
        host.sample()


def test_tracks_as_users_have_them(tmp_path, rng):
    # One recording written with ',', ';' and tabs; columns given as the CLI
    # gives them ("id,t,x,y,z"), as a list, or as a dict of some roles.
    frames = random_walk(rng, 25, 6)
    rows = [(i, f * 0.01, *frames[f, i]) for i in range(6) for f in range(25)]
    for name, sep in (("comma.csv", ","), ("semi.csv", ";"), ("tabs.csv", "\t")):
        lines = [sep.join(("insect", "t", "px", "py", "pz"))]
        lines += [sep.join((str(i), f"{t:.2f}", *(f"{v:.7f}" for v in p))) for i, t, *p in rows]
        (tmp_path / name).write_text("\n".join(lines) + "\n")
    ref = swarmcl.Metrics.from_csv(tmp_path / "comma.csv", columns="insect,t,px,py,pz")
    with ref:
        for file, kw in (("semi.csv", dict(delimiter=";", columns=["insect", "t", "px", "py", "pz"])),
                         ("tabs.csv", dict(delimiter="tab", columns="insect,t,px,py,pz")),
                         ("tabs.csv", dict(delimiter="\t", columns={"id": "insect", "time": "t", "x": "px",
                                                                    "y": "py", "z": "pz"}))):
            with swarmcl.Metrics.from_csv(tmp_path / file, **kw) as m:
                for k in range(len(swarmcl.METRICS)):
                    assert m.info(k) == ref.info(k), (file, k)
        with pytest.raises(TypeError, match="unknown option delimitter"):
            swarmcl.Metrics.from_csv(tmp_path / "semi.csv", delimitter=";")
        with pytest.raises(TypeError, match="unknown option k .*it takes columns, delimiter"):
            swarmcl.Metrics.from_csv(tmp_path / "semi.csv", k=3)
        with pytest.raises(ValueError, match="delimiter: one character"):
            swarmcl.Metrics.from_csv(tmp_path / "semi.csv", delimiter=";;")
        with pytest.raises(ValueError, match="columns: expected five names"):
            swarmcl.Metrics.from_csv(tmp_path / "comma.csv", columns="insect,t,px")
        # Without the delimiter the header is one column: an error naming it.
        with pytest.raises(swarmcl.SwarmclError, match="insect"):
            swarmcl.Metrics.from_csv(tmp_path / "semi.csv", columns="insect,t,px,py,pz")

"""FASTSWARM (the energy model) through the Python package: datasets, the
model dataclass with the C defaults, stimuli and keypoints, determinism and
errors."""

import numpy as np
import pytest

import swarmcl


def synthetic_tracks(n_tracks=6, samples=40, dt=0.01, seed=3):
    rng = np.random.default_rng(seed)
    tracks = []
    for _ in range(n_tracks):
        v = rng.normal(0, 0.5, 3)
        p = np.zeros(3)
        pts = []
        for _ in range(samples):
            pts.append(p.copy())
            v += rng.normal(0, 0.1, 3) - 0.05 * v
            p = p + v * dt
        tracks.append((np.arange(samples) * dt, np.array(pts)))
    return tracks


def test_defaults_come_from_c():
    m = swarmcl.EnergyModel()
    assert m.rho == 2.5
    assert m.weights == swarmcl.EnergyWeights(rep=1, oa=1, cos=0.05, dir=1, acc=1, env=0, noise=0.2, user=0)
    assert m.danger_weights.oa == 0 and m.danger_weights.cos == 0 and m.danger_weights.env == 2
    assert m.centre is None and m.keypoints is None and m.span == 1
    assert m.keep_out is True
    assert m.noise.type == swarmcl.NoiseType.CURL


def test_dataset_from_tracks_csv_and_file(tmp_path):
    tracks = synthetic_tracks()
    d = swarmcl.Dataset.from_tracks(tracks, k=100, groups=5)
    assert d.info() == {"samples": 100, "groups": 5, "frame_time": pytest.approx(0.01)}
    v, a = d.samples()
    speed = np.linalg.norm(v, axis=1)
    assert np.all(np.diff(speed) >= 0)
    csv = tmp_path / "tracks.csv"
    with open(csv, "w") as f:
        f.write("track,t,px,py,pz\n")
        for i, (t, p) in enumerate(tracks):
            for tk, pk in zip(t, p):
                f.write(f"{i},{float(tk)!r},{float(pk[0])!r},{float(pk[1])!r},{float(pk[2])!r}\n")
    d2 = swarmcl.Dataset.from_csv(csv, columns={"id": "track", "time": "t", "x": "px", "y": "py", "z": "pz"},
                                  time_format="seconds", k=100, groups=5)
    np.testing.assert_allclose(d2.samples()[0], v, atol=1e-4)
    path = tmp_path / "d.swds"
    d2.save(path)
    d3 = swarmcl.Dataset.load(path)
    np.testing.assert_array_equal(d3.samples()[0], d2.samples()[0])


def test_bad_input_raises():
    with pytest.raises(swarmcl.InvalidArgumentError, match="3 or more"):
        swarmcl.Dataset.from_tracks([(np.array([0.0, 0.01]), np.zeros((2, 3)))])
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.Dataset.synthetic(k=0)
    with pytest.raises(swarmcl.IOError_):
        swarmcl.Dataset.load("/nonexistent/dataset.swds")
    with pytest.raises(ValueError):
        swarmcl.Dataset.from_csv("x.csv", columns={"speed": "s"})


def run(ctx, seed=4, steps=30, model=None):
    data = swarmcl.Dataset.synthetic(k=300, seed=1)
    with swarmcl.Swarm(ctx, agent_count=60, seed=seed, domain=((-1, -1, -1), (1, 1, 1)),
                       interaction_radius=0.4, dt=0.01) as s:
        p = np.random.default_rng(seed).uniform(-0.3, 0.3, (60, 3))
        s.write_positions(p)
        s.set_energy_model(data, model or swarmcl.EnergyModel(centre=(0, 0, 0)))
        s.step(steps)
        return s.positions, s.velocities


def test_energy_model_runs_deterministically(ctx):
    a, va = run(ctx)
    b, vb = run(ctx)
    np.testing.assert_array_equal(a, b)
    assert np.isfinite(a).all()
    speeds = np.linalg.norm(va, axis=1)
    assert (speeds > 0).all()  # velocities are dataset samples
    c, _ = run(ctx, seed=5)
    assert not np.array_equal(a, c)


def test_stimuli_and_keypoints(ctx):
    data = swarmcl.Dataset.synthetic()
    kp = np.array([[0.3, 0, 0], [0, 0.3, 0], [-0.3, 0, 0], [0, -0.3, 0]], dtype=np.float32)
    model = swarmcl.EnergyModel(keypoints=kp, weights=swarmcl.EnergyWeights(oa=0.5, cos=0, noise=1, user=1),
                                stimuli=[swarmcl.Stimulus("attract", (0, 0, 0.5))])
    with swarmcl.Swarm(ctx, agent_count=20, seed=2, domain=((-1, -1, -1), (1, 1, 1)), dt=0.01) as s:
        s.set_energy_model(data, model)
        assert (s.energy_goals() == -1).all()
        s.step(3)
        g = s.energy_goals()
        assert ((g >= 0) & (g < 4)).all()
        s.set_energy_stimuli([swarmcl.Stimulus("startle", (0, 0, 0), (0.1, 0, 0), d_danger=0.2)])
        s.set_energy_keypoints(kp[:3], closed=False)
        s.step(3)
        with pytest.raises(swarmcl.InvalidArgumentError, match="at least 2"):
            s.set_energy_keypoints(kp[:1])
        with pytest.raises(ValueError):
            s.set_energy_stimuli([swarmcl.Stimulus("scary", (0, 0, 0))])
        with pytest.raises(swarmcl.InvalidArgumentError):
            s.set_energy_model(data, swarmcl.EnergyModel(rho=-1))
        s.clear_model()
        with pytest.raises(swarmcl.InvalidArgumentError, match="no energy model"):
            s.energy_goals()


def test_scenario_with_energy_model(ctx):
    text = """{"name": "e", "dt": 0.01, "steps": 5, "domain": {"min": [-1, -1, -1], "max": [1, 1, 1]},
               "agents": {"count": 20, "initial": {"type": "sphere", "center": [0, 0, 0], "radius": 0.3}},
               "model": {"type": "energy", "dataset": {"type": "synthetic", "k": 100, "groups": 5}}}"""
    with swarmcl.Scenario.parse(text) as sc:
        assert sc.info["model"] == "energy"
        with sc.create_swarm(ctx) as s:
            s.step(5)
            assert np.isfinite(s.positions).all()


def test_trajectory_synthesis_continue_and_mix(ctx, tmp_path):
    tracks = synthetic_tracks(n_tracks=5, samples=30)
    data = swarmcl.Dataset.synthetic()
    with swarmcl.Swarm(ctx, capacity=16, domain=((-1, -1, -1), (1, 1, 1)), dt=0.01) as s:
        s.start_from_tracks(tracks)
        assert s.agent_count == 5
        p0 = s.positions
        np.testing.assert_allclose(p0, [p[-1] for _, p in tracks], atol=1e-6)
        np.testing.assert_allclose(s.velocities, [(p[-1] - p[-2]) / 0.01 for _, p in tracks], rtol=1e-4, atol=1e-4)
        s.set_energy_model(data, swarmcl.EnergyModel(centre=(0, 0, 0)))
        frames = []
        for _ in range(20):
            s.step(1)
            frames.append(s.positions)
    frames = np.array(frames)
    # The continuation starts where the tracks end: one step away.
    assert np.linalg.norm(frames[0] - p0, axis=1).max() < 0.05
    out = tmp_path / "mixed.csv"
    start = tracks[0][0][-1] + 0.01  # the simulated frame 0 follows the last real sample
    rows = swarmcl.write_mixed_csv(out, tracks, frames, frame_time=0.01, start_time=start)
    table = np.genfromtxt(out, delimiter=",", names=True)
    assert rows == len(table) == 5 * 30 + 20 * 5
    assert set(np.unique(table["id"][table["source"] == 0])) == {5, 6, 7, 8, 9}
    assert table["frame"][table["source"] == 1].max() == -1  # real samples end just before frame 0
    with pytest.raises(swarmcl.InvalidArgumentError, match="3 or more"):
        with swarmcl.Swarm(ctx, capacity=4) as s:
            s.start_from_tracks([(np.array([0.0, 0.01]), np.zeros((2, 3)))])

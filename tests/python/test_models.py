"""The field model and noise sampling through the Python descriptors."""

import numpy as np
import pytest

import swarmcl

DOMAIN = ((-1.5, -1.5, 0.5), (1.5, 1.5, 3.5))


def run_field(ctx, seed=7, noise_seed=3, steps=20, n=2000):
    model = swarmcl.FieldModel(
        noise=swarmcl.NoiseDesc(type="curl", seed=noise_seed, domain_walls=True, time_scale=2.0),
        goal=(0.0, 0.0, 2.0), goal_radius=0.5, goal_falloff=0.5, min_distance=0.03)
    with swarmcl.Swarm(ctx, agent_count=n, seed=seed, domain=DOMAIN, interaction_radius=0.1,
                       dt=1 / 30) as s:
        s.set_field_model(model)
        s.step(steps)
        return s.positions, s.take_step_stats()


def test_field_model_runs_and_reports(ctx):
    p, stats = run_field(ctx)
    assert np.isfinite(p).all()
    assert stats.agents == 2000 and stats.steps == 20
    assert stats.mde_moved_total >= stats.mde_moved_last


def test_field_model_is_deterministic_for_a_seed(ctx):
    a, _ = run_field(ctx, noise_seed=3)
    b, _ = run_field(ctx, noise_seed=3)
    np.testing.assert_array_equal(a, b)
    c, _ = run_field(ctx, noise_seed=4)
    assert not np.array_equal(a, c)


def test_take_step_stats_resets_and_clear_model(ctx):
    with swarmcl.Swarm(ctx, agent_count=500, seed=1, domain=DOMAIN) as s:
        s.set_field_model(swarmcl.FieldModel(min_distance=0.05))
        s.step(4)
        assert s.take_step_stats().steps == 4
        assert s.take_step_stats().steps == 0
        s.clear_model()
        s.velocities = np.zeros((500, 3))
        before = s.positions
        s.step(5)
        np.testing.assert_array_equal(s.positions, before)   # ballistic, at rest


def test_boundaries_accepted(ctx):
    noise = swarmcl.NoiseDesc(boundaries=[
        swarmcl.Sphere(center=(0, 0, 2), radius=0.3),
        swarmcl.Box(center=(1, 1, 1), half_extents=(0.2, 0.2, 0.2), radius=0.05),
        swarmcl.Plane(normal=(0, 0, 1), offset=0.5)])
    with swarmcl.Swarm(ctx, agent_count=300, seed=2, domain=DOMAIN) as s:
        s.set_field_model(swarmcl.FieldModel(noise=noise))
        s.step(3)
        assert np.isfinite(s.positions).all()


def test_bad_noise_descriptors(ctx):
    pts = np.zeros((4, 3))
    region = ((-1, -1, -1), (1, 1, 1))
    bad = [
        swarmcl.NoiseDesc(scale=0.0),
        swarmcl.NoiseDesc(gain=float("nan")),
        swarmcl.NoiseDesc(region=region, boundaries=[swarmcl.Sphere((0, 0, 0), 0.0)]),
        swarmcl.NoiseDesc(type="white", baked=True, region=region),
    ]
    for desc in bad:
        with pytest.raises(swarmcl.InvalidArgumentError) as e:
            swarmcl.noise_sample(ctx, desc, pts)
        assert str(e.value), desc
    with swarmcl.Swarm(ctx, agent_count=10, seed=1) as s:
        with pytest.raises(swarmcl.InvalidArgumentError, match="scale"):
            s.set_field_model(swarmcl.FieldModel(noise=swarmcl.NoiseDesc(scale=-1.0)))
        with pytest.raises(TypeError):
            s.set_field_model(swarmcl.NoiseDesc())
    with pytest.raises(TypeError):
        swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(boundaries=["sphere"]), pts)
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(type="white"), [[0, np.nan, 0]])


def test_noise_sample_shapes(ctx, rng):
    region = ((-1, -1, -1), (1, 1, 1))
    for kind in swarmcl.NoiseType:
        desc = swarmcl.NoiseDesc(type=kind, region=region)
        out = swarmcl.noise_sample(ctx, desc, rng.uniform(-1, 1, (123, 3)))
        assert out.shape == (123, 3) and out.dtype == np.float32
        assert np.isfinite(out).all()
    assert swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(), [[0.1, 0.2, 0.3]]).shape == (1, 3)


def test_white_noise_statistics(ctx):
    n, gain = 50_000, 0.8
    pts = np.zeros((n, 3), np.float32)
    desc = swarmcl.NoiseDesc(type="white", gain=gain, seed=42)
    v = swarmcl.noise_sample(ctx, desc, pts, step=0)
    assert v.min() >= -gain and v.max() <= gain
    assert abs(v.mean()) < 0.01 * gain
    np.testing.assert_allclose(v.var(axis=0), gain**2 / 3, rtol=0.03)
    corr = np.corrcoef(v.T)
    assert np.abs(corr[np.triu_indices(3, 1)]).max() < 0.02
    np.testing.assert_array_equal(v, swarmcl.noise_sample(ctx, desc, pts, step=0))
    w = swarmcl.noise_sample(ctx, desc, pts, step=1)
    assert abs(np.corrcoef(v[:, 0], w[:, 0])[0, 1]) < 0.02


def test_gaussian_noise_statistics(ctx):
    n, gain = 50_000, 0.3
    v = swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(type="gaussian", gain=gain, seed=1),
                             np.zeros((n, 3)), step=5)
    assert abs(v.mean()) < 0.01 * gain
    np.testing.assert_allclose(v.std(axis=0), gain, rtol=0.03)

"""Swarm state, stepping, neighbour queries and errors on bad input."""

import numpy as np
import pytest

import swarmcl


def make(ctx, n=500, capacity=1024, **kw):
    kw.setdefault("seed", 5)
    kw.setdefault("interaction_radius", 0.1)
    return swarmcl.Swarm(ctx, capacity=max(n, capacity), agent_count=n, **kw)


def test_round_trip_in_agent_id_order(ctx, rng):
    with make(ctx, 0) as s:
        p = rng.uniform(-1, 1, (400, 3))            # float64: converted once
        v = rng.normal(size=(400, 3)).astype(np.float32)
        s.write_positions(p)
        assert s.agent_count == 400 and len(s) == 400
        s.write_velocities(v)
        np.testing.assert_array_equal(s.positions, p.astype(np.float32))
        np.testing.assert_array_equal(s.velocities, v)
        # a neighbour query reorders the device state by grid cell; reads stay in id order
        s.nearest_neighbor()
        np.testing.assert_array_equal(s.read_positions(), p.astype(np.float32))
        np.testing.assert_array_equal(s.read_velocities(), v)


def test_property_assignment_and_array_likes(ctx):
    with make(ctx, 0) as s:
        s.positions = [[0, 0, 0], [1, 2, 3]]
        np.testing.assert_array_equal(s.positions, [[0, 0, 0], [1, 2, 3]])
        f = np.asfortranarray(np.arange(12, dtype=np.float64).reshape(4, 3) / 10)
        s.positions = f
        np.testing.assert_array_equal(s.positions, f.astype(np.float32))
        s.velocities = f[:, ::-1]                  # non-contiguous view
        np.testing.assert_array_equal(s.velocities, f[:, ::-1].astype(np.float32))


def test_new_agents_start_at_rest(ctx):
    with swarmcl.Swarm(ctx, capacity=10) as s:
        s.positions = np.zeros((2, 3))
        s.velocities = np.ones((2, 3))
        s.positions = np.zeros((5, 3))
        v = s.velocities
        np.testing.assert_array_equal(v[:2], 1)
        np.testing.assert_array_equal(v[2:], 0)


def test_ballistic_step(ctx, rng):
    dt = 0.01
    with make(ctx, 300, dt=dt) as s:
        p0 = s.positions
        v = rng.uniform(-1, 1, (300, 3)).astype(np.float32)
        s.velocities = v
        assert s.step_count == 0
        s.step(10)
        s.step()
        assert s.step_count == 11
        np.testing.assert_allclose(s.positions, p0 + 11 * dt * v, atol=1e-5)
        np.testing.assert_array_equal(s.velocities, v)


def test_seed_places_agents_reproducibly(ctx):
    lo, hi = (-1, 0, 2), (1, 0.5, 3)
    with make(ctx, 200, seed=9, domain=(lo, hi)) as a, make(ctx, 200, seed=9, domain=(lo, hi)) as b:
        pa = a.positions
        np.testing.assert_array_equal(pa, b.positions)
        assert (pa >= np.float32(lo)).all() and (pa <= np.float32(hi)).all()


# ---- bad input -----------------------------------------------------------------

def test_nan_positions_refused_and_nothing_changes(ctx):
    with make(ctx, 10) as s:
        before = s.positions
        bad = before.copy()
        bad[3, 1] = np.nan
        with pytest.raises(swarmcl.InvalidArgumentError) as e:
            s.write_positions(bad)
        err = e.value
        assert isinstance(err, ValueError)
        assert err.status == swarmcl.lib.SWCL_ERROR_INVALID_ARGUMENT
        assert err.status_name == "SWCL_ERROR_INVALID_ARGUMENT"
        assert "swcl_swarm_write" in str(err) and "finite" in str(err)
        np.testing.assert_array_equal(s.positions, before)
        bad_v = np.zeros((10, 3))
        bad_v[0, 0] = np.inf
        with pytest.raises(swarmcl.InvalidArgumentError):
            s.velocities = bad_v


def test_count_above_capacity(ctx):
    with swarmcl.Swarm(ctx, capacity=8) as s:
        with pytest.raises(swarmcl.InvalidArgumentError, match="capacity"):
            s.write_positions(np.zeros((9, 3)))
        assert s.agent_count == 0
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.Swarm(ctx, capacity=4, agent_count=5)


def test_velocity_count_must_match(ctx):
    with make(ctx, 10) as s:
        with pytest.raises(swarmcl.InvalidArgumentError):
            s.write_velocities(np.zeros((9, 3)))


def test_bad_swarm_descriptors(ctx):
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.Swarm(ctx, capacity=0)
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.Swarm(ctx, capacity=10, interaction_radius=-1.0)
    with pytest.raises(swarmcl.InvalidArgumentError):
        swarmcl.Swarm(ctx, capacity=10, dt=float("nan"))
    with pytest.raises(ValueError):
        swarmcl.Swarm(ctx, capacity=-3)


def test_shapes_checked_in_python(ctx):
    with make(ctx, 4) as s:
        with pytest.raises(ValueError, match=r"\(N, 3\)"):
            s.write_positions(np.zeros((4, 2)))
        with pytest.raises(ValueError):
            s.write_positions(np.zeros(12))
        with pytest.raises(ValueError):
            s.step(-1)


def test_negative_radius(ctx):
    with make(ctx, 50) as s:
        for r in (-0.1, 0.0, float("nan")):
            with pytest.raises(swarmcl.InvalidArgumentError, match="radius"):
                s.neighbor_count(r)
        with pytest.raises(swarmcl.InvalidArgumentError):
            s.neighbor_lists(-1.0, 4)


# ---- neighbour queries -------------------------------------------------------------

def test_neighbours_on_a_line(ctx):
    with swarmcl.Swarm(ctx, capacity=16, interaction_radius=0.1) as s:
        s.positions = [[0.125 * i, 0, 0] for i in range(5)]   # exact in float32
        np.testing.assert_array_equal(s.neighbor_count(0.15), [1, 2, 2, 2, 1])
        dist, ids = s.nearest_neighbor()
        assert dist.dtype == np.float32 and ids.dtype == np.uint32
        np.testing.assert_array_equal(dist, 0.125)
        np.testing.assert_array_equal(ids, [1, 0, 1, 2, 3])      # ties: lowest id
        lists, counts, truncated = s.neighbor_lists(0.25, 3)
        assert lists.shape == (5, 3)
        np.testing.assert_array_equal(counts, [2, 3, 4, 3, 2])
        assert truncated == 1
        assert list(lists[0]) == [1, 2, swarmcl.NO_AGENT]
        assert list(lists[2]) == [1, 3, 0]                    # nearest first, ties: lowest id


def test_neighbour_count_matches_brute_force(ctx, rng):
    with make(ctx, 0) as s:
        p = rng.uniform(0, 1, (600, 3)).astype(np.float32)
        s.positions = p
        d = np.linalg.norm(p[:, None, :].astype(np.float64) - p[None, :, :], axis=-1)
        r = 0.12
        expected = (d <= r).sum(axis=1) - 1
        got = s.neighbor_count(r).astype(np.int64)
        # float32 on the device: only pairs within rounding of r may differ
        near = (np.abs(d - r) < 1e-5).sum(axis=1)
        assert (np.abs(got - expected) <= near).all()
        dist, ids = s.nearest_neighbor()
        np.fill_diagonal(d, np.inf)
        np.testing.assert_allclose(dist, d.min(axis=1), rtol=1e-5, atol=1e-6)


def test_single_agent_has_no_neighbour(ctx):
    with swarmcl.Swarm(ctx, capacity=4) as s:
        s.positions = [[0, 0, 0]]
        dist, ids = s.nearest_neighbor()
        assert np.isinf(dist[0]) and ids[0] == swarmcl.NO_AGENT

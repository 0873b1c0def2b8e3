"""Reads go straight into caller-owned arrays; writes convert at most once."""

import numpy as np
import pytest

import swarmcl
from swarmcl import _core


@pytest.fixture
def swarm(ctx):
    with swarmcl.Swarm(ctx, capacity=1000, agent_count=1000, seed=11) as s:
        s.velocities = np.full((1000, 3), 0.5, np.float32)
        yield s


def test_read_into_caller_array(swarm):
    out = np.zeros((1000, 3), np.float32)
    address = out.ctypes.data
    got = swarm.read_positions(out=out)
    assert got is out
    assert out.ctypes.data == address
    assert np.shares_memory(got, out)
    assert np.any(out != 0)
    np.testing.assert_array_equal(out, swarm.positions)
    swarm.step(3)
    swarm.read_positions(out)                      # refilled in place
    np.testing.assert_array_equal(out, swarm.positions)
    v = np.empty_like(out)
    assert swarm.read_velocities(v) is v
    np.testing.assert_array_equal(v, 0.5)


def test_read_into_a_view_of_a_larger_buffer(swarm):
    big = np.zeros((2000, 3), np.float32)
    view = big[500:1500]                           # C-contiguous slice
    swarm.read_positions(view)
    np.testing.assert_array_equal(big[500:1500], swarm.positions)
    assert not big[:500].any() and not big[1500:].any()


def test_out_array_checked(swarm):
    with pytest.raises(ValueError, match="float32"):
        swarm.read_positions(np.empty((1000, 3), np.float64))
    with pytest.raises(ValueError, match="shape"):
        swarm.read_positions(np.empty((999, 3), np.float32))
    with pytest.raises(ValueError, match="contiguous"):
        swarm.read_positions(np.empty((1000, 6), np.float32)[:, ::2])
    ro = np.empty((1000, 3), np.float32)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="writeable"):
        swarm.read_positions(ro)
    with pytest.raises(TypeError):
        swarm.read_positions([[0, 0, 0]] * 1000)


def test_positions_property_returns_new_arrays(swarm):
    a, b = swarm.positions, swarm.positions
    assert a is not b and not np.shares_memory(a, b)
    assert a.dtype == np.float32 and a.shape == (1000, 3) and a.flags.c_contiguous


def test_write_does_not_copy_float32_contiguous():
    a = np.zeros((10, 3), np.float32)
    assert _core._xyz_in(a, "t") is a
    b = _core._xyz_in(a.astype(np.float64), "t")
    assert b.dtype == np.float32 and b.flags.c_contiguous


def test_query_results_into_caller_array(swarm):
    counts = np.empty(1000, np.uint32)
    assert swarm.neighbor_count(0.2, out=counts) is counts
    np.testing.assert_array_equal(counts, swarm.neighbor_count(0.2))


def test_noise_sample_into_caller_array(ctx):
    pts = np.random.default_rng(0).uniform(-1, 1, (256, 3)).astype(np.float32)
    out = np.empty_like(pts)
    got = swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(type="perlin"), pts, out=out)
    assert got is out
    np.testing.assert_array_equal(out, swarmcl.noise_sample(ctx, swarmcl.NoiseDesc(type="perlin"), pts))

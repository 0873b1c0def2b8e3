"""Handles: close(), context managers, garbage collection, closed objects."""

import gc
import weakref

import numpy as np
import pytest

import swarmcl
from conftest import raw_swarm_alive

OK = 0


def test_close_then_use_raises_invalid_handle(ctx):
    s = swarmcl.Swarm(ctx, capacity=16, agent_count=4)
    hid = s.handle_id
    assert not s.closed and raw_swarm_alive(hid) == OK
    s.close()
    assert s.closed
    assert raw_swarm_alive(hid) == swarmcl.lib.SWCL_ERROR_INVALID_HANDLE
    s.close()                                      # twice is fine
    with pytest.raises(swarmcl.InvalidHandleError, match="not a live swarm"):
        s.step()
    with pytest.raises(swarmcl.InvalidHandleError):
        s.read_positions(np.empty((0, 3), np.float32))
    with pytest.raises(swarmcl.InvalidHandleError):
        _ = s.agent_count
    assert "closed" in repr(s)


def test_context_manager_releases(ctx):
    with swarmcl.Swarm(ctx, capacity=16, agent_count=4) as s:
        hid = s.handle_id
        assert raw_swarm_alive(hid) == OK
    assert s.closed and raw_swarm_alive(hid) == swarmcl.lib.SWCL_ERROR_INVALID_HANDLE


def test_released_on_garbage_collection(ctx):
    s = swarmcl.Swarm(ctx, capacity=16, agent_count=4)
    hid = s.handle_id
    ref = weakref.ref(s)
    del s
    gc.collect()
    assert ref() is None
    assert raw_swarm_alive(hid) == swarmcl.lib.SWCL_ERROR_INVALID_HANDLE


def test_no_reference_cycles_released_at_once(ctx):
    gc.disable()
    try:
        s = swarmcl.Swarm(ctx, capacity=16, agent_count=4)
        s.step()
        hid = s.handle_id
        del s                                      # refcount alone releases it
        assert raw_swarm_alive(hid) == swarmcl.lib.SWCL_ERROR_INVALID_HANDLE
    finally:
        gc.enable()


def test_context_released_and_swarm_outlives_it():
    c = swarmcl.Context()
    s = swarmcl.Swarm(c, capacity=16, agent_count=4, seed=3)
    c.close()
    with pytest.raises(swarmcl.InvalidHandleError):
        _ = c.device
    with pytest.raises(swarmcl.InvalidHandleError):
        swarmcl.Swarm(c, capacity=4)
    s.step(2)                                      # swarms keep their device alive
    assert s.step_count == 2 and s.positions.shape == (4, 3)
    s.close()


def test_context_gc():
    ffi, lib = swarmcl.ffi, swarmcl.lib
    c = swarmcl.Context()
    hid = c.handle_id
    info = ffi.new("swcl_device_info*")
    info.struct_size = ffi.sizeof("swcl_device_info")
    raw = ffi.new("swcl_context*", [hid])[0]
    assert lib.swcl_context_device_info(raw, info) == OK
    del c
    gc.collect()
    assert lib.swcl_context_device_info(raw, info) == lib.SWCL_ERROR_INVALID_HANDLE


def test_many_swarms_do_not_leak(ctx):
    ids = []
    for _ in range(50):
        s = swarmcl.Swarm(ctx, capacity=64, agent_count=64)
        ids.append(s.handle_id)
    del s
    gc.collect()
    assert all(raw_swarm_alive(i) == swarmcl.lib.SWCL_ERROR_INVALID_HANDLE for i in ids)

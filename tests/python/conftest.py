"""Shared fixtures for the Python package tests (run by scripts/test.sh).

The tests import the installed package (pip install .); from a source tree,
PYTHONPATH=bindings/python with a C build in build/ (or SWARMCL_LIBRARY) works too."""

import pathlib

import numpy as np
import pytest

import swarmcl

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def ctx():
    with swarmcl.Context() as c:
        yield c


@pytest.fixture
def rng():
    return np.random.default_rng(1234)


def raw_swarm_alive(handle_id: int) -> int:
    """The status of a raw C call on a swarm id (SWCL_OK while it lives)."""
    ffi, lib = swarmcl.ffi, swarmcl.lib
    n = ffi.new("uint32_t*")
    return lib.swcl_swarm_agent_count(ffi.new("swcl_swarm*", [handle_id])[0], n)

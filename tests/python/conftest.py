"""Shared fixtures for the Python package tests (run by scripts/test.sh).

The tests import the installed package (pip install .); from a source tree,
PYTHONPATH=bindings/python with a C build in build/ (or SWARMCL_LIBRARY) works too."""

import json
import pathlib
import struct

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


#: The touring leader of the policy-model tests (~100 m round a square).
TOUR = [(25, 0, 0, 0.8), (25, 25, 3, 1.0), (0, 25, 0, 0.8), (0, 0, 0, 0.7)]


def follower_swarm(ctx, n=100, seed=3):
    """n agents in a ball 8 m behind the origin, heading +x at 0.5 m/s."""
    s = swarmcl.Swarm(ctx, agent_count=n, domain=((-60, -60, -30), (60, 60, 30)), interaction_radius=18.5,
                      dt=0.1, seed=seed)
    rng = np.random.default_rng(seed)
    s.write_positions(rng.normal(0, 4, (n, 3)).astype(np.float32) + np.float32([-8, 0, 0]))
    s.write_velocities(np.tile(np.float32([0.5, 0, 0]), (n, 1)))
    return s


def follow_tour(s, weights=None, rounds=20, steps=25):
    """Moves swarm s with a policy (default: the shipped one) after the TOUR
    leader.  After each round: the followers' mean distance to the leader
    and their mean nearest-neighbour distance (two lists)."""
    kw = {} if weights is None else {"weights": str(weights)}
    s.set_policy_model(swarmcl.PolicyModel(leader_mode="tour", leader_speed=0.6, waypoints=TOUR, **kw))
    far, nearest = [], []
    for _ in range(rounds):
        s.step(steps)
        p = s.read_positions()
        lp, _, _ = s.policy_leader()
        assert np.isfinite(p).all()
        far.append(float(np.linalg.norm(p - lp, axis=1).mean()))
        d = np.linalg.norm(p[:, None, :].astype(np.float64) - p[None, :, :], axis=2)
        np.fill_diagonal(d, np.inf)
        nearest.append(float(d.min(axis=1).mean()))
    return far, nearest


def policy_bytes(weights, efs=True, activations=None, extra=None) -> bytes:
    """A policy-mlp/1 file's bytes from a list of (out, in) weight shapes (or
    arrays); biases zero, activations relu then tanh unless given, extra
    tensors (obs_mean, ...) added as they are: to break one thing."""
    tensors = {}
    for i, w in enumerate(weights):
        w = np.zeros(w, np.float32) if isinstance(w, tuple) else np.asarray(w, np.float32)
        tensors[f"layers.{i}.weight"] = w
        tensors[f"layers.{i}.bias"] = np.zeros(w.shape[0], np.float32)
    tensors.update(extra or {})
    acts = activations or ",".join(["relu"] * (len(weights) - 1) + ["tanh"])
    header, blobs, at = {}, [], 0
    for name, t in tensors.items():
        b = np.asarray(t, np.float32).tobytes()
        header[name] = {"dtype": "F32", "shape": list(np.shape(t)), "data_offsets": [at, at + len(b)]}
        blobs.append(b)
        at += len(b)
    header["__metadata__"] = {"swarmcl.format": "policy-mlp/1", "swarmcl.activations": acts,
                              "swarmcl.action_scale": "1,1,1,1", "swarmcl.efs": "1" if efs else "0"}
    h = json.dumps(header).encode()
    h += b" " * (-len(h) % 8)
    return struct.pack("<Q", len(h)) + h + b"".join(blobs)


def do_nothing_policy(path, obs_dim=54):
    """Writes a policy-mlp/1 file whose actions are all 0 (one linear layer,
    zero weights and bias): each follower keeps its speed and heading.  The
    baseline a following test must beat.  Returns path."""
    pathlib.Path(path).write_bytes(policy_bytes([(4, obs_dim)], efs=obs_dim == 54, activations="linear"))
    return path

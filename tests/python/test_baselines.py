"""The papers' baselines (docs/baselines.md): the example scenarios load and
run, the same seed gives bitwise the same run, and the noise object's type is
what moves the insects (Gaussian, white and Perlin runs differ)."""

import json
import os

import numpy as np
import pytest

import swarmcl

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "scenarios")
NAMES = ["baseline_bswarm", "baseline_boids_perlin", "baseline_boids_random"]


def run(ctx, name, steps=20, agents=60, seed=None):
    with open(os.path.join(EXAMPLES, name + ".json")) as f:
        sc = json.load(f)
    sc.pop("output")
    sc["agents"]["count"] = agents
    if seed is not None:
        sc["model"]["noise"]["seed"] = seed
    with swarmcl.Scenario.parse(json.dumps(sc)) as s, s.create_swarm(ctx) as swarm:
        swarm.step(steps)
        return swarm.positions, swarm.velocities


@pytest.mark.parametrize("name", NAMES)
def test_baseline_runs_and_repeats_bitwise(ctx, name):
    p1, v1 = run(ctx, name)
    p2, v2 = run(ctx, name)
    assert np.isfinite(p1).all() and np.isfinite(v1).all()
    assert np.array_equal(p1, p2) and np.array_equal(v1, v2)
    assert np.linalg.norm(v1, axis=1).max() <= 1.5 + 1e-5  # the scenarios' max_speed
    p3, _ = run(ctx, name, seed=99)
    assert not np.array_equal(p1, p3)  # the noise seed matters


def test_noise_types_differ(ctx):
    runs = [run(ctx, n)[0] for n in NAMES]
    for a in range(3):
        for b in range(a + 1, 3):
            assert not np.allclose(runs[a], runs[b])

"""The policy model from Python (docs/rl-swarm.md, "Policy model"): the
shipped policy drives a swarm after its leader, bad weights raise ParseError
naming the problem and leave the swarm usable, the example scenario loads and
runs, observations and actions come back in agent-id order."""

import pathlib

import numpy as np
import pytest

import swarmcl
from conftest import do_nothing_policy, follow_tour, follower_swarm, policy_bytes

REPO = pathlib.Path(__file__).resolve().parents[2]


def test_shipped_policy_follows_a_touring_leader(ctx, tmp_path):
    """The leader goes round most of the tour (~100 m) in 500 steps; the
    shipped policy's followers stay nearer to it than followers that do
    nothing (keep their start heading and speed), by a bound set between the
    two.  Measured (PoCL CPU): mean distance to the leader over the tour
    10.75 (max 18.1) for the shipped policy, 15.9 (max 22.3) doing nothing;
    the old check, max < 20, was about what doing nothing gets."""
    assert pathlib.Path(swarmcl.SHIPPED_POLICY).is_file()
    with follower_swarm(ctx) as s:
        far, _ = follow_tour(s)
        p = s.read_positions()
        lp, _, _ = s.policy_leader()
        obs, act = s.policy_observe()
        assert obs.shape == (100, 54) and act.shape == (100, 4)
        np.testing.assert_allclose(obs[:, 4:7], lp - p, atol=1e-3)
    with follower_swarm(ctx) as s:
        idle, _ = follow_tour(s, do_nothing_policy(tmp_path / "zero.safetensors"))
    assert np.mean(idle) > 13.0, idle           # the bound means something: doing nothing fails it
    assert np.mean(far) < 13.0, far             # ... and the shipped policy passes it
    assert np.mean(far) < np.mean(idle) - 3.0, (far, idle)


def test_bad_weights_raise_and_the_swarm_stays_usable(ctx, tmp_path):
    good = pathlib.Path(swarmcl.SHIPPED_POLICY).read_bytes()
    with follower_swarm(ctx, 30) as s:
        s.set_policy_model(swarmcl.PolicyModel(weights=good))
        for bad, what in [(good[: len(good) // 3], "truncated"), (good[:4], "truncated"),
                          (b"\x05\x00\x00\x00\x00\x00\x00\x00{oops", "not valid JSON"),
                          (good.replace(b'"F32"', b'"F16"', 1), "expected F32")]:
            with pytest.raises(swarmcl.ParseError, match=what):
                s.set_policy_model(swarmcl.PolicyModel(weights=bad))
            s.step(2)  # the previous policy still moves it
        path = tmp_path / "cut.safetensors"
        path.write_bytes(good[:1000])
        with pytest.raises(swarmcl.ParseError, match="cut.safetensors"):
            s.set_policy_model(swarmcl.PolicyModel(weights=str(path)))
        with pytest.raises(ValueError):
            swarmcl.PolicyModel(leader_mode="teleport").to_c()
        assert np.isfinite(s.read_positions()).all()


def test_layer_sizes_that_do_not_match_name_what_was_expected(ctx):
    """A policy file whose first layer does not take the observation (54
    with EFS, 51 without, by its swarmcl.efs), whose layers do not chain, or
    whose last layer does not give the 4 actions: ParseError naming the
    tensor, the shape expected and the shape found; the swarm keeps its
    policy and keeps stepping."""
    good = pathlib.Path(swarmcl.SHIPPED_POLICY).read_bytes()
    cases = [
        (policy_bytes([(16, 51), (4, 16)], efs=True),
         r"layers.0.weight' has shape \[16, 51\], expected \[out, 54\] \(the first layer takes the observation: "
         r"54 entries, as swarmcl.efs is \"1\""),
        (policy_bytes([(16, 54), (4, 16)], efs=False),
         r"layers.0.weight' has shape \[16, 54\], expected \[out, 51\]"),
        (policy_bytes([(16, 54), (8, 12), (4, 8)]), r"layers.1.weight' has shape \[8, 12\], expected \[out, 16\]"),
        (policy_bytes([(16, 54), (3, 16)]),
         r"layers.1.weight' has shape \[3, 16\], expected \[4, 16\]: the last layer must have 4 outputs"),
        (policy_bytes([(16, 54), (4, 16)], extra={"obs_mean": np.zeros(51), "obs_std": np.ones(51)}),
         r"obs_mean has shape \[51\], expected \[54\]"),
    ]
    with follower_swarm(ctx, 30) as s:
        s.set_policy_model(swarmcl.PolicyModel(weights=good))
        before, _ = s.policy_observe()
        for bad, what in cases:
            with pytest.raises(swarmcl.ParseError, match=what):
                s.set_policy_model(swarmcl.PolicyModel(weights=bad))
            s.step(2)  # the previous policy still moves it
            obs, act = s.policy_observe()
            assert obs.shape == (30, 54) and act.shape == (30, 4)
        assert np.isfinite(s.read_positions()).all()


def test_joystick_controls_turn_the_leader(ctx):
    with follower_swarm(ctx, 20) as s:
        s.set_policy_model()
        s.set_policy_leader_controls(0.0, (0.0, 0.1, 0.0))
        s.step(30)
        _, q, u = s.policy_leader()
        assert q[1] > 0.5 and u == pytest.approx(0.5)


def test_example_scenario_runs(ctx):
    with swarmcl.Scenario.load(REPO / "examples" / "scenarios" / "policy_roaming.json") as sc:
        assert sc.info["model"] == "policy"
        with sc.create_swarm(ctx) as s:
            s.step(20)
            assert np.isfinite(s.read_positions()).all()


def test_policy_infer_is_the_mlp_a_step_runs_and_a_numpy_forward(ctx):
    """swarm.policy_infer runs the MLP alone on given observations: on the
    swarm's own observations it gives policy_observe's actions bitwise, on
    any it matches a float64 numpy forward of the same weights (relu, relu,
    tanh); non-finite observations are refused with nothing written, a
    wrong width is a ValueError, a swarm without the policy model an
    InvalidArgumentError."""
    rng = np.random.default_rng(7)
    weights = [rng.normal(0, 0.3, shape).astype(np.float32) for shape in ((32, 54), (16, 32), (4, 16))]
    with follower_swarm(ctx, 40) as s:
        s.set_policy_model(swarmcl.PolicyModel(weights=policy_bytes(weights)))
        s.step(3)
        obs, act = s.policy_observe()
        assert np.array_equal(s.policy_infer(obs), act)
        x = rng.normal(0, 2, (1000, 54)).astype(np.float32)
        h = x.astype(np.float64)
        for i, w in enumerate(weights):
            h = h @ w.astype(np.float64).T
            h = np.tanh(h) if i == len(weights) - 1 else np.maximum(h, 0.0)
        got = s.policy_infer(x)
        assert got.shape == (1000, 4) and np.abs(got).max() > 0.1
        np.testing.assert_allclose(got, h, atol=2e-5)
        assert s.policy_infer(x.reshape(10, 100, 54)).shape == (10, 100, 4)
        assert s.policy_infer(np.zeros((0, 54), np.float32)).shape == (0, 4)
        bad = x.copy()
        bad[500, 3] = np.nan
        with pytest.raises(swarmcl.InvalidArgumentError, match="finite"):
            s.policy_infer(bad)
        with pytest.raises(ValueError, match="54"):
            s.policy_infer(x[:, :50])
        assert np.array_equal(s.policy_infer(x), got)  # still usable, the same answer
    with follower_swarm(ctx, 10) as s:
        with pytest.raises(swarmcl.InvalidArgumentError, match="not the policy model"):
            s.policy_infer(np.zeros((2, 54), np.float32))

"""The environment as RL libraries take it (issue 28): PettingZoo's API and
seed tests on SwarmParallelEnv, and Stable-Baselines3 training on the
registered Gymnasium env with no adapter written by the user."""

import os
import warnings

import numpy as np
import pytest

if os.environ.get("SWARMCL_REQUIRE_RL") == "1":
    import gymnasium  # noqa: F401 - scripts/test.sh installs swarmcl[rl]
    import pettingzoo  # noqa: F401
else:
    pytest.importorskip("gymnasium")
    pytest.importorskip("pettingzoo")

from swarmcl.rl import RlEnv  # noqa: E402
from swarmcl.rl.parallel import SwarmParallelEnv  # noqa: E402


def test_parallel_env_passes_pettingzoo_api_and_seed_tests(ctx):
    from pettingzoo.test import parallel_api_test, parallel_seed_test

    env = SwarmParallelEnv(4, ctx, max_steps=25)
    try:
        assert env.possible_agents == [f"follower_{i}" for i in range(4)]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            parallel_api_test(env, num_cycles=40)   # 40 > 25: the episode ends inside, agents become []
        assert not [str(w.message) for w in caught], [str(w.message) for w in caught]
        assert env.agents == []
    finally:
        env.close()
    parallel_seed_test(lambda: SwarmParallelEnv(3, ctx, max_steps=20), num_cycles=20)


def test_parallel_env_is_the_c_environment_and_state_is_the_worlds(ctx):
    rng = np.random.default_rng(2)
    with RlEnv(ctx, 1, 3, max_steps=4) as raw:
        env = SwarmParallelEnv(3, ctx, max_steps=4)
        try:
            obs, infos = env.reset(seed=11)
            ref = raw.reset(11)
            for t in range(4):
                for i, a in enumerate(env.agents):
                    np.testing.assert_array_equal(obs[a], ref[i])
                act = (rng.uniform(-1, 1, (3, 4)) * env.action_space("follower_0").high).astype(np.float32)
                obs, rew, te, tr, _ = env.step({f"follower_{i}": act[i] for i in range(3)})
                ref, r2, te2, tr2 = raw.step(act)
                assert [rew[f"follower_{i}"] for i in range(3)] == r2.tolist()
                st = env.state()
                s2 = raw.read_state()
                assert st.shape == env.state_space.shape == (28,)
                np.testing.assert_array_equal(st[:9], s2["positions"][:, :3].ravel())
                np.testing.assert_array_equal(st[21:24], s2["leader_positions"][0, :3])
            assert all(tr.values()) and env.agents == []        # M = 4 steps: every follower truncated
            with pytest.raises(RuntimeError, match="reset"):
                env.step({})
            env.reset(seed=1)
            with pytest.raises(ValueError, match=r"missing \['follower_2'\]"):
                env.step({"follower_0": np.zeros(4, np.float32), "follower_1": np.zeros(4, np.float32)})
            with pytest.raises(ValueError, match=r"shape \(4,\)"):
                env.step({f"follower_{i}": np.zeros(3, np.float32) for i in range(3)})
            nan = {f"follower_{i}": np.zeros(4, np.float32) for i in range(3)}
            nan["follower_1"] = np.array([0, np.nan, 0, 0], np.float32)
            with pytest.raises(ValueError, match="finite.*agent 1"):
                env.step(nan)
            env.step({f"follower_{i}": np.zeros(4, np.float32) for i in range(3)})   # still usable
        finally:
            env.close()


def test_stable_baselines3_trains_on_the_registered_env(ctx):
    """A few hundred steps of SB3's PPO on gymnasium.make(ENV_ID, agents=4):
    no adapter, the policy's weights move, episodes are counted, actions come
    back inside the action space."""
    if os.environ.get("SWARMCL_REQUIRE_RL") == "1":
        import stable_baselines3  # noqa: F401 - in the rl extra
    else:
        pytest.importorskip("stable_baselines3")
    import gymnasium
    import torch
    from stable_baselines3 import PPO

    from swarmcl.rl import ENV_ID

    env = gymnasium.make(ENV_ID, agents=4, context=ctx, max_steps=50, unit_actions=True)
    try:
        model = PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=2, seed=0, device="cpu", verbose=0)
        before = [p.detach().clone() for p in model.policy.parameters()]
        model.learn(total_timesteps=256)
        assert model.num_timesteps >= 256
        moved = sum(not torch.equal(a, b) for a, b in zip(before, model.policy.parameters()))
        assert moved >= len(before) // 2, f"{moved} of {len(before)} tensors changed"
        lengths = [e["l"] for e in model.ep_info_buffer]
        assert len(lengths) >= 4 and set(lengths) == {50}        # M = 50: episodes truncated at 50 steps
        obs, _ = env.reset(seed=3)
        act, _ = model.predict(obs, deterministic=True)
        assert act.shape == (4, 4) and env.action_space.contains(act.astype(np.float32))
    finally:
        env.close()

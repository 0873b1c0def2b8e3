"""swarmcl.rl's Gymnasium environments over swcl_rl_env_* (issue 15 item 5)."""

import os
import warnings

import numpy as np
import pytest

import swarmcl

if os.environ.get("SWARMCL_REQUIRE_RL") == "1":
    import gymnasium  # noqa: F401 - scripts/test.sh installs swarmcl[rl]
else:
    gymnasium = pytest.importorskip("gymnasium")

from gymnasium.vector import AutoresetMode  # noqa: E402

from swarmcl.rl import RlEnv, SwarmSingleEnv, SwarmVectorEnv  # noqa: E402


def _actions(rng, n):
    return (rng.uniform(-1, 1, size=(n, 4)) * np.array([0.1, 0.07, 0.07, 0.07])).astype(np.float32)


def _bits(a):
    return np.ascontiguousarray(a).view(np.uint8).tobytes()


def test_vector_api_shapes_dtypes_and_spaces(ctx):
    env = SwarmVectorEnv(2, 3, context=ctx, max_steps=50)
    try:
        assert env.num_envs == 6
        assert env.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
        assert env.single_observation_space.shape == (54,) and env.single_observation_space.dtype == np.float32
        assert env.single_action_space.shape == (4,) and env.single_action_space.dtype == np.float32
        np.testing.assert_allclose(env.single_action_space.high, [0.1, 2 * np.sin(np.deg2rad(2))] + 2 * [2 * np.sin(np.deg2rad(2))],
                                   rtol=1e-6)
        assert env.observation_space.shape == (6, 54) and env.action_space.shape == (6, 4)
        obs, info = env.reset(seed=3)
        assert obs.shape == (6, 54) and obs.dtype == np.float32 and isinstance(info, dict)
        assert env.observation_space.contains(obs)
        obs, rew, term, trunc, info = env.step(env.action_space.sample())
        assert obs.shape == (6, 54) and obs.dtype == np.float32
        assert rew.shape == (6,) and rew.dtype == np.float32
        assert term.shape == (6,) and term.dtype == np.bool_ and trunc.shape == (6,) and trunc.dtype == np.bool_
        assert np.isfinite(obs).all() and np.isfinite(rew).all()
        assert list(env.world_of(np.arange(6))) == [0, 0, 0, 1, 1, 1]
    finally:
        env.close()
    with SwarmVectorEnv(1, 4, context=ctx, efs=False) as e51:
        assert e51.single_observation_space.shape == (51,)
        assert e51.reset(seed=1)[0].shape == (4, 51)


def test_same_seed_gives_the_same_bits(ctx):
    rng = np.random.default_rng(5)
    acts = [_actions(rng, 8) for _ in range(15)]

    def run(env, seed):
        out = [_bits(env.reset(seed=seed)[0])]
        for a in acts:
            o, r, _, _, _ = env.step(a)
            out += [_bits(o), _bits(r)]
        return out

    with SwarmVectorEnv(2, 4, context=ctx) as a, SwarmVectorEnv(2, 4, context=ctx) as b:
        first = run(a, 11)
        assert run(b, 11) == first
        assert run(a, 11) == first          # the same env reset again
        assert run(a, 12)[0] != first[0]    # another seed, another start
        o1, _ = a.reset()
        o2, _ = a.reset()                   # no seed: a fresh one each time
        assert _bits(o1) != _bits(o2)


def test_worlds_are_the_agents_of_one_launch(ctx):
    """num_envs = W * N: one step moves every world; world w's agents are
    slots w*N .. w*N+N-1, and a world alone gives the same bits."""
    with SwarmVectorEnv(3, 5, context=ctx) as env:
        obs, _ = env.reset(seed=9)
        raw = RlEnv(ctx, 3, 5)
        try:
            np.testing.assert_array_equal(obs, raw.reset(9))
            a = _actions(np.random.default_rng(0), 15)
            o, r, _, _, _ = env.step(a)
            o2, r2, _, _ = raw.step(a)
            assert _bits(o) == _bits(o2) and _bits(r) == _bits(r2)
        finally:
            raw.close()


def test_autoreset_next_step_per_world(ctx):
    """NEXT_STEP: the step that ends a world returns its last observation
    with the flag set (broadcast to its agents); the next step ignores its
    actions, resets only that world and returns reward 0, flags false."""
    W, N, M = 2, 3, 3
    env = SwarmVectorEnv(W, N, context=ctx, max_steps=M)
    ref = RlEnv(ctx, W, N, max_steps=M)
    try:
        rng = np.random.default_rng(2)
        env.reset(seed=4)
        env.step(_actions(rng, W * N))
        # Put world 0 one step behind world 1 (raw per-world reset): the
        # worlds now end on different steps.
        env.env.reset_worlds(np.array([True, False]))
        o, r, te, tr, _ = env.step(_actions(rng, W * N))
        assert not tr.any() and not te.any()
        o, r, te, tr, _ = env.step(_actions(rng, W * N))        # world 1: step M
        assert list(tr) == [False] * N + [True] * N and not te.any()
        last_w1 = o[N:].copy()
        o, r, te, tr, _ = env.step(_actions(rng, W * N))        # world 1 reset, world 0: step M
        assert list(tr) == [True] * N + [False] * N
        assert np.all(r[N:] == 0) and np.all(r[:N] != 0)
        # World 1's observations are its next episode's start: the C env
        # reset(4), then world 1 to episode 1 (world 0's slots differ).
        ref.reset(4)
        start = ref.reset_worlds(np.array([False, True]))
        assert _bits(o[N:]) == _bits(start[N:])
        assert _bits(o[N:]) != _bits(last_w1)
        o, r, te, tr, _ = env.step(_actions(rng, W * N))        # world 0 reset, world 1 steps on
        assert not tr.any() and np.all(r[:N] == 0) and np.all(r[N:] != 0)
        ref.reset(4)  # world 0: the raw reset above was its episode 1, this is episode 2
        ref.reset_worlds(np.array([True, False]))
        start0 = ref.reset_worlds(np.array([True, False]))
        assert _bits(o[:N]) == _bits(start0[:N])
    finally:
        env.close()
        ref.close()


def test_navigation_terminates_and_resets(ctx):
    # A two-waypoint path 3 units long: the leader passes its end quickly.
    wp = [[0, 0, 0, 1.0], [3, 0, 0, 1.0]]
    with SwarmVectorEnv(2, 2, context=ctx, waypoints=wp, max_steps=500) as env:
        env.reset(seed=1)
        zero = np.zeros((4, 4), np.float32)
        for t in range(200):
            _, _, te, tr, _ = env.step(zero)
            if te.any():
                break
        assert te.all() and not tr.any(), "both worlds' leaders should reach the end together"
        _, r, te, tr, _ = env.step(zero)
        assert not te.any() and np.all(r == 0)


def test_bad_input_is_refused_and_the_env_stays_usable(ctx):
    rng = np.random.default_rng(8)
    good = [_actions(rng, 4) for _ in range(3)]
    with SwarmVectorEnv(2, 2, context=ctx) as env, SwarmVectorEnv(2, 2, context=ctx) as ref:
        with pytest.raises(RuntimeError, match="reset"):
            env.step(good[0])
        env.reset(seed=2)
        ref.reset(seed=2)
        bad = good[0].copy()
        bad[3, 1] = np.nan
        with pytest.raises(ValueError, match="finite.*slot 3, world 1, agent 1"):
            env.step(bad)
        bad[3, 1] = np.inf
        with pytest.raises(ValueError, match="finite"):
            env.step(bad)
        with pytest.raises(ValueError, match=r"shape \(4, 4\)"):
            env.step(np.zeros((3, 4), np.float32))
        with pytest.raises(ValueError, match=r"shape \(4, 4\)"):
            env.step(np.zeros((4, 3), np.float32))
        with pytest.raises(ValueError, match="options"):
            env.reset(seed=2, options={"x": 1})
        for a in good:  # nothing moved: the same bits as an env that never saw bad input
            o, r, _, _, _ = env.step(a)
            o2, r2, _, _, _ = ref.step(a)
            assert _bits(o) == _bits(o2) and _bits(r) == _bits(r2)
    for worlds, agents, name in ((0, 3, "worlds"), (3, 0, "agents")):
        with pytest.raises(swarmcl.InvalidArgumentError, match=name):
            SwarmVectorEnv(worlds, agents, context=ctx)
    with pytest.raises(swarmcl.InvalidArgumentError):
        SwarmVectorEnv(1, 1, context=ctx, scenario="no-such-scenario")
    with pytest.raises(TypeError, match="unknown parameter"):
        SwarmVectorEnv(1, 1, context=ctx, not_a_parameter=1)


def test_c_api_refuses_nan_actions_itself(ctx):
    """Below the Python check: swcl_rl_env_step refuses NaN with a message."""
    ffi, lib = swarmcl.ffi, swarmcl.lib
    with SwarmVectorEnv(1, 2, context=ctx) as env:
        env.reset(seed=1)
        a = np.zeros(8, np.float32)
        a[5] = np.nan
        st = lib.swcl_rl_env_step(env.env._h, ffi.from_buffer("float[]", a), a.size, ffi.NULL, 0, ffi.NULL, 0,
                                  ffi.NULL, ffi.NULL, 0)
        assert st == lib.SWCL_ERROR_INVALID_ARGUMENT
        assert "finite" in ffi.string(lib.swcl_last_error()).decode()
        env.step(np.zeros((2, 4), np.float32))


def test_single_env_passes_gymnasium_env_checker(ctx):
    """gymnasium.utils.env_checker.check_env is for single environments: the
    1 world x 1 agent case (SwarmSingleEnv) passes it, warnings included
    except the advice to normalise the action box (ours is in env units) and
    the notes on the observation box's infinite bounds (the leader offset is
    unbounded)."""
    from gymnasium.utils.env_checker import check_env

    env = SwarmSingleEnv(context=ctx, max_steps=20)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env, skip_render_check=True)
        expected = ("symmetric and normalized", "observation space minimum value is -infinity",
                    "observation space maximum value is infinity")
        other = [str(w.message) for w in caught if not any(e in str(w.message) for e in expected)]
        assert not other, other
    finally:
        env.close()

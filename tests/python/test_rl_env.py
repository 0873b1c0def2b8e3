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

from swarmcl.rl import ENV_ID, RlEnv, SwarmSingleEnv, SwarmVectorEnv, SwarmWorldEnv  # noqa: E402


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


# ---- issue 28: what RL users expect --------------------------------------


def test_registered_make_and_make_vec(ctx):
    """Importing swarmcl.rl registers ENV_ID: gymnasium.make gives one world
    of N followers, gymnasium.make_vec W * N followers (num_envs = W * N)."""
    assert ENV_ID == "swarmcl/LeaderFollow-v0" and ENV_ID in gymnasium.registry
    env = gymnasium.make(ENV_ID, agents=3, context=ctx, max_steps=20)
    try:
        assert isinstance(env.unwrapped, SwarmWorldEnv) and env.unwrapped.agents == 3
        assert env.observation_space.shape == (3, 54) and env.action_space.shape == (3, 4)
        obs, _ = env.reset(seed=5)
        assert obs.shape == (3, 54)
        _, r, te, tr, info = env.step(env.action_space.sample())
        assert isinstance(r, float) and r == pytest.approx(float(info["rewards"].mean()))
    finally:
        env.close()
    venv = gymnasium.make_vec(ENV_ID, num_envs=6, agents=3, context=ctx, max_steps=20)
    try:
        assert isinstance(venv, SwarmVectorEnv) and (venv.num_envs, venv.worlds, venv.agents) == (6, 2, 3)
        obs, _ = venv.reset(seed=5)
        assert obs.shape == (6, 54)
        with RlEnv(ctx, 2, 3, max_steps=20) as raw:   # the same bits as the C environment
            assert _bits(obs) == _bits(raw.reset(5))
    finally:
        venv.close()
    with gymnasium.make_vec(ENV_ID, num_envs=4, context=ctx) as v1:   # agents default 1: 4 worlds
        assert (v1.num_envs, v1.worlds, v1.agents) == (4, 4, 1)
    with pytest.raises(ValueError, match="multiple of agents = 3"):
        gymnasium.make_vec(ENV_ID, num_envs=7, agents=3, context=ctx)
    # A fresh interpreter that never imported swarmcl.rl: Gymnasium's module prefix imports it.
    import subprocess
    import sys

    code = ("import gymnasium as g; e = g.make('swarmcl.rl:" + ENV_ID + "', agents=2, max_steps=3); "
            "e.reset(seed=1); print(e.unwrapped.agents, [e.step(e.action_space.sample())[3] for _ in range(3)])")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.split() == ["2", "[False,", "False,", "True]"]
    with pytest.raises(ValueError, match="worlds \\* agents = 3 \\* 2"):
        SwarmVectorEnv(3, 2, context=ctx, num_envs=8)


def _run_stats(env, seed, acts, stagger=None):
    env.reset(seed=seed)
    out = []
    for t, a in enumerate(acts):
        o, r, te, tr, info = env.step(a)
        out.append((r.copy(), te | tr, info))
        if t == 0 and stagger is not None:   # worlds out of step (raw reset): they end on different steps
            env.unwrapped.env.reset_worlds(stagger)
    return out


def test_vector_infos_carry_episode_statistics_as_the_wrapper_gives_them(ctx):
    """infos["episode"] / ["_episode"] at each world's episode end: the same
    returns and lengths as gymnasium's RecordEpisodeStatistics around an env
    without them, per world, with the autoreset step not counted."""
    from gymnasium.wrappers.vector import RecordEpisodeStatistics

    rng = np.random.default_rng(3)
    acts = [_actions(rng, 6) for _ in range(11)]
    stagger = np.array([True, False])     # world 0 restarts after step 0: world 1 ends first
    with SwarmVectorEnv(2, 3, context=ctx, max_steps=4) as env, \
            SwarmVectorEnv(2, 3, context=ctx, max_steps=4, episode_statistics=False) as plain:
        ours = _run_stats(env, 8, acts, stagger)
        wrapped = RecordEpisodeStatistics(plain)
        theirs = _run_stats(wrapped, 8, acts, stagger)
        for t, ((r, done, info), (r2, done2, info2)) in enumerate(zip(ours, theirs)):
            assert _bits(r) == _bits(r2) and (done == done2).all()
            assert ("episode" in info) == done.any() == ("episode" in info2), t
            if done.any():
                np.testing.assert_array_equal(info["_episode"], info2["_episode"])
                np.testing.assert_allclose(info["episode"]["r"], info2["episode"]["r"], rtol=1e-12)
                np.testing.assert_array_equal(info["episode"]["l"], info2["episode"]["l"])
                assert (info["episode"]["t"][done] >= 0).all() and (info["episode"]["t"][~done] == 0).all()
        assert [t for t, (_, d, _) in enumerate(ours) if d.any()] == [3, 4, 8, 9]   # worlds 1, 0, 1, 0
        # World 1's first episode: max_steps = 4 steps, its return the sum of its rewards.
        assert ours[3][2]["episode"]["l"].tolist() == [0, 0, 0, 4, 4, 4]
        np.testing.assert_allclose(ours[3][2]["episode"]["r"][3:],
                                   sum(r.astype(np.float64) for r, _, _ in ours[:4])[3:], rtol=1e-12)
        # Its second: steps 5-8 (step 4 was the autoreset step, reward 0, not counted).
        assert ours[8][2]["episode"]["l"].tolist() == [0, 0, 0, 4, 4, 4]
        np.testing.assert_allclose(ours[8][2]["episode"]["r"][3:],
                                   sum(r.astype(np.float64) for r, _, _ in ours[5:9])[3:], rtol=1e-12)
    with SwarmVectorEnv(1, 2, context=ctx, max_steps=2) as env:
        with pytest.raises(ValueError, match="already exist"):   # wrapping twice: turn ours off first
            _run_stats(RecordEpisodeStatistics(env), 1, [np.zeros((2, 4), np.float32)] * 2)


def test_world_env_episode_statistics_match_the_wrapper(ctx):
    from gymnasium.wrappers import RecordEpisodeStatistics

    rng = np.random.default_rng(4)
    acts = [_actions(rng, 3) for _ in range(5)]
    with SwarmWorldEnv(3, ctx, max_steps=5) as env, SwarmWorldEnv(3, ctx, max_steps=5, episode_statistics=False) as p:
        w = RecordEpisodeStatistics(p)
        env.reset(seed=2)
        w.reset(seed=2)
        for t, a in enumerate(acts):
            _, r, te, tr, info = env.step(a)
            _, r2, te2, tr2, info2 = w.step(a)
            assert r == r2 and (te, tr) == (te2, tr2) and ("episode" in info) == (t == 4) == ("episode" in info2)
        assert info["episode"]["r"] == pytest.approx(info2["episode"]["r"], rel=1e-12)
        assert info["episode"]["l"] == info2["episode"]["l"] == 5


def test_reset_with_a_seed_per_world(ctx):
    """reset(seed=[s_0, ..., s_W-1]): world w starts as reset(seed=s_w)
    starts it; a list of the wrong length is a ValueError naming W, and the
    env stays usable."""
    rng = np.random.default_rng(6)
    acts = [_actions(rng, 12) for _ in range(4)]
    with SwarmVectorEnv(3, 4, context=ctx) as env, SwarmVectorEnv(3, 4, context=ctx) as ref:
        mixed, _ = env.reset(seed=[7, 9, 7])
        a, _ = ref.reset(seed=7)
        b, _ = ref.reset(seed=9)
        assert _bits(mixed[:4]) == _bits(a[:4]) and _bits(mixed[4:8]) == _bits(b[4:8])
        assert _bits(mixed[8:]) == _bits(a[8:]) and _bits(mixed[4:8]) != _bits(a[4:8])
        same, _ = env.reset(seed=np.array([7, 7, 7]))        # a list of one seed = that seed
        assert _bits(same) == _bits(a)
        drawn, _ = env.reset(seed=[None, 9, None])            # None entries: drawn from the env's generator
        assert _bits(drawn[4:8]) == _bits(b[4:8]) and _bits(drawn[:4]) != _bits(a[:4])
        for bad, err, what in (([1, 2], ValueError, "3 expected, got 2"), (list(range(12)), ValueError, "got 12"),
                               ([1, -2, 3], ValueError, r"\[0, 2\^64\)"), ("123", TypeError, "per-world seeds")):
            with pytest.raises(err, match=what):
                env.reset(seed=bad)
        env.reset(seed=[7, 9, 7])
        ref.reset(seed=[7, 9, 7])
        for act in acts:   # the refused resets changed nothing
            o, r, _, _, _ = env.step(act)
            o2, r2, _, _, _ = ref.step(act)
            assert _bits(o) == _bits(o2) and _bits(r) == _bits(r2)


def test_world_env_with_several_followers_passes_gymnasium_env_checker(ctx):
    """check_env on one world of 6 followers: neighbours, EFS and every
    neighbour reward are exercised (the 1 x 1 env has none)."""
    from gymnasium.utils.env_checker import check_env

    with SwarmWorldEnv(6, ctx, max_steps=20) as env:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env, skip_render_check=True)
        expected = ("symmetric and normalized", "observation space minimum value is -infinity",
                    "observation space maximum value is infinity")
        other = [str(w.message) for w in caught if not any(e in str(w.message) for e in expected)]
        assert not other, other
        obs, _ = env.reset(seed=1)
        assert (obs[:, [51, 53]] != 0).all()          # EFS: every follower has neighbours (same start heading)
        obs, _, _, _, info = env.step(_actions(np.random.default_rng(1), 6))
        assert (obs[:, 51:54] != 0).all()             # ... and, once they turn, heading differences
        assert len(set(info["rewards"].tolist())) > 1  # the followers' own rewards


def test_world_env_refuses_bad_actions_and_stays_usable(ctx):
    rng = np.random.default_rng(9)
    good = [_actions(rng, 4) for _ in range(3)]
    with SwarmWorldEnv(4, ctx) as env, SwarmWorldEnv(4, ctx) as ref:
        with pytest.raises(RuntimeError, match="reset"):
            env.step(good[0])
        env.reset(seed=3)
        ref.reset(seed=3)
        for bad, err, what in ((np.zeros((3, 4), np.float32), ValueError, r"shape \(4, 4\).*got \(3, 4\)"),
                               (np.zeros(16, np.float32), ValueError, r"shape \(4, 4\).*got \(16,\)"),
                               (np.zeros((4, 4), bool), TypeError, r"float32 expected\), got dtype bool"),
                               (np.zeros((4, 4), complex), TypeError, "got dtype complex"),
                               ([["a"] * 4] * 4, TypeError, "float32 expected"),
                               ([[0.0] * 4, [0.0] * 3], ValueError, r"shape \(4, 4\)")):
            with pytest.raises(err, match=what):
                env.step(bad)
        nan = good[0].copy()
        nan[2, 3] = np.nan
        with pytest.raises(ValueError, match="finite.*follower 2"):
            env.step(nan)
        for a in good:   # nothing moved
            o, r, _, _, i = env.step(a)
            o2, r2, _, _, i2 = ref.step(a)
            assert _bits(o) == _bits(o2) and r == r2
        assert _bits(env.step(good[0].astype(np.float64))[0]) == _bits(ref.step(good[0])[0])  # float64 is cast
    with SwarmVectorEnv(1, 2, context=ctx) as venv:
        venv.reset(seed=1)
        with pytest.raises(TypeError, match=r"float32 expected\), got dtype <U1"):
            venv.step(np.full((2, 4), "x"))
        venv.step(np.zeros((2, 4), np.float32))
    with SwarmSingleEnv(context=ctx) as single:
        single.reset(seed=1)
        with pytest.raises(ValueError, match=r"shape \(4,\)"):
            single.step(np.zeros((1, 4), np.float32))
        single.step(np.zeros(4, np.float32))


def test_unit_actions_are_the_env_actions_scaled(ctx):
    """unit_actions=True: the action space is [-1, 1] per component (no
    check_env advice to normalise it), and an action a moves the world as
    a * action_scale in env units does."""
    from gymnasium.utils.env_checker import check_env

    rng = np.random.default_rng(12)
    with SwarmWorldEnv(3, ctx, unit_actions=True, max_steps=20) as env, SwarmWorldEnv(3, ctx) as ref:
        assert (env.action_space.low == -1).all() and (env.action_space.high == 1).all()
        scale = ref.env.action_scale()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env, skip_render_check=True)
        assert not [w for w in caught if "normalized" in str(w.message)]
        env.reset(seed=4)
        ref.reset(seed=4)
        for _ in range(5):
            a = rng.uniform(-1, 1, (3, 4)).astype(np.float32)
            o, r, _, _, _ = env.step(a)
            o2, r2, _, _, _ = ref.step(a * scale)
            assert _bits(o) == _bits(o2) and r == r2
    with SwarmVectorEnv(2, 2, context=ctx, unit_actions=True) as venv, SwarmVectorEnv(2, 2, context=ctx) as vref:
        assert venv.single_action_space.high.tolist() == [1, 1, 1, 1]
        venv.reset(seed=5)
        vref.reset(seed=5)
        a = rng.uniform(-1, 1, (4, 4)).astype(np.float32)
        assert _bits(venv.step(a)[0]) == _bits(vref.step(a * vref.env.action_scale())[0])
        bad = a.copy()
        bad[1, 0] = np.nan
        with pytest.raises(ValueError, match="finite.*slot 1"):
            venv.step(bad)


def test_world_env_renders_rgb_arrays(ctx):
    """render_mode="rgb_array": a top view centred on the leader (red), the
    followers white where their positions fall; check_env's render check
    passes; None without a render mode."""
    from gymnasium.utils.env_checker import check_env

    with SwarmWorldEnv(5, ctx, render_mode="rgb_array", render_size=200, render_extent=50.0, scenario="maze") as env:
        check_env(env)
        env.reset(seed=2)
        img = env.render()
        assert img.shape == (200, 200, 3) and img.dtype == np.uint8
        assert img[100, 100].tolist() == [230, 40, 40]             # the leader at the centre
        st = env.env.read_state()
        d = (st["positions"][:, :2] - st["leader_positions"][0, :2]) * 4.0   # 200 px / 50 m
        for dx, dy in d:
            c, r = int(np.floor(100 + dx)), int(np.floor(100 - dy))
            if 0 <= r < 200 and 0 <= c < 200 and abs(dx) > 3 and abs(dy) > 3:   # not under the leader's square
                assert img[r, c].tolist() == [235, 235, 235]
        wall = (img == [110, 110, 110]).all(axis=2)                # the maze's long walls y = +-23 (+-1), x >= -10
        assert wall[100 - 24 * 4 + 1:100 - 22 * 4, 100:].all() and not wall[100 - 24 * 4 + 1:100 - 22 * 4, :99].any()
        assert env.metadata["render_fps"] == 10
    with SwarmWorldEnv(2, ctx) as plain:
        plain.reset(seed=1)
        assert plain.render() is None
    with pytest.raises(ValueError, match="render_mode"):
        SwarmWorldEnv(2, ctx, render_mode="human")
    env = gymnasium.make(ENV_ID, agents=3, context=ctx, render_mode="rgb_array")
    try:
        env.reset(seed=1)
        assert env.render().shape == (256, 256, 3)
    finally:
        env.close()


def test_per_world_layout_is_the_flat_one_reshaped(ctx):
    """RlEnv(per_world=True): observations (W, N, D), rewards (W, N), the
    RAG's actions and the followers' state (W, N, 4): the same bits as the
    flat layout of a twin env, reshaped; actions taken in either layout."""
    W, N = 3, 4
    with RlEnv(ctx, W, N, max_steps=30) as flat, RlEnv(ctx, W, N, max_steps=30, per_world=True) as shaped:
        assert shaped.per_world and not flat.per_world
        o_flat, o_shaped = flat.reset(7), shaped.reset(7)
        assert o_shaped.shape == (W, N, 54) and o_flat.shape == (W * N, 54)
        assert _bits(o_shaped) == _bits(o_flat)
        np.testing.assert_array_equal(o_shaped[1, 2], o_flat[1 * N + 2])  # slot = world * N + agent
        for t in range(5):
            a_flat, a_shaped = flat.rag_actions(), shaped.rag_actions()
            assert a_shaped.shape == (W, N, 4) and _bits(a_shaped) == _bits(a_flat)
            # the shaped env takes (W, N, 4), the flat one (W*N, 4): the same step
            o_flat, r_flat, te_f, tr_f = flat.step(a_flat)
            o_shaped, r_shaped, te_s, tr_s = shaped.step(a_shaped if t % 2 else a_flat)
            assert o_shaped.shape == (W, N, 54) and r_shaped.shape == (W, N) and r_shaped.dtype == np.float32
            assert te_s.shape == (W,) and tr_s.shape == (W,)
            assert _bits(o_shaped) == _bits(o_flat) and _bits(r_shaped) == _bits(r_flat)
            np.testing.assert_array_equal(r_shaped[2], r_flat[2 * N:3 * N])
        assert _bits(flat.step(a_flat.reshape(W, N, 4))[0]) == _bits(shaped.step(a_flat)[0])  # either layout, both
        st_f, st_s = flat.read_state(), shaped.read_state()
        assert st_s["positions"].shape == (W, N, 4) and st_s["velocities"].shape == (W, N, 4)
        assert st_s["leader_positions"].shape == (W, 4)
        assert _bits(st_s["positions"]) == _bits(st_f["positions"])
        assert shaped.reset_seeds([1, 2, 3]).shape == (W, N, 54)
        assert shaped.reset_worlds([True, False, True]).shape == (W, N, 54)
    with RlEnv(ctx, 2, 3, efs=False, per_world=True) as e51:
        assert e51.reset(1).shape == (2, 3, 51)
        with pytest.raises(ValueError, match=r"\(worlds \* agents, 4\) or \(worlds, agents, 4\)"):
            e51.step(np.zeros((3, 2, 4), np.float32))   # W and N swapped
        assert e51.step(np.zeros((2, 3, 4), np.float32))[1].shape == (2, 3)  # still usable
    with pytest.raises(TypeError, match="per_world must be True or False"):
        RlEnv(ctx, 1, 2, per_world="yes")
    # The wrappers' spaces have their own layout: refused there, naming RlEnv.
    for make in (lambda: SwarmVectorEnv(2, 3, context=ctx, per_world=True),
                 lambda: SwarmWorldEnv(3, context=ctx, per_world=True)):
        with pytest.raises(ValueError, match=r"per_world=True is RlEnv's option"):
            make()


def test_policy_whose_layers_do_not_match_the_observation(ctx, tmp_path):
    """swarmcl.rl.export.load_policy checks a file as the library's loader
    does (a ValueError naming the tensor, what was expected and what the file
    has), and policy_actions refuses observations of another width (a 54-input
    EFS policy on an efs=False env's 51): the env is untouched and keeps
    stepping, and the policy keeps working on observations of its width."""
    from conftest import policy_bytes
    from swarmcl.rl.export import load_policy, policy_actions

    def loaded(name, data):
        path = tmp_path / name
        path.write_bytes(data)
        return path

    bad = [
        (policy_bytes([(16, 51), (4, 16)], efs=True),
         r"layers.0.weight' has shape \[16, 51\], expected \[out, 54\] \(the first layer takes the observation: 54 "
         r"entries, as swarmcl.efs is \"1\""),
        (policy_bytes([(16, 54), (4, 16)], efs=False), r"layers.0.weight' has shape \[16, 54\], expected \[out, 51\]"),
        (policy_bytes([(16, 54), (8, 12), (4, 8)]), r"layers.1.weight' has shape \[8, 12\], expected \[out, 16\] "
                                                    r"\(in = the previous layer's out\)"),
        (policy_bytes([(16, 54), (3, 16)]), r"layers.1.weight' has shape \[3, 16\], expected \[4, 16\] \(the last "
                                            r"layer gives the 4 actions; it has 3 outputs\)"),
        (policy_bytes([(16, 54), (4, 16)], extra={"obs_std": np.ones(54)}), "obs_mean and obs_std must be given"),
        (policy_bytes([(16, 54), (4, 16)], extra={"obs_mean": np.zeros(51), "obs_std": np.ones(51)}),
         r"obs_mean has shape \[51\], expected \[54\]"),
        (policy_bytes([(16, 54), (4, 16)])[:200], "beyond the end of the file"),
    ]
    for i, (data, what) in enumerate(bad):
        path = loaded(f"bad{i}.safetensors", data)
        with pytest.raises(ValueError, match=what) as err:
            load_policy(path)
        assert str(path) in str(err.value)
    efs_policy = load_policy(loaded("efs.safetensors", policy_bytes([(16, 54), (4, 16)])))
    assert efs_policy["obs_dim"] == 54 and efs_policy["efs"]
    with RlEnv(ctx, 2, 3, efs=False) as env:
        obs = env.reset(4)
        with pytest.raises(ValueError, match=r"the policy takes 54 observations per agent \(with EFS\), got "
                                             r"observations of shape \(6, 51\)"):
            policy_actions(efs_policy, obs)
        obs, rew, _, _ = env.step(env.rag_actions())  # the env is untouched and steps on
        assert obs.shape == (6, 51) and np.isfinite(rew).all()
    with RlEnv(ctx, 2, 3, per_world=True) as env:  # (W, N, D) observations: actions (W, N, 4)
        obs = env.reset(4)
        act = policy_actions(efs_policy, obs)
        assert act.shape == (2, 3, 4)
        assert np.isfinite(env.step(act)[1]).all()


def test_rag_leader_coupling_is_a_parameter(ctx):
    """The RAG's leader coupling from Python: the defaults (PD, k_p 0.25,
    k_d 1) in params, rag_leader_pd=False the first coupling (other
    actions from the same state), bad gains refused naming them."""
    from swarmcl.rl import default_params

    d = default_params()
    assert d["rag_leader_pd"] is True and d["rag_leader_kp"] == 0.25 and d["rag_leader_kd"] == 1.0
    with RlEnv(ctx, 2, 20) as pd, RlEnv(ctx, 2, 20, rag_leader_pd=False) as zones, \
            RlEnv(ctx, 2, 20, rag_leader_kp=0.25, rag_leader_kd=1.0) as same:
        assert zones.params["rag_leader_pd"] is False
        pd.reset(3), zones.reset(3), same.reset(3)
        assert _bits(pd.rag_actions()) == _bits(same.rag_actions())
        assert _bits(pd.rag_actions()) != _bits(zones.rag_actions())
    with pytest.raises(swarmcl.InvalidArgumentError, match="rag_leader_kd = -0.5"):
        RlEnv(ctx, 1, 2, rag_leader_kd=-0.5)

"""Gymnasium environments over the C API's leader-following environment.

``SwarmVectorEnv`` is a ``gymnasium.vector.VectorEnv`` whose sub-environments
are the followers of W worlds x N agents (num_envs = W * N), all driven by
one shared policy: one ``step`` is one device launch for every world.
``SwarmWorldEnv`` is one world of N followers as a plain ``gymnasium.Env``
(observation (N, D), action (N, 4), reward the followers' mean): what
``gymnasium.make`` gives and what ``gymnasium.utils.env_checker.check_env``
and single-agent libraries take.  ``SwarmSingleEnv`` is its 1 x 1 case with
flat (D,) / (4,) spaces.

Registered as ``swarmcl/LeaderFollow-v0`` when swarmcl.rl is imported:
``gymnasium.make(ENV_ID, agents=N)`` (SwarmWorldEnv) and
``gymnasium.make_vec(ENV_ID, num_envs=W * N, agents=N)`` (SwarmVectorEnv).
Both add RecordEpisodeStatistics' ``infos["episode"]`` themselves
(``episode_statistics=False`` turns that off, e.g. before wrapping them in
gymnasium's RecordEpisodeStatistics, which refuses keys already there).

Episodes end per world (terminated: a navigation leader passed its last
waypoint; truncated: M steps), so the flags are broadcast to the world's N
agents, and autoreset is per world (``swcl_rl_env_reset_worlds``)."""

from __future__ import annotations

import operator
import time
from typing import Any, Optional, Sequence, Union

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from .._core import Context
from .native_env import ACTION_DIM, RlEnv, checked_actions, flat_layout_only

__all__ = ["SwarmVectorEnv", "SwarmWorldEnv", "SwarmSingleEnv", "ENV_ID", "register_envs"]

#: The Gymnasium id (namespace swarmcl, version 0).
ENV_ID = "swarmcl/LeaderFollow-v0"


def register_envs() -> None:
    """Registers ENV_ID with Gymnasium (done when swarmcl.rl is imported):
    ``gymnasium.make`` builds a SwarmWorldEnv, ``gymnasium.make_vec`` a
    SwarmVectorEnv.  Episodes end by the env's own M steps (``max_steps``,
    Table 1's 1,200), so no TimeLimit is added."""
    if ENV_ID not in gym.registry:
        gym.register(id=ENV_ID, entry_point="swarmcl.rl.env:SwarmWorldEnv",
                     vector_entry_point="swarmcl.rl.env:SwarmVectorEnv")


def _spaces(env: RlEnv, unit_actions: bool = False):
    """(observation, action) spaces of one follower: actions in env units,
    +-action_scale(), or in [-1, 1] with unit_actions (times action_scale()
    inside step)."""
    obs = gym.spaces.Box(-np.inf, np.inf, shape=(env.obs_dim,), dtype=np.float32)
    s = np.ones(ACTION_DIM, np.float32) if unit_actions else env.action_scale()
    act = gym.spaces.Box(-s, s, shape=(ACTION_DIM,), dtype=np.float32)
    return obs, act


def _seed_from(rng: np.random.Generator) -> int:
    return int(rng.integers(0, 2**63, dtype=np.int64))


def _world_seeds(seed, worlds: int, what: str) -> list:
    """A list of per-world seeds checked: one per world (None: drawn later)."""
    if isinstance(seed, (str, bytes)) or not hasattr(seed, "__len__"):
        raise TypeError(f"{what}: seed must be an int, None or a sequence of {worlds} per-world seeds, "
                        f"got {type(seed).__name__}")
    seeds = list(seed)
    if len(seeds) != worlds:
        raise ValueError(f"{what}: a seed list needs one seed per world: {worlds} expected, got {len(seeds)} "
                         f"(sub-environments are followers; a world's followers share its seed)")
    out = []
    for s in seeds:
        if s is None:
            out.append(None)
            continue
        s = operator.index(s)
        if not 0 <= s < 2**64:
            raise ValueError(f"{what}: seeds must be in [0, 2^64), got {s}")
        out.append(s)
    return out


class _EpisodeStats:
    """What gymnasium.wrappers.vector.RecordEpisodeStatistics adds to infos,
    kept per slot: at the step that ends an episode, infos["episode"] =
    {"r": returns, "l": lengths, "t": seconds} (0 where not done) and
    infos["_episode"] the done mask; the autoreset step after it starts the
    next episode's sums at zero (its reward 0 is not counted)."""

    def __init__(self, n: int):
        self.n = n
        self.reset()

    def reset(self) -> None:
        self.returns = np.zeros(self.n)
        self.lengths = np.zeros(self.n, dtype=int)
        self.start = np.full(self.n, time.perf_counter())
        self.prev_done = np.zeros(self.n, dtype=bool)

    def step(self, rewards, done, infos: dict) -> None:
        p = self.prev_done
        self.returns[p] = 0.0
        self.lengths[p] = 0
        self.start[p] = time.perf_counter()
        self.returns[~p] += rewards[~p]
        self.lengths[~p] += 1
        self.prev_done = done = np.asarray(done, dtype=bool).copy()
        if done.any():
            secs = np.round(time.perf_counter() - self.start, 6)
            infos["episode"] = {"r": np.where(done, self.returns, 0.0), "l": np.where(done, self.lengths, 0),
                                "t": np.where(done, secs, 0.0)}
            infos["_episode"] = done


class SwarmVectorEnv(VectorEnv):
    """W worlds x N followers as num_envs = W * N sub-environments.

    Autoreset NEXT_STEP (``gymnasium.make_vec``'s default): the step that
    ends a world returns its last observations with terminated / truncated
    set; the next ``step`` ignores that world's actions, resets it to its
    next episode and returns its first observations with reward 0 and both
    flags false.  (The C step advances every world at once; a finished world
    is stepped once more and then reset, its results discarded.)

    ``worlds`` x ``agents`` followers; or ``num_envs`` (what
    ``gymnasium.make_vec`` passes) = worlds * agents with ``agents``
    (default 1) followers per world.  ``context``: a swarmcl.Context (one is
    created and owned when None); ``episode_statistics``: infos["episode"]
    as RecordEpisodeStatistics gives it; ``unit_actions``: the action space
    is [-1, 1]^4 per follower (times the action scale inside step) instead
    of env units; other keywords go to RlEnv (scenario, max_steps, efs, ...)."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, worlds: Optional[int] = None, agents: Optional[int] = None,
                 context: Optional[Context] = None, *, num_envs: Optional[int] = None,
                 episode_statistics: bool = True, unit_actions: bool = False, **env_kwargs):
        agents = 1 if agents is None else operator.index(agents)
        if num_envs is not None:
            num_envs = operator.index(num_envs)
            if agents < 1 or num_envs < 1 or num_envs % agents:
                raise ValueError(f"SwarmVectorEnv: num_envs = worlds * agents must be a positive multiple of "
                                 f"agents = {agents}, got num_envs = {num_envs}")
            if worlds is not None and operator.index(worlds) * agents != num_envs:
                raise ValueError(f"SwarmVectorEnv: num_envs = {num_envs} but worlds * agents = "
                                 f"{operator.index(worlds)} * {agents}")
            worlds = num_envs // agents
        worlds = 1 if worlds is None else worlds
        flat_layout_only(env_kwargs, type(self).__name__)
        self._own_context = context is None
        ctx = Context() if context is None else context
        try:
            self.env = RlEnv(ctx, worlds, agents, **env_kwargs)
        except Exception:
            if self._own_context:
                ctx.close()
            raise
        self.context = ctx
        self.worlds, self.agents = self.env.worlds, self.env.agents
        self.num_envs = self.env.slots
        self.single_observation_space, self.single_action_space = _spaces(self.env, unit_actions)
        self._scale = self.env.action_scale() if unit_actions else None
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None
        self._pending = np.zeros(self.worlds, dtype=bool)  # worlds to reset at the next step
        self._was_reset = False
        self._stats = _EpisodeStats(self.num_envs) if episode_statistics else None

    # ---- per-world flags broadcast to the agents -----------------------------

    def _per_agent(self, flags: np.ndarray) -> np.ndarray:
        return np.repeat(flags, self.agents)

    def world_of(self, index) -> np.ndarray:
        """The world of sub-environment index (slot = world * N + agent)."""
        return np.asarray(index) // self.agents

    # ---- Gymnasium API ------------------------------------------------------

    def reset(self, *, seed: Union[None, int, Sequence[Optional[int]]] = None, options: Optional[dict] = None):
        """Every world to its start.  seed (int): the same bits every time;
        None: a seed drawn from the env's generator; a list of W seeds, one
        per world (not per sub-environment: a world's followers share it;
        None entries drawn): world w starts as reset(seed=seeds[w]) starts
        it.  Returns (obs (W*N, D) float32, infos {})."""
        if options:
            raise ValueError(f"SwarmVectorEnv.reset: no options are supported, got {sorted(options)}")
        if seed is None or isinstance(seed, (int, np.integer)):
            super().reset(seed=None if seed is None else int(seed))  # seeds self.np_random when given
            obs = self.env.reset(int(seed) if seed is not None else _seed_from(self.np_random))
        else:
            seeds = _world_seeds(seed, self.worlds, "SwarmVectorEnv.reset")
            given = [s for s in seeds if s is not None]
            if given:
                self._np_random = np.random.default_rng(given)
            obs = self.env.reset_seeds([s if s is not None else _seed_from(self.np_random) for s in seeds])
        self._pending[:] = False
        self._was_reset = True
        if self._stats is not None:
            self._stats.reset()
        return obs, {}

    def step(self, actions):
        """actions (W*N, 4) float32 (finite; clamped by Eq. 2's kinematics).
        Returns obs (W*N, D) float32, rewards (W*N,) float32, terminations and
        truncations (W*N,) bool (per world, broadcast), infos ({} or, at the
        end of an episode, "episode" / "_episode")."""
        if not self._was_reset:
            raise RuntimeError("SwarmVectorEnv.step: call reset() first")
        if self._scale is not None:
            actions = self.env._actions_in(actions, "SwarmVectorEnv.step").reshape(-1, ACTION_DIM) * self._scale
        obs, rew, term, trunc = self.env.step(actions)  # checks shape and finiteness first
        if self._pending.any():
            obs = self.env.reset_worlds(self._pending)
            slots = self._per_agent(self._pending)
            rew[slots] = 0.0
            term[self._pending] = False
            trunc[self._pending] = False
        self._pending = term | trunc
        term, trunc, infos = self._per_agent(term), self._per_agent(trunc), {}
        if self._stats is not None:
            self._stats.step(rew, term | trunc, infos)
        return obs, rew, term, trunc, infos

    def close_extras(self, **kwargs: Any) -> None:
        self.env.close()
        if self._own_context:
            self.context.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ---- extras for training (whole arrays) ----------------------------------

    def rag_actions(self) -> np.ndarray:
        """The rule-based action generator's actions for the current state (W*N, 4)."""
        return self.env.rag_actions()

    def set_leader_controls(self, controls) -> None:
        self.env.set_leader_controls(controls)


class SwarmWorldEnv(gym.Env):
    """One world of N followers as a single ``gymnasium.Env``: observation
    (N, D) float32, action (N, 4) float32 (one row per follower, the same
    bounds as SwarmVectorEnv's single action), reward the mean of the
    followers' Eq. 14-19 rewards (each one in ``info["rewards"]``),
    terminated / truncated the world's.  What ``gymnasium.make(ENV_ID,
    agents=N)`` gives and what single-agent libraries (Stable-Baselines3)
    take as they are; to train one policy shared by the followers, use
    SwarmVectorEnv.  No autoreset: after an episode ends call reset.
    ``unit_actions``: actions in [-1, 1] (times the action scale inside
    step), as most libraries expect; default env units."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, agents: int = 1, context: Optional[Context] = None, *, episode_statistics: bool = True,
                 unit_actions: bool = False, render_mode: Optional[str] = None, render_size: int = 256,
                 render_extent: float = 40.0, **env_kwargs):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"{type(self).__name__}: render_mode must be None or 'rgb_array', got {render_mode!r}")
        if operator.index(render_size) < 16 or not float(render_extent) > 0:
            raise ValueError(f"{type(self).__name__}: render_size must be >= 16 and render_extent > 0, got "
                             f"{render_size}, {render_extent}")
        flat_layout_only(env_kwargs, type(self).__name__)
        self._own_context = context is None
        ctx = Context() if context is None else context
        try:
            self.env = RlEnv(ctx, 1, agents, **env_kwargs)
        except Exception:
            if self._own_context:
                ctx.close()
            raise
        self.context = ctx
        self.agents = self.env.agents
        obs, act = _spaces(self.env, unit_actions)
        self._scale = self.env.action_scale() if unit_actions else None
        n = self.agents
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, shape=(n,) + obs.shape, dtype=np.float32)
        self.action_space = gym.spaces.Box(np.tile(act.low, (n, 1)), np.tile(act.high, (n, 1)), dtype=np.float32)
        self.render_mode = render_mode
        self.render_size, self.render_extent = int(render_size), float(render_extent)
        self.metadata = dict(self.metadata, render_fps=round(1.0 / self.env.params["dt"]))
        self._statistics = episode_statistics
        self._return, self._length, self._start = 0.0, 0, time.perf_counter()
        self._was_reset = False

    def _obs(self, obs: np.ndarray) -> np.ndarray:
        return obs

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """The world to its start (seed: the same bits every time; None: one
        drawn from the env's generator).  Returns (obs, {})."""
        if options:
            raise ValueError(f"{type(self).__name__}.reset: no options are supported, got {sorted(options)}")
        super().reset(seed=seed)
        obs = self.env.reset(seed if seed is not None else _seed_from(self.np_random))
        self._return, self._length, self._start = 0.0, 0, time.perf_counter()
        self._was_reset = True
        return self._obs(obs), {}

    def step(self, action):
        what = f"{type(self).__name__}.step"
        if not self._was_reset:
            raise RuntimeError(f"{what}: call reset() first")
        a = checked_actions(action, (self.action_space.shape,), what, "(the action space's shape)")
        if not np.isfinite(a).all():
            bad = int(np.flatnonzero((~np.isfinite(a.reshape(-1, ACTION_DIM))).any(axis=1))[0])
            raise ValueError(f"{what}: actions must be finite (NaN or Inf at follower {bad})")
        a = a.reshape(self.agents, ACTION_DIM)
        obs, rew, term, trunc = self.env.step(a if self._scale is None else a * self._scale)
        reward = float(rew.mean())
        terminated, truncated = bool(term[0]), bool(trunc[0])
        info = {"rewards": rew}
        self._return += reward
        self._length += 1
        if self._statistics and (terminated or truncated):
            info["episode"] = {"r": self._return, "l": self._length,
                               "t": round(time.perf_counter() - self._start, 6)}
        return self._obs(obs), reward, terminated, truncated, info

    def render(self):
        """render_mode "rgb_array": the world seen from above (x right, y up),
        (render_size, render_size, 3) uint8, centred on the leader and
        render_extent metres across: box obstacles' footprints grey, the
        followers white 3 x 3 squares, the leader a red 5 x 5 square.
        None when render_mode is None (Gymnasium's convention)."""
        if self.render_mode is None:
            return None
        if not self._was_reset:
            raise RuntimeError(f"{type(self).__name__}.render: call reset() first")
        n = self.render_size
        img = np.zeros((n, n, 3), np.uint8)
        img[:] = (24, 28, 40)
        st = self.env.read_state()
        centre = st["leader_positions"][0, :2].astype(np.float64)
        px = n / self.render_extent

        def pixel(xy):
            d = (np.asarray(xy, np.float64).reshape(-1, 2) - centre) * px
            return np.floor(n / 2 + d[:, 0]).astype(int), np.floor(n / 2 - d[:, 1]).astype(int)

        for box in self.env.layout()["obstacles"]:
            (c0, c1), (r1, r0) = pixel([box[:2] - box[3:5], box[:2] + box[3:5]])
            img[max(r0, 0):max(min(r1 + 1, n), 0), max(c0, 0):max(min(c1 + 1, n), 0)] = (110, 110, 110)
        for xy, half, colour in ((st["positions"][:, :2], 1, (235, 235, 235)),
                                 (st["leader_positions"][:, :2], 2, (230, 40, 40))):
            cols, rows = pixel(xy)
            for c, r in zip(cols, rows):
                r0, r1, c0, c1 = (max(v, 0) for v in (r - half, min(r + half + 1, n), c - half, min(c + half + 1, n)))
                img[r0:r1, c0:c1] = colour
        return img

    def close(self) -> None:
        if not self.env.closed:
            self.env.close()
            if self._own_context:
                self.context.close()


class SwarmSingleEnv(SwarmWorldEnv):
    """One world with one follower with flat spaces: observation (D,),
    action (4,) (SwarmWorldEnv's (1, D) and (1, 4) without the agent axis).
    Neighbours, EFS and three of the five rewards are never exercised with
    one follower: check and train on SwarmWorldEnv(agents=N) or
    SwarmVectorEnv."""

    def __init__(self, context: Optional[Context] = None, **env_kwargs):
        super().__init__(1, context, **env_kwargs)
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, shape=self.observation_space.shape[1:],
                                                dtype=np.float32)
        self.action_space = gym.spaces.Box(self.action_space.low[0], self.action_space.high[0], dtype=np.float32)

    def _obs(self, obs: np.ndarray) -> np.ndarray:
        return obs[0]

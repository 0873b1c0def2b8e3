"""Gymnasium environments over the C API's leader-following environment.

``SwarmVectorEnv`` is a ``gymnasium.vector.VectorEnv`` whose sub-environments
are the followers of W worlds x N agents (num_envs = W * N), all driven by
one shared policy: one ``step`` is one device launch for every world.
``SwarmSingleEnv`` is the 1 x 1 case as a plain ``gymnasium.Env`` (what
``gymnasium.utils.env_checker.check_env`` checks).

Episodes end per world (terminated: a navigation leader passed its last
waypoint; truncated: M steps), so the flags are broadcast to the world's N
agents, and autoreset is per world (``swcl_rl_env_reset_worlds``)."""

from __future__ import annotations

from typing import Any, Optional

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from .._core import Context
from .native_env import ACTION_DIM, RlEnv

__all__ = ["SwarmVectorEnv", "SwarmSingleEnv"]


def _spaces(env: RlEnv):
    obs = gym.spaces.Box(-np.inf, np.inf, shape=(env.obs_dim,), dtype=np.float32)
    s = env.action_scale()
    act = gym.spaces.Box(-s, s, shape=(ACTION_DIM,), dtype=np.float32)
    return obs, act


def _seed_from(rng: np.random.Generator) -> int:
    return int(rng.integers(0, 2**63, dtype=np.int64))


class SwarmVectorEnv(VectorEnv):
    """W worlds x N followers as num_envs = W * N sub-environments.

    Autoreset NEXT_STEP (``gymnasium.make_vec``'s default): the step that
    ends a world returns its last observations with terminated / truncated
    set; the next ``step`` ignores that world's actions, resets it to its
    next episode and returns its first observations with reward 0 and both
    flags false.  (The C step advances every world at once; a finished world
    is stepped once more and then reset, its results discarded.)

    ``context``: a swarmcl.Context (one is created and owned when None);
    other keywords go to RlEnv (scenario, max_steps, efs, ...)."""

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(self, worlds: int = 1, agents: int = 1, context: Optional[Context] = None, **env_kwargs):
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
        self.single_observation_space, self.single_action_space = _spaces(self.env)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None
        self._pending = np.zeros(self.worlds, dtype=bool)  # worlds to reset at the next step
        self._was_reset = False

    # ---- per-world flags broadcast to the agents -----------------------------

    def _per_agent(self, flags: np.ndarray) -> np.ndarray:
        return np.repeat(flags, self.agents)

    def world_of(self, index) -> np.ndarray:
        """The world of sub-environment index (slot = world * N + agent)."""
        return np.asarray(index) // self.agents

    # ---- Gymnasium API ------------------------------------------------------

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Every world to its start.  seed (int): the same bits every time;
        None: a seed drawn from the env's generator.  Returns (obs (W*N, D)
        float32, infos {})."""
        if options:
            raise ValueError(f"SwarmVectorEnv.reset: no options are supported, got {sorted(options)}")
        super().reset(seed=seed)  # seeds self.np_random when seed is given
        c_seed = seed if seed is not None else _seed_from(self.np_random)
        obs = self.env.reset(c_seed)
        self._pending[:] = False
        self._was_reset = True
        return obs, {}

    def step(self, actions):
        """actions (W*N, 4) float32 (finite; clamped by Eq. 2's kinematics).
        Returns obs (W*N, D) float32, rewards (W*N,) float32, terminations and
        truncations (W*N,) bool (per world, broadcast), infos {}."""
        if not self._was_reset:
            raise RuntimeError("SwarmVectorEnv.step: call reset() first")
        obs, rew, term, trunc = self.env.step(actions)  # checks shape and finiteness first
        if self._pending.any():
            obs = self.env.reset_worlds(self._pending)
            slots = self._per_agent(self._pending)
            rew[slots] = 0.0
            term[self._pending] = False
            trunc[self._pending] = False
        self._pending = term | trunc
        return obs, rew, self._per_agent(term), self._per_agent(trunc), {}

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


class SwarmSingleEnv(gym.Env):
    """One world with one follower as a ``gymnasium.Env`` (for check_env and
    single-agent tools).  Not the way to train a swarm: use SwarmVectorEnv."""

    metadata = {"render_modes": []}

    def __init__(self, context: Optional[Context] = None, **env_kwargs):
        self._own_context = context is None
        ctx = Context() if context is None else context
        try:
            self.env = RlEnv(ctx, 1, 1, **env_kwargs)
        except Exception:
            if self._own_context:
                ctx.close()
            raise
        self.context = ctx
        self.observation_space, self.action_space = _spaces(self.env)
        self.render_mode = None

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        c_seed = seed if seed is not None else _seed_from(self.np_random)
        return self.env.reset(c_seed)[0], {}

    def step(self, action):
        a = np.asarray(action, dtype=np.float32).reshape(1, ACTION_DIM) if np.size(action) == ACTION_DIM \
            else np.asarray(action)
        obs, rew, term, trunc = self.env.step(a)
        return obs[0], float(rew[0]), bool(term[0]), bool(trunc[0]), {}

    def close(self) -> None:
        if not self.env.closed:
            self.env.close()
            if self._own_context:
                self.context.close()

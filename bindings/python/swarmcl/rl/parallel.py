"""The leader-following environment as a PettingZoo ``ParallelEnv``: one
world's N followers are the named agents ``follower_0`` ... ``follower_{N-1}``,
each with its own observation (Eq. 11-13), action {v, omega.xyz} (Eq. 2)
and reward (Eq. 14-19); ``state()`` is the world's state.  Needs
``pettingzoo`` (the ``rl`` extra).

The followers of a world start and end together (the leader's path or M
steps), so every agent terminates or truncates on the same step; after that
``agents`` is empty until ``reset``.  For many worlds in one launch use
SwarmVectorEnv (swarmcl.rl.env)."""

from __future__ import annotations

from typing import Optional

import gymnasium as gym
import numpy as np
from pettingzoo import ParallelEnv

from .._core import Context
from .env import _seed_from, _spaces
from .native_env import ACTION_DIM, RlEnv, checked_actions, flat_layout_only

__all__ = ["SwarmParallelEnv"]


class SwarmParallelEnv(ParallelEnv):
    """One world of ``agents`` followers as a PettingZoo ParallelEnv.

    ``context``: a swarmcl.Context (one is created and owned when None);
    other keywords go to RlEnv (scenario, max_steps, efs, ...).  state():
    follower positions (N, 3), headings (N, 3), speeds (N,), then the
    leader's position, heading and speed, flattened to (7 N + 7,) float32."""

    metadata = {"name": "swarmcl_leader_follow_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(self, agents: int = 2, context: Optional[Context] = None, **env_kwargs):
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
        self.possible_agents = [f"follower_{i}" for i in range(self.env.agents)]
        self.agents: list = []
        self._obs_space, self._act_space = _spaces(self.env)
        n = self.env.agents
        self.state_space = gym.spaces.Box(-np.inf, np.inf, shape=(7 * n + 7,), dtype=np.float32)
        self.render_mode = None
        self._rng = np.random.default_rng()

    def observation_space(self, agent):
        return self._obs_space

    def action_space(self, agent):
        return self._act_space

    def _index(self, agent) -> int:
        try:
            return self.possible_agents.index(agent)
        except ValueError:
            raise KeyError(f"SwarmParallelEnv: no agent {agent!r} (agents are follower_0 .. "
                           f"follower_{len(self.possible_agents) - 1})") from None

    def reset(self, seed: Optional[int] = None, options: Optional[dict] = None):
        """The world to its start (seed: the same bits every time; None: one
        drawn from the env's generator).  ``options`` are accepted and
        ignored (PettingZoo's parallel_api_test passes some; this env has
        none).  Returns (observations, infos)."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        obs = self.env.reset(int(seed) if seed is not None else _seed_from(self._rng))
        self.agents = list(self.possible_agents)
        return {a: obs[i] for i, a in enumerate(self.agents)}, {a: {} for a in self.agents}

    def step(self, actions: dict):
        """actions: {agent: (4,) action} for every live agent.  Returns the
        dicts (observations, rewards, terminations, truncations, infos)."""
        if not self.agents:
            raise RuntimeError("SwarmParallelEnv.step: no live agents: call reset() first")
        if not isinstance(actions, dict):
            raise TypeError(f"SwarmParallelEnv.step: actions must be a dict {{agent: action}}, "
                            f"got {type(actions).__name__}")
        missing = [a for a in self.agents if a not in actions]
        extra = [a for a in actions if a not in self.agents]
        if missing or extra:
            raise ValueError(f"SwarmParallelEnv.step: actions need exactly the live agents; missing {missing}, "
                             f"unknown {extra}")
        a = np.empty((self.env.agents, ACTION_DIM), np.float32)
        for name in self.agents:
            a[self._index(name)] = checked_actions(actions[name], ((ACTION_DIM,),), f"SwarmParallelEnv.step ({name})")
        obs, rew, term, trunc = self.env.step(a)  # checks finiteness, naming the agent's slot
        te, tr = bool(term[0]), bool(trunc[0])
        agents = self.agents
        out = ({n: obs[i] for i, n in enumerate(agents)}, {n: float(rew[i]) for i, n in enumerate(agents)},
               {n: te for n in agents}, {n: tr for n in agents}, {n: {} for n in agents})
        if te or tr:
            self.agents = []
        return out

    def state(self) -> np.ndarray:
        st = self.env.read_state()
        p, v = st["positions"], st["velocities"]
        lp, lv = st["leader_positions"][0], st["leader_velocities"][0]
        return np.concatenate([p[:, :3].ravel(), v[:, :3].ravel(), v[:, 3], lp[:3], lv[:3], lv[3:4]]).astype(
            np.float32)

    def close(self) -> None:
        if not self.env.closed:
            self.env.close()
            if self._own_context:
                self.context.close()

"""Algorithm 1 (DDPG with RAG) over the C API's batched environment.

W worlds x N followers share one actor; every env step adds W*N transitions
to the replay buffer and makes one DDPG update (Algorithm 1 lines 19-24).
Every K episodes the leader changes (a new reset seed, hence new headings
and speeds, and a new joystick plan) and the protection flags are cleared
(lines 7-9); with RAG, that change's first episode is driven by the
rule-based action generator and its transitions are protected (lines
12-14), the other K - 1 by the actor plus Gaussian noise (line 16).  Within
a leader's K episodes every episode starts identically (§III-C2).

Checkpoints are taken between episodes and hold everything the next episode
depends on (networks, optimisers, buffer, generators, counters), so a
resumed run continues bit for bit like an uninterrupted one."""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass, field
from typing import Optional

import numpy as np
import torch

from .._core import Context
from .ddpg import DDPG, DDPGConfig, ReplayBuffer, obs_scale
from .export import export_actor
from .native_env import RlEnv

__all__ = ["TrainConfig", "Trainer"]

CHECKPOINT_FORMAT = "swarmcl-ddpg-checkpoint/1"


@dataclass
class TrainConfig:
    worlds: int = 4
    agents: int = 32
    scenario: str = "roaming"
    max_steps: int = 1200          # M (Table 1)
    episodes_per_leader: int = 500  # K (Table 1)
    rag: bool = True               # RAG exploration (Algorithm 1); False: noise only
    efs: bool = True
    seed: int = 1
    # Ours: the joystick leader of "roaming" gets a new random steering
    # direction every leader_turn_every steps (its Δq control, a vector of
    # length leader_turn in the heading units of Eq. 2) and a speed drift of
    # at most leader_du per step; the plan is fixed per leader change.
    leader_turn_every: int = 100
    leader_turn: float = 0.07
    leader_du: float = 0.002
    updates_per_step: int = 1
    # Ours (0: off, the paper's reward): potential-based shaping of the
    # training reward (Ng, Harada & Russell 1999), Phi(s) = -leader_shaping
    # * s_lead^d (observation 7, the distance to the leader): r + gamma
    # (1 - done) Phi(s') - Phi(s).  It leaves the optimal policy unchanged
    # and pays each step's approach to the leader at once instead of through
    # Eq. 17's slow exp(-lambda d).  Evaluations report the env's reward.
    leader_shaping: float = 0.0
    # Ours (None: off): each step's env reward is clipped from below at this
    # for learning (before the shaping).  Eq. 19's -(d - d*)^2 is unbounded:
    # a follower 30 away from its neighbours gets ~ -600, which swamps every
    # other term in the critic's targets (reward clipping as in DQN).
    reward_floor: Optional[float] = None
    eval_seed: int = 987654321     # evaluation episodes: fixed start and leader plan
    env: dict = field(default_factory=dict)  # extra RlEnv parameters

    def to_dict(self) -> dict:
        return asdict(self)


class NStep:
    """n-step returns over synchronous steps of all W*N slots (ours; off by
    default).  The transition of step t is stored when step t + n - 1 is
    done: R = sum_{i<k} gamma^i r_{t+i}, s' = s_{t+k}, k = n, fewer when
    the world terminated first (done = 1, the sum stops there) or the
    episode ended (flush: k = steps left, bootstrapped from the last state).
    The update's target is R + gamma^k (1 - done) Q'(s', pi'(s'))."""

    def __init__(self, n: int, gamma: float):
        self.n, self.gamma = int(n), float(gamma)
        self.pending: list = []   # [obs, act, mask, R (float64), discount, k, done], oldest first

    def push(self, obs, act, rew, done, mask, next_obs) -> list:
        """Adds step t's rewards to every pending sum; returns the rows
        (obs, act, R, s', done, k) of the step that now has n rewards."""
        for p in self.pending:
            live = p[6] == 0          # slots whose world had not terminated
            p[3] += np.where(live, p[4] * rew, 0.0)
            p[6] = np.where(live, done, p[6])
            p[5] += live
            p[4] = np.where(live, p[4] * self.gamma, p[4])
        self.pending.append([obs, act, mask, rew.astype(np.float64), np.full(rew.shape, self.gamma), np.ones(rew.shape),
                             done.astype(np.float32)])
        return [self._row(self.pending.pop(0), next_obs)] if len(self.pending) == self.n else []

    def flush(self, next_obs) -> list:
        rows = [self._row(p, next_obs) for p in self.pending]
        self.pending = []
        return rows

    @staticmethod
    def _row(p, next_obs) -> tuple:
        obs, act, mask, R, _, k, done = p
        return (obs[mask], act[mask], R[mask].astype(np.float32), next_obs[mask], done[mask],
                k[mask].astype(np.float32))


def _u64(*parts: int) -> int:
    return int(np.random.SeedSequence([int(p) for p in parts]).generate_state(1, np.uint64)[0])


class Trainer:
    def __init__(self, context: Context, config: Optional[TrainConfig] = None,
                 ddpg: Optional[DDPGConfig] = None):
        self.config = c = config or TrainConfig()
        self.env = RlEnv(context, c.worlds, c.agents, scenario=c.scenario, max_steps=c.max_steps, efs=c.efs,
                         **c.env)
        self.scale = self.env.action_scale()
        self.rng = np.random.default_rng(c.seed)
        torch.manual_seed(c.seed)
        self.agent = DDPG(self.env.obs_dim, ddpg, obs_std=obs_scale(self.env.obs_dim, self.env.params["r_coh"]))
        d = self.agent.config
        self.buffer = ReplayBuffer(d.buffer_size, self.env.obs_dim, d.max_protected_fraction)
        self.episode = 0            # episodes completed
        self.env_steps = 0
        self.train_seconds = 0.0
        self.history: list = []     # one dict per training episode
        self.evals: list = []       # one dict per evaluation

    # ---- the leader ----------------------------------------------------------

    def _leader_plan(self, key: int) -> Optional[np.ndarray]:
        """(segments, W, 4) joystick controls for one episode, from key alone."""
        c = self.config
        if c.scenario != "roaming":  # navigation leaders follow their waypoints
            return None
        g = np.random.default_rng(key)
        segs = -(-c.max_steps // c.leader_turn_every)
        d = g.normal(size=(segs, c.worlds, 3)) * np.array([1.0, 1.0, 0.25])
        d *= c.leader_turn / np.maximum(np.linalg.norm(d, axis=2, keepdims=True), 1e-9)
        du = g.uniform(-c.leader_du, c.leader_du, size=(segs, c.worlds, 1))
        return np.concatenate([du, d], axis=2).astype(np.float32)

    def _leader_key(self, block: int) -> int:
        return _u64(self.config.seed, 1, block)

    # ---- episodes ------------------------------------------------------------

    def _rollout(self, reset_seed: int, plan, policy: str, learn: bool, protect: bool = False,
                 track_distance: bool = False) -> dict:
        """One episode of every world.  policy: "rag", "actor" (with noise
        when learn) or "greedy" (the actor without noise)."""
        c, env, N = self.config, self.env, self.config.agents
        obs = env.reset(reset_seed)
        alive = np.ones(c.worlds, bool)
        total, count, dist_sum, dist_n, steps = 0.0, 0, 0.0, 0, 0
        noise = self.agent.config.noise
        n = self.agent.config.n_step
        nstep = NStep(n, self.agent.config.gamma) if learn and n > 1 else None
        for t in range(c.max_steps):
            if plan is not None and t % c.leader_turn_every == 0:
                env.set_leader_controls(plan[t // c.leader_turn_every])
            if policy == "rag":
                a_env = env.rag_actions()
                a_net = np.clip(a_env / self.scale, -1.0, 1.0)
            else:
                a_net = self.agent.act(obs)
                if policy == "actor" and learn:
                    a_net = np.clip(a_net + noise * self.rng.standard_normal(a_net.shape).astype(np.float32),
                                    -1.0, 1.0)
                a_env = a_net * self.scale
            obs2, rew, term, trunc = env.step(a_env)
            mask = np.repeat(alive, N)
            if learn:
                done = np.repeat(term, N).astype(np.float32)
                r_learn = rew if c.reward_floor is None else np.maximum(rew, np.float32(c.reward_floor))
                if c.leader_shaping:
                    g = self.agent.config.gamma
                    r_learn = (r_learn + c.leader_shaping * (obs[:, 7] - g * (1.0 - done) * obs2[:, 7])).astype(np.float32)
                if nstep is None:   # Algorithm 1 line 18 as printed
                    self.buffer.add(obs[mask], a_net[mask], r_learn[mask], obs2[mask], done[mask], protect)
                else:
                    for row in nstep.push(obs, a_net, r_learn, done, mask, obs2):
                        self.buffer.add(*row[:5], protect, steps=row[5])
                d = self.agent.config
                if len(self.buffer) >= d.batch_size:
                    for _ in range(c.updates_per_step):
                        self.agent.update(self.buffer.sample(self.rng, d.batch_size))
                self.env_steps += 1
            total += float(rew[mask].sum(dtype=np.float64))
            count += int(mask.sum())
            if track_distance and t % 10 == 9:
                s = env.read_state()
                lp = np.repeat(s["leader_positions"][:, :3], N, axis=0)
                dist = np.linalg.norm(s["positions"][:, :3] - lp, axis=1)
                dist_sum += float(dist[mask].sum())
                dist_n += int(mask.sum())
            alive &= ~term
            steps = t + 1
            obs = obs2
            if not alive.any():
                break
        if nstep is not None:   # the episode's last n - 1 steps: partial returns, bootstrapped from its end
            for row in nstep.flush(obs):
                self.buffer.add(*row[:5], protect, steps=row[5])
        out = {"mean_reward": total / max(count, 1), "steps": steps}
        if track_distance:
            out["mean_leader_distance"] = dist_sum / max(dist_n, 1)
        return out

    def train_episode(self) -> dict:
        """Algorithm 1 lines 5-25 for episode self.episode (0-based)."""
        c, e = self.config, self.episode
        K = c.episodes_per_leader
        block, first = e // K, e % K == 0
        if first:
            self.buffer.clear_protection()        # line 9
        use_rag = c.rag and first                 # line 12
        t0 = time.perf_counter()
        r = self._rollout(self._leader_key(block), self._leader_plan(self._leader_key(block)),
                          "rag" if use_rag else "actor", learn=True, protect=use_rag)
        self.train_seconds += time.perf_counter() - t0
        self.episode += 1
        rec = {"episode": e, "rag": use_rag, "mean_reward": r["mean_reward"], "steps": r["steps"],
               "updates": self.agent.updates, "train_seconds": self.train_seconds,
               "protected": int(self.buffer.protected.sum()), "buffer": len(self.buffer)}
        self.history.append(rec)
        return rec

    def evaluate(self, policy: str = "greedy", episodes: int = 1) -> dict:
        """Mean reward per agent-step and mean follower-leader distance on
        fixed evaluation starts (no learning; the training generators are
        untouched)."""
        rs, ds = [], []
        for k in range(episodes):
            key = _u64(self.config.eval_seed, k)
            r = self._rollout(key, self._leader_plan(_u64(key, 7)), policy, learn=False, track_distance=True)
            rs.append(r["mean_reward"])
            ds.append(r["mean_leader_distance"])
        return {"mean_reward": float(np.mean(rs)), "mean_leader_distance": float(np.mean(ds))}

    def train(self, episodes: Optional[int] = None, budget_seconds: Optional[float] = None,
              eval_every: int = 0, eval_episodes: int = 1, checkpoint: Optional[str] = None,
              checkpoint_every: int = 0, log=None) -> None:
        """Episodes until `episodes` in total are done or the training time
        (evaluations excluded) reaches budget_seconds."""
        if episodes is None and budget_seconds is None:
            raise ValueError("Trainer.train: give episodes or budget_seconds")
        while True:
            if episodes is not None and self.episode >= episodes:
                break
            if budget_seconds is not None and self.train_seconds >= budget_seconds:
                break
            if eval_every and self.episode % eval_every == 0:
                self._record_eval(eval_episodes, log)
            rec = self.train_episode()
            if log:
                log(f"episode {rec['episode']} {'RAG' if rec['rag'] else 'actor'} reward/agent-step "
                    f"{rec['mean_reward']:.3f} updates {rec['updates']} t={rec['train_seconds']:.0f}s")
            if checkpoint and checkpoint_every and self.episode % checkpoint_every == 0:
                self.save(checkpoint)
        if eval_every:
            self._record_eval(eval_episodes, log)
        if checkpoint:
            self.save(checkpoint)

    def _record_eval(self, eval_episodes: int, log) -> None:
        if self.evals and self.evals[-1]["episode"] == self.episode:
            return
        ev = self.evaluate("greedy", eval_episodes)
        ev.update(episode=self.episode, updates=self.agent.updates, train_seconds=self.train_seconds)
        self.evals.append(ev)
        if log:
            log(f"eval after {self.episode} episodes: reward/agent-step {ev['mean_reward']:.3f}, "
                f"leader distance {ev['mean_leader_distance']:.2f}")

    # ---- checkpoints and export ------------------------------------------------

    def state_dict(self) -> dict:
        return {"format": CHECKPOINT_FORMAT, "train_config": self.config.to_dict(),
                "ddpg_config": self.agent.config.to_dict(), "agent": self.agent.state_dict(),
                "buffer": self.buffer.state_dict(), "rng": self.rng.bit_generator.state,
                "torch_rng": torch.get_rng_state(), "episode": self.episode, "env_steps": self.env_steps,
                "train_seconds": self.train_seconds, "history": self.history, "evals": self.evals}

    def save(self, path: str) -> None:
        """Writes the checkpoint atomically (a temporary file, then rename)."""
        tmp = f"{path}.tmp"
        torch.save(self.state_dict(), tmp)
        os.replace(tmp, path)

    @classmethod
    def load(cls, context: Context, path: str) -> "Trainer":
        d = torch.load(path, map_location="cpu", weights_only=False)
        if not isinstance(d, dict) or d.get("format") != CHECKPOINT_FORMAT:
            raise ValueError(f"{path}: not a {CHECKPOINT_FORMAT} checkpoint")
        t = cls(context, TrainConfig(**d["train_config"]), DDPGConfig(**d["ddpg_config"]))
        t.agent.load_state_dict(d["agent"])
        t.buffer.load_state_dict(d["buffer"])
        t.rng.bit_generator.state = d["rng"]
        torch.set_rng_state(d["torch_rng"])
        t.episode, t.env_steps = int(d["episode"]), int(d["env_steps"])
        t.train_seconds = float(d["train_seconds"])
        t.history, t.evals = list(d["history"]), list(d["evals"])
        return t

    def export(self, path: str) -> dict:
        """The actor as a policy-mlp/1 safetensors file (helpers' contract)."""
        c = self.config
        env = dict(self.env.params, scenario=c.scenario, worlds=c.worlds, agents=c.agents)
        by = (f"ddpg{'+rag' if c.rag else ''}, {self.episode} episodes, {self.agent.updates} updates, "
              f"{c.worlds}x{c.agents} agents, seed {c.seed}")
        return export_actor(self.agent.actor, path, self.scale, c.efs, env, by)

    def close(self) -> None:
        self.env.close()


def config_json(trainer: Trainer) -> str:
    return json.dumps({"train": trainer.config.to_dict(), "ddpg": trainer.agent.config.to_dict()}, indent=1)

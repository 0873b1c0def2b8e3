"""DDPG with a rule-based action generator (paper §III-C, Algorithm 1; §IV-A, Fig. 6).

Networks (Fig. 6, with two departures of ours, docs/rl-swarm.md "Training",
"Networks"): the actor 54 -> 128 (relu) -> 256 (relu) -> 64 (linear) -> 4
(tanh), times the env's action scale; the critic the same shape with the
action concatenated to the observation at its input and one output.  The
paper's text ends the actor at the linear 64-neuron layer and names no
tanh: the 64 -> 4 (64 -> 1) output layer and the tanh are ours.
Target copies of both, updated softly with rate tau (Algorithm 1 line 24).

The replay buffer holds (s, a, r, s', done, f) with f the protection flag of
Algorithm 1 (lines 9, 14, 17): protected (RAG) transitions are never
overwritten by unprotected ones; an unprotected write with every slot
protected is dropped.  Actions are stored in the network's units (env
action / action scale, in [-1, 1])."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Optional, Sequence

import numpy as np
import torch
from torch import nn

__all__ = ["DDPGConfig", "Actor", "Critic", "ReplayBuffer", "DDPG", "obs_scale"]


@dataclass
class DDPGConfig:
    """Table 1's values as defaults (the paper's names in comments)."""
    lr_actor: float = 1e-4           # learning rate (actor)
    lr_critic: float = 1e-3          # learning rate (critic)
    gamma: float = 0.98              # discount factor
    buffer_size: int = 10_000        # replay buffer size S
    batch_size: int = 300            # batch size H
    tau: float = 1e-3                # target update rate lambda
    noise: float = 0.05              # exploration noise Psi (std, in the actor's [-1, 1] units)
    hidden: Sequence[int] = field(default_factory=lambda: (128, 256, 64))  # Fig. 6
    # Ours (not in the paper): the largest fraction of the buffer protected
    # RAG transitions may hold (1.0: Algorithm 1 as printed).
    max_protected_fraction: float = 1.0
    # Ours: rewards are multiplied by this before Eq. 5 (Q of order
    # reward / (1 - gamma) otherwise: ~500 for Eq. 14's ~10 per step).
    reward_scale: float = 1.0
    # Ours: weight of a penalty on the actor's squared pre-tanh outputs,
    # keeping tanh out of saturation (where Eq. 6's gradient vanishes).
    preact_penalty: float = 0.0
    # The last layers start in U(-init, init) (original DDPG [133], §7: 3e-3)
    # so that the first actions sit near 0, not at tanh's ends.
    final_init: float = 3e-3
    # Ours: critic-only updates before the actor's first update (the critic
    # learns Q of the seeded experience before Eq. 6 follows its gradient).
    actor_delay: int = 0
    # Ours: weight of a behaviour-cloning term on protected (RAG) rows in the
    # actor's loss, mean over the batch of f * |pi(s) - a|^2 (as in TD3+BC);
    # 0: Algorithm 1 as printed.  Without RAG no row is protected and it is 0.
    bc_weight: float = 0.0
    # Ours, TD3 (Fujimoto et al. 2018), all off by default (Algorithm 1 as
    # printed): twin critics with the smaller target (clipped double Q),
    # target policy smoothing (Gaussian noise of std target_noise, clipped
    # to +-target_noise_clip, on the target actor's action in [-1, 1]) and
    # the actor and both targets updated every policy_delay-th update.
    twin_critics: bool = False
    target_noise: float = 0.0
    target_noise_clip: float = 0.5
    policy_delay: int = 1
    # Ours: n-step returns (the trainer sums n rewards; the buffer keeps how
    # many, k, and the target bootstraps with gamma^k).  1: Eq. 5 as printed.
    n_step: int = 1
    # Ours: the gradient norm of each network is clipped to this (0: off).
    grad_clip: float = 0.0

    def __post_init__(self):
        if self.n_step < 1:
            raise ValueError(f"DDPGConfig: n_step must be >= 1, got {self.n_step}")
        if self.policy_delay < 1:
            raise ValueError(f"DDPGConfig: policy_delay must be >= 1, got {self.policy_delay}")
        if self.target_noise < 0 or self.target_noise_clip < 0 or self.grad_clip < 0:
            raise ValueError("DDPGConfig: target_noise, target_noise_clip and grad_clip must be >= 0")

    def to_dict(self) -> dict:
        d = asdict(self)
        d["hidden"] = list(self.hidden)
        return d


def obs_scale(obs_dim: int, r_coh: float = 18.0) -> np.ndarray:
    """Fixed input scaling (ours; the paper gives none): the observation
    layout of docs/rl-swarm.md divided by typical magnitudes, so every input
    is O(1): speeds and headings 1, leader offset and distance 10, rays and
    the mean neighbour distance R_coh.  Written to the export as obs_std
    (obs_mean 0)."""
    s = np.ones(obs_dim, dtype=np.float32)
    s[4:8] = 10.0          # s_lead^p, s_lead^d
    s[9:51] = r_coh        # 42 rays
    if obs_dim == 54:
        s[53] = r_coh      # mean neighbour distance (EFS)
    return s


def _init_last(net: nn.Sequential, bound: float) -> None:
    if bound > 0:
        with torch.no_grad():
            net[-1].weight.uniform_(-bound, bound)
            net[-1].bias.uniform_(-bound, bound)


def _mlp(sizes: Sequence[int]) -> nn.Sequential:
    layers = []
    for i in range(len(sizes) - 1):
        layers.append(nn.Linear(sizes[i], sizes[i + 1]))
    return nn.Sequential(*layers)


class Actor(nn.Module):
    """pi(s | theta): relu, relu, linear, then tanh on the 4 outputs (Fig. 6's
    layers plus our 64 -> 4 tanh output layer: docs/rl-swarm.md, "Networks")."""

    ACTIVATIONS = ("relu", "relu", "linear", "tanh")

    def __init__(self, obs_dim: int, hidden: Sequence[int] = (128, 256, 64), obs_std=None, final_init: float = 0.0):
        super().__init__()
        self.net = _mlp([obs_dim, *hidden, 4])
        _init_last(self.net, final_init)
        std = torch.as_tensor(obs_std if obs_std is not None else np.ones(obs_dim), dtype=torch.float32)
        self.register_buffer("obs_std", std)

    def activations(self) -> list:
        n = len(self.net)
        return ["relu"] * (n - 2) + ["linear", "tanh"] if n >= 2 else ["tanh"]

    def preactivation(self, obs: torch.Tensor) -> torch.Tensor:
        x = obs / self.obs_std
        n = len(self.net)
        for i, layer in enumerate(self.net):
            x = layer(x)
            if i < n - 2:
                x = torch.relu(x)
        return x

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        return torch.tanh(self.preactivation(obs))


class Critic(nn.Module):
    """Q(s, a | phi): the actor's shape with [s, a] in and one value out."""

    def __init__(self, obs_dim: int, hidden: Sequence[int] = (128, 256, 64), obs_std=None, final_init: float = 0.0):
        super().__init__()
        self.net = _mlp([obs_dim + 4, *hidden, 1])
        _init_last(self.net, final_init)
        std = torch.as_tensor(obs_std if obs_std is not None else np.ones(obs_dim), dtype=torch.float32)
        self.register_buffer("obs_std", std)

    def forward(self, obs: torch.Tensor, act: torch.Tensor) -> torch.Tensor:
        x = torch.cat([obs / self.obs_std, act], dim=1)
        n = len(self.net)
        for i, layer in enumerate(self.net):
            x = layer(x)
            if i < n - 2:
                x = torch.relu(x)
        return x.squeeze(1)


class ReplayBuffer:
    """Experience replay E of size S with protection flags (Algorithm 1).

    Slots are chosen oldest-first among those a write may take: an
    unprotected write only takes unprotected slots; a protected write takes
    unprotected slots first, then (beyond max_protected) the oldest protected
    ones.  Whole batches go in at once (one row per agent)."""

    def __init__(self, size: int, obs_dim: int, max_protected_fraction: float = 1.0):
        if size < 1:
            raise ValueError(f"ReplayBuffer: size must be >= 1, got {size}")
        if not 0.0 <= max_protected_fraction <= 1.0:
            raise ValueError(f"ReplayBuffer: max_protected_fraction must be in [0, 1], got {max_protected_fraction}")
        self.size, self.obs_dim = int(size), int(obs_dim)
        self.max_protected = int(round(max_protected_fraction * size))
        self.obs = np.zeros((size, obs_dim), np.float32)
        self.act = np.zeros((size, 4), np.float32)
        self.rew = np.zeros(size, np.float32)
        self.next_obs = np.zeros((size, obs_dim), np.float32)
        self.done = np.zeros(size, np.float32)
        self.steps = np.ones(size, np.float32)     # k: rewards summed into rew (n-step returns)
        self.protected = np.zeros(size, bool)
        self.stamp = np.full(size, -1, np.int64)   # insertion order; -1: empty
        self.count = 0                              # filled slots
        self.clock = 0                              # writes so far
        self.dropped = 0                            # unprotected writes refused (all protected)

    def __len__(self) -> int:
        return self.count

    def clear_protection(self) -> None:
        """Algorithm 1 line 9: every protection flag to false."""
        self.protected[:] = False

    def _slots_for(self, n: int, protect: bool) -> np.ndarray:
        empty = np.flatnonzero(self.stamp < 0)
        free = self._oldest(np.flatnonzero(~self.protected & (self.stamp >= 0)), max(0, n - empty.size))
        open_ = np.concatenate([empty, free])  # what an unprotected write may take, best first
        if not protect:
            return open_[:n]
        # A protected write: open slots while fewer than max_protected are
        # protected, then the oldest protected ones.
        budget = max(0, self.max_protected - int(self.protected.sum()))
        take = open_[:min(n, budget)]
        prot = self._oldest(np.flatnonzero(self.protected), n - take.size)
        return np.concatenate([take, prot])

    def _oldest(self, slots: np.ndarray, n: int) -> np.ndarray:
        """The n slots of `slots` with the smallest stamps, oldest first (stamps
        are unique: a partial selection, then a sort of those n only, gives
        what a full sort would; a full sort per step costs ~10 ms at 200k)."""
        if n <= 0:
            return slots[:0]
        if n < slots.size:
            slots = slots[np.argpartition(self.stamp[slots], n - 1)[:n]]
        return slots[np.argsort(self.stamp[slots], kind="stable")]

    def add(self, obs, act, rew, next_obs, done, protect: bool, steps=None) -> int:
        """Stores a batch (rows of the same protection flag); returns how many
        were stored (the last ones of the batch win when not all fit).
        steps: rewards summed into each rew (n-step returns; default 1)."""
        n = len(rew)
        if n == 0:
            return 0
        slots = self._slots_for(min(n, self.size), bool(protect))
        k = slots.size
        if k < n:
            self.dropped += n - k
        if k == 0:
            return 0
        src = slice(n - k, n)
        self.obs[slots] = obs[src]
        self.act[slots] = act[src]
        self.rew[slots] = rew[src]
        self.next_obs[slots] = next_obs[src]
        self.done[slots] = done[src]
        self.steps[slots] = 1.0 if steps is None else np.asarray(steps, np.float32)[src]
        self.protected[slots] = bool(protect)
        self.stamp[slots] = self.clock + np.arange(k)
        self.clock += k
        self.count = int((self.stamp >= 0).sum())
        return k

    def sample(self, rng: np.random.Generator, batch: int):
        """(s, a, r, s', done, f, k) of `batch` rows drawn uniformly with replacement."""
        idx = rng.integers(0, self.count, size=batch) if self.count == self.size else \
            np.flatnonzero(self.stamp >= 0)[rng.integers(0, self.count, size=batch)]
        return (self.obs[idx], self.act[idx], self.rew[idx], self.next_obs[idx], self.done[idx],
                self.protected[idx].astype(np.float32), self.steps[idx])

    def state_dict(self) -> dict:
        return {k: getattr(self, k).copy() if isinstance(getattr(self, k), np.ndarray) else getattr(self, k)
                for k in ("obs", "act", "rew", "next_obs", "done", "steps", "protected", "stamp", "count", "clock",
                          "dropped", "max_protected")}

    def load_state_dict(self, d: dict) -> None:
        for k, v in d.items():
            setattr(self, k, np.array(v, copy=True) if isinstance(v, np.ndarray) else v)


class DDPG:
    """The four networks, their optimisers and one update (Eq. 5, Eq. 6)."""

    def __init__(self, obs_dim: int, config: Optional[DDPGConfig] = None, obs_std=None):
        self.config = c = config or DDPGConfig()
        self.obs_dim = obs_dim
        self.actor = Actor(obs_dim, c.hidden, obs_std, c.final_init)
        self.critic = Critic(obs_dim, c.hidden, obs_std, c.final_init)
        self.actor_target = Actor(obs_dim, c.hidden, obs_std)
        self.critic_target = Critic(obs_dim, c.hidden, obs_std)
        self.actor_target.load_state_dict(self.actor.state_dict())     # Algorithm 1 line 2
        self.critic_target.load_state_dict(self.critic.state_dict())
        self.critics = [self.critic]
        self.critic_targets = [self.critic_target]
        if c.twin_critics:  # TD3's second critic (ours; created after the paper's four networks)
            self.critic2 = Critic(obs_dim, c.hidden, obs_std, c.final_init)
            self.critic2_target = Critic(obs_dim, c.hidden, obs_std)
            self.critic2_target.load_state_dict(self.critic2.state_dict())
            self.critics.append(self.critic2)
            self.critic_targets.append(self.critic2_target)
        for p in (*self.actor_target.parameters(), *(q for t in self.critic_targets for q in t.parameters())):
            p.requires_grad_(False)
        self.actor_opt = torch.optim.Adam(self.actor.parameters(), lr=c.lr_actor)
        self.critic_opt = torch.optim.Adam([q for net in self.critics for q in net.parameters()], lr=c.lr_critic)
        self.updates = 0

    @torch.no_grad()
    def act(self, obs: np.ndarray) -> np.ndarray:
        """The actor's actions in [-1, 1] for a batch of observations."""
        return self.actor(torch.from_numpy(np.ascontiguousarray(obs, np.float32))).numpy()

    def target(self, r, s2, d, k) -> torch.Tensor:
        """Eq. 5's y = r + gamma^k (1 - done) Q'(s', pi'(s')) (k = 1 as
        printed; k > 1 for n-step rows).  TD3 options: the smaller of the two
        target critics, and clipped Gaussian noise on pi'(s')."""
        c = self.config
        with torch.no_grad():
            a2 = self.actor_target(s2)
            if c.target_noise > 0:
                eps = (torch.randn_like(a2) * c.target_noise).clamp(-c.target_noise_clip, c.target_noise_clip)
                a2 = (a2 + eps).clamp(-1.0, 1.0)
            q2 = self.critic_targets[0](s2, a2)
            for tgt in self.critic_targets[1:]:
                q2 = torch.minimum(q2, tgt(s2, a2))
            return r + torch.pow(torch.full_like(k, c.gamma), k) * (1.0 - d) * q2

    def update(self, batch) -> dict:
        """One critic step on Eq. 5's Bellman error, one actor step along
        Eq. 6's deterministic policy gradient, then the soft target update
        (the actor and targets every policy_delay-th update; 1 as printed)."""
        c = self.config
        s, a, r, s2, d = (torch.from_numpy(np.ascontiguousarray(x)) for x in batch[:5])
        f = torch.from_numpy(np.ascontiguousarray(batch[5])) if len(batch) > 5 else torch.zeros_like(r)
        k = torch.from_numpy(np.ascontiguousarray(batch[6])) if len(batch) > 6 else torch.ones_like(r)
        r = r * c.reward_scale
        y = self.target(r, s2, d, k)
        critic_loss = sum(torch.mean((y - net(s, a)) ** 2) for net in self.critics)
        self.critic_opt.zero_grad(set_to_none=True)
        critic_loss.backward()
        if c.grad_clip > 0:
            for net in self.critics:
                nn.utils.clip_grad_norm_(net.parameters(), c.grad_clip)
        self.critic_opt.step()

        actor_loss = torch.zeros(())
        delayed = self.updates % c.policy_delay == 0
        if self.updates >= c.actor_delay and delayed:
            pre = self.actor.preactivation(s)
            pi = torch.tanh(pre)
            actor_loss = -self.critic(s, pi).mean()
            if c.preact_penalty > 0:
                actor_loss = actor_loss + c.preact_penalty * (pre ** 2).mean()
            if c.bc_weight > 0:
                actor_loss = actor_loss + c.bc_weight * (f * ((pi - a) ** 2).sum(dim=1)).mean()
            self.actor_opt.zero_grad(set_to_none=True)
            actor_loss.backward()
            if c.grad_clip > 0:
                nn.utils.clip_grad_norm_(self.actor.parameters(), c.grad_clip)
            self.actor_opt.step()

        if delayed:
            with torch.no_grad():  # phi' <- lambda phi + (1 - lambda) phi' (Algorithm 1 line 24)
                pairs = [*zip(self.critics, self.critic_targets), (self.actor, self.actor_target)]
                for net, tgt in pairs:
                    for p, pt in zip(net.parameters(), tgt.parameters()):
                        pt.mul_(1.0 - c.tau).add_(p, alpha=c.tau)
        self.updates += 1
        return {"critic_loss": float(critic_loss.detach()), "actor_loss": float(actor_loss.detach())}

    def _parts(self) -> tuple:
        twin = ("critic2", "critic2_target") if self.config.twin_critics else ()
        return ("actor", "critic", "actor_target", "critic_target", *twin, "actor_opt", "critic_opt")

    def state_dict(self) -> dict:
        d = {k: getattr(self, k).state_dict() for k in self._parts()}
        d["updates"] = self.updates
        return d

    def load_state_dict(self, d: dict) -> None:
        for k in self._parts():
            getattr(self, k).load_state_dict(d[k])
        self.updates = int(d["updates"])

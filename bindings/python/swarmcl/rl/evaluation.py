"""The §IV evaluation metrics of the DRL swarm paper, in NumPy
(drl-swarm-animation-rule-based-action-generator, §IV-B to §IV-D;
docs/rl-swarm.md, "Evaluation (§IV)").

* ``speed_differential``: the average |u_i - u_leader| of Tables 2-3.
* ``inter_agent_distance``: mu and sigma of Eq. 20-21 over the pairs within
  a neighbour radius.
* ``cohesion_repulsion``: the cohesion / repulsion occurrences of Table 4
  (the paper cites Eliot et al. 2018 and gives no formula; our reading
  below).
* ``swarm_rewards``: Eq. 14-19 for a swarm state that is not in the
  environment (the policy model's swarms of Fig. 11), for the followers
  ``rows``; the same arithmetic as the environment's kernel (the test
  compares them).

Pair loops go over all agents in row blocks (``block`` rows at a time), so a
100,000-agent swarm can be measured on a sample of rows without an N^2
matrix."""

from __future__ import annotations

from typing import Optional

import numpy as np

__all__ = ["speed_differential", "inter_agent_distance", "cohesion_repulsion", "swarm_rewards",
           "REWARD_DEFAULTS"]

#: Table 1's weights and docs/rl-swarm.md's lambdas (swcl_rl_env_desc_default).
REWARD_DEFAULTS = dict(w_spd=1.3, w_dir=1.0, w_leader=4.9, w_obs=16.0, w_dist=9.5, l_spd=2.0, l_dir=1.0,
                       l_leader=0.1, r_sep=1.0, r_ali=9.0, r_coh=18.0, dist_target=0.0)


def speed_differential(follower_speeds, leader_speed) -> float:
    """Mean over followers (and frames) of |u_i - u_leader| (Tables 2-3).
    ``follower_speeds`` (..., N) and ``leader_speed`` (...) broadcast."""
    u = np.asarray(follower_speeds, np.float64)
    ul = np.asarray(leader_speed, np.float64)[..., None]
    if u.size == 0:
        raise ValueError("speed_differential: no follower speeds")
    return float(np.mean(np.abs(u - ul)))


def _check_positions(positions, what: str) -> np.ndarray:
    p = np.asarray(positions, np.float64)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) < 2:
        raise ValueError(f"{what}: positions must have shape (N >= 2, 3), got {p.shape}")
    if not np.isfinite(p).all():
        raise ValueError(f"{what}: positions must be finite")
    return p


def _rows(n: int, rows: Optional[np.ndarray]) -> np.ndarray:
    if rows is None:
        return np.arange(n)
    r = np.asarray(rows, np.int64).reshape(-1)
    if r.size == 0 or r.min() < 0 or r.max() >= n:
        raise ValueError(f"rows must be non-empty indices in [0, {n})")
    return r


def _pair_blocks(p: np.ndarray, rows: np.ndarray, block: Optional[int]):
    """(row indices, offsets p_j - p_i (B, N, 3), distances (B, N)) with the
    agent itself at distance inf; B rows at a time (default: ~4 M pairs)."""
    block = block or max(1, min(256, 4_000_000 // len(p)))
    for k in range(0, len(rows), block):
        r = rows[k:k + block]
        off = p[None, :, :] - p[r, None, :]
        d = np.sqrt(np.einsum("bnk,bnk->bn", off, off))
        d[np.arange(len(r)), r] = np.inf
        yield r, off, d


def inter_agent_distance(positions, radius: float, rows=None, block: Optional[int] = None):
    """Eq. 20-21: mu and sigma of ||p_i - p_j|| over every agent i of ``rows``
    (default all) and its neighbours j within ``radius`` (N_nbr^i).  Returns
    (mu, sigma, pairs); (nan, nan, 0) when no agent has a neighbour."""
    p = _check_positions(positions, "inter_agent_distance")
    if not np.isfinite(radius) or radius <= 0:
        raise ValueError(f"inter_agent_distance: radius must be > 0, got {radius}")
    s = s2 = 0.0
    count = 0
    for _, _, d in _pair_blocks(p, _rows(len(p), rows), block):
        near = d[d <= radius]
        s += float(near.sum())
        s2 += float(np.square(near).sum())
        count += near.size
    if count == 0:
        return float("nan"), float("nan"), 0
    mu = s / count
    return mu, float(np.sqrt(max(s2 / count - mu * mu, 0.0))), count


def cohesion_repulsion(positions, r_sep: float = 1.0, r_ali: float = 9.0, r_coh: float = 18.0,
                       w_sep: float = 4.0, w_coh: float = 2.0, rows=None, block: Optional[int] = None):
    """Table 4's occurrences for one frame: (repulsion, cohesion) agent counts.

    Our reading of Eliot et al.'s cohesion/repulsion metric (the DRL paper
    cites it without a formula): each agent's repulsion vector is the RAG's
    separation term (Eq. 8-9, T = -1: (w_sep / N_sep) sum of unit vectors
    away from the neighbours within r_sep) and its cohesion vector the
    attraction term (T = +1: (w_coh / N_coh) sum of unit vectors towards the
    neighbours in (r_ali, r_coh]); an agent is a repulsion occurrence when
    the repulsion vector is the longer one, a cohesion occurrence when the
    cohesion vector is, neither when both are zero.  A stable swarm has the
    two counts close (§IV-C)."""
    p = _check_positions(positions, "cohesion_repulsion")
    if not 0 < r_sep <= r_ali <= r_coh:
        raise ValueError("cohesion_repulsion: radii must satisfy 0 < r_sep <= r_ali <= r_coh")
    rep = coh = 0
    for _, off, d in _pair_blocks(p, _rows(len(p), rows), block):
        unit = off / np.where(np.isfinite(d) & (d > 0), d, np.inf)[..., None]
        sep = d <= r_sep
        att = (d > r_ali) & (d <= r_coh)
        ns, na = sep.sum(1), att.sum(1)
        vr = -(unit * sep[..., None]).sum(1) * (w_sep / np.maximum(ns, 1))[:, None]
        vc = (unit * att[..., None]).sum(1) * (w_coh / np.maximum(na, 1))[:, None]
        lr, lc = np.linalg.norm(vr, axis=1), np.linalg.norm(vc, axis=1)
        rep += int(np.count_nonzero(lr > lc))
        coh += int(np.count_nonzero(lc > lr))
    return rep, coh


def swarm_rewards(positions, headings, speeds, leader_position, rows=None, neighbor_radius: Optional[float] = None,
                  block: Optional[int] = None, **params) -> np.ndarray:
    """Eq. 14-19 (docs/rl-swarm.md "Rewards") of the followers ``rows``
    (default all) of one obstacle-free world: positions (N, 3), unit
    headings (N, 3), speeds (N,), the leader's position (3,).  ``params``
    override REWARD_DEFAULTS.  Neighbours: the other followers within
    ``neighbor_radius`` (default r_coh), as in the environment."""
    unknown = set(params) - set(REWARD_DEFAULTS)
    if unknown:
        raise ValueError(f"swarm_rewards: unknown parameters {sorted(unknown)}")
    c = {**REWARD_DEFAULTS, **params}
    p = _check_positions(positions, "swarm_rewards")
    q = np.asarray(headings, np.float64)
    u = np.asarray(speeds, np.float64).reshape(-1)
    if q.shape != p.shape or u.shape != (len(p),):
        raise ValueError(f"swarm_rewards: headings {q.shape} and speeds {u.shape} must match positions {p.shape}")
    lp = np.asarray(leader_position, np.float64).reshape(3)
    r_nbr = c["r_coh"] if neighbor_radius is None else float(neighbor_radius)
    d_target = c["dist_target"] if c["dist_target"] > 0 else 0.5 * (c["r_ali"] - c["r_sep"])
    rows = _rows(len(p), rows)
    out = np.empty(len(rows))
    k = 0
    for r, _, d in _pair_blocks(p, rows, block):
        nb = d <= r_nbr
        nn = nb.sum(1)
        inv = np.where(nn > 0, 1.0 / np.maximum(nn, 1), 0.0)
        sdu = (np.abs(u[r, None] - u[None, :]) * nb).sum(1)
        dq = np.sqrt(np.einsum("bnk,bnk->bn", q[None, :, :] - q[r, None, :], q[None, :, :] - q[r, None, :]))
        sq = (dq * nb).sum(1)
        sdist = (np.square(np.where(nb, d, d_target) - d_target)).sum(1)
        rew = np.where(nn > 0, c["w_spd"] * np.exp(-c["l_spd"] * sdu * inv) + c["w_dir"] * np.exp(-c["l_dir"] * sq * inv)
                       + c["w_dist"] - sdist * inv, 0.0)
        dl = np.linalg.norm(lp[None, :] - p[r], axis=1)
        rew += c["w_leader"] * np.exp(-c["l_leader"] * (dl + c["r_sep"]))
        out[k:k + len(r)] = rew
        k += len(r)
    return out

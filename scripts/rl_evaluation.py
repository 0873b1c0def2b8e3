#!/usr/bin/env python3
"""The §IV evaluation of the DRL swarm paper (issue 15 item 8;
drl-swarm-animation-rule-based-action-generator, §IV-B to §IV-D):

* control accuracy (Table 2): 90° and 180° turns of a joystick leader to the
  top, bottom, left and right, 200 followers, the average speed
  differential to the leader, rule-based (RAG actions) against the learned
  policies (the shipped behaviour-cloning actor and the DDPG actor);
* the three navigation scenarios (Table 3): quadrilateral, stairway, maze;
* swarm quality (Table 4, Fig. 10): cohesion / repulsion occurrences and the
  inter-agent distance mu / sigma (Eq. 20-21) over time;
* scalability (Fig. 11): policies trained at 200 agents, with and without
  EFS, run by the library's policy model at 200, 600, 1,000 and 100,000
  agents, average reward per agent-step (Eq. 14-19).

Writes docs/rl-evaluation.md (our tables beside the paper's), three PNGs
under docs/images/, the scenario meshes under examples/meshes/ and
bench/results/rl/evaluation.json.

  PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python scripts/rl_evaluation.py
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import sys
import time
from pathlib import Path

import numpy as np

import swarmcl
from machine_info import cpu_model  # scripts/machine_info.py
from result_paths import shown_command, shown_value  # scripts/result_paths.py: no machine's absolute path in results
from swarmcl.rl import RlEnv, default_params
from swarmcl.rl.evaluation import cohesion_repulsion, inter_agent_distance, speed_differential, swarm_rewards
from swarmcl.rl.export import load_policy, policy_actions
from swarmcl.rl.layout import boxes_to_obj

ROOT = Path(__file__).resolve().parents[1]

# The paper's numbers (Tables 2-4).
PAPER_T2 = {("90", "top"): (0.1332, 0.0974), ("90", "bottom"): (0.1458, 0.0842), ("90", "left"): (0.1692, 0.0528),
            ("90", "right"): (0.1260, 0.0644), ("180", "top"): (0.2432, 0.1337), ("180", "bottom"): (0.2016, 0.1287),
            ("180", "left"): (0.3024, 0.1551), ("180", "right"): (0.2754, 0.1698)}
PAPER_T3 = {"quadrilateral": (0.1136, 0.0934), "stairway": (0.3744, 0.1127), "maze": (0.3962, 0.1895)}
PAPER_T4 = {("90", "top"): (103.0, 70.3, 61.7, 68.1), ("90", "bottom"): (99.7, 48.8, 54.7, 61.6),
            ("90", "left"): (109.1, 74.2, 69.9, 76.7), ("90", "right"): (95.8, 49.0, 50.3, 53.4),
            ("180", "top"): (150.6, 129.3, 78.9, 84.6), ("180", "bottom"): (146.1, 57.0, 97.6, 111.4),
            ("180", "left"): (161.7, 85.5, 96.6, 101.6), ("180", "right"): (149.1, 46.3, 84.2, 82.7)}
UP = np.array([0.0, 0.0, 1.0])
COLORS = ("tab:orange", "tab:blue", "tab:green", "tab:purple")


def turn_targets(q0: np.ndarray, direction: str) -> np.ndarray:
    """The 90° heading of a turn from horizontal headings q0 (W, 3): left /
    right about +z, top / bottom towards +z / -z."""
    left = np.cross(UP, q0)
    left /= np.linalg.norm(left, axis=1, keepdims=True)
    return {"left": left, "right": -left, "top": np.tile(UP, (len(q0), 1)),
            "bottom": np.tile(-UP, (len(q0), 1))}[direction]


def actions(env: RlEnv, obs: np.ndarray, policy) -> np.ndarray:
    """The RAG's actions (rule-based, policy None) or the policy's."""
    return env.rag_actions() if policy is None else policy_actions(policy, obs)


def label(method: str) -> str:
    return "rule-based" if method == "rule" else f"`{method}`"


def world_metrics(pos: np.ndarray, speeds: np.ndarray, leader_pos: np.ndarray, leader_speed: float,
                  r_coh: float) -> dict:
    rep, coh = cohesion_repulsion(pos)
    mu, sigma, _ = inter_agent_distance(pos, r_coh)
    return {"speed_diff": speed_differential(speeds, leader_speed), "rep": rep, "coh": coh, "mu": mu, "sigma": sigma,
            "lead": float(np.linalg.norm(pos - leader_pos[None, :], axis=1).mean())}


def control_test(ctx, policy, angle, direction, args) -> dict:
    """One row of Tables 2 and 4: `worlds` recordings (worlds with their own
    starts) of `agents` followers; a straight warm-up, then the turn; the
    metrics over the `record` steps from the turn's start."""
    W, N = args.worlds, args.agents
    env = RlEnv(ctx, W, N, scenario="roaming", max_steps=10**6, efs=policy is None or policy["efs"])
    try:
        obs = env.reset(args.seed)
        r_coh = env.params["r_coh"]
        series, rows = [], []
        q0 = target = None
        passed = np.zeros(W, bool)
        for t in range(args.warmup + args.record):
            st = env.read_state()
            ql = st["leader_velocities"][:, :3].astype(np.float64)
            if t == args.warmup:
                q0 = ql.copy()
                target = turn_targets(q0, direction)
            if t >= args.warmup:
                goal = target
                if angle == "180":  # through the 90° heading, then to the reverse of the start
                    passed |= np.einsum("wk,wk->w", ql, target) > np.cos(np.deg2rad(2.0))
                    goal = np.where(passed[:, None], -q0, target)
                ctl = np.zeros((W, 4), np.float32)
                ctl[:, 1:] = goal - ql
                env.set_leader_controls(ctl)
            obs, _, _, _ = env.step(actions(env, obs, policy))
            st = env.read_state()
            pos, vel, lvel = st["positions"][:, :3], st["velocities"], st["leader_velocities"]
            if t % args.series_every == 0 or t >= args.warmup:
                lpos = st["leader_positions"][:, :3]
                per_world = [world_metrics(pos[w * N:(w + 1) * N], vel[w * N:(w + 1) * N, 3], lpos[w], float(lvel[w, 3]),
                                           r_coh) for w in range(W)]
                if t % args.series_every == 0:
                    series.append({"t": round((t + 1) * env.params["dt"], 3),
                                   "mu": float(np.mean([m["mu"] for m in per_world])),
                                   "sigma": float(np.mean([m["sigma"] for m in per_world]))})
                if t >= args.warmup:
                    rows.append(per_world)
        final_angle = np.degrees(np.arccos(np.clip(np.einsum("wk,wk->w", st["leader_velocities"][:, :3], q0), -1, 1)))
        return {"speed_diff": float(np.mean([[m["speed_diff"] for m in r] for r in rows])),
                "speed_diff_per_world": np.mean([[m["speed_diff"] for m in r] for r in rows], axis=0).tolist(),
                "repulsion": float(np.mean([[m["rep"] for m in r] for r in rows])),
                "cohesion": float(np.mean([[m["coh"] for m in r] for r in rows])),
                "leader_distance": float(np.mean([[m["lead"] for m in r] for r in rows])),
                "leader_turned_deg": float(final_angle.mean()), "series": series}
    finally:
        env.close()


def navigation_test(ctx, policy, scenario, args) -> dict:
    """One row of Table 3: the navigation leader's whole path; metrics per
    step over the worlds not yet finished."""
    W, N = args.nav_worlds, args.agents
    env = RlEnv(ctx, W, N, scenario=scenario, max_steps=args.nav_max_steps,
                efs=policy is None or policy["efs"])
    try:
        obs = env.reset(args.seed)
        layout = env.layout()
        done = np.zeros(W, bool)
        diffs, reps, cohs, lead = [], [], [], []
        track, snapshots = [], []  # world 0, for the figure
        steps = 0
        while not done.all() and steps < args.nav_max_steps:
            obs, _, term, trunc = env.step(actions(env, obs, policy))
            steps += 1
            st = env.read_state()
            track.append(st["leader_positions"][0, :3].copy())
            if steps % 200 == 0 and not done[0]:
                snapshots.append(st["positions"][:N, :3].copy())
            vel, lvel = st["velocities"], st["leader_velocities"]
            for w in np.flatnonzero(~done):
                sl = slice(w * N, (w + 1) * N)
                diffs.append(speed_differential(vel[sl, 3], float(lvel[w, 3])))
                lead.append(float(np.linalg.norm(st["positions"][sl, :3] - st["leader_positions"][w, :3], axis=1).mean()))
                if steps % 10 == 0:
                    rep, coh = cohesion_repulsion(st["positions"][sl, :3])
                    reps.append(rep)
                    cohs.append(coh)
            done |= term | trunc
        return {"speed_diff": float(np.mean(diffs)), "repulsion": float(np.mean(reps)), "cohesion": float(np.mean(cohs)),
                "leader_distance": float(np.mean(lead)), "steps": steps, "finished": bool(done.all()),
                "_figure": {"layout": layout, "track": np.array(track), "snapshots": snapshots}}
    finally:
        env.close()


def _turn(q: np.ndarray, dq: np.ndarray, max_angle: float) -> np.ndarray:
    """Eq. 2's heading update (kernels/lib/rl_common.cl rl_turn) in NumPy."""
    t0 = q + dq
    n = np.linalg.norm(t0, axis=1, keepdims=True)
    t = t0 / np.maximum(n, 1e-30)
    c = np.clip(np.einsum("ik,ik->i", q, t), -1.0, 1.0)
    w = t - c[:, None] * q
    w /= np.maximum(np.linalg.norm(w, axis=1, keepdims=True), 1e-30)
    bent = np.cos(max_angle) * q + np.sin(max_angle) * w
    bent /= np.linalg.norm(bent, axis=1, keepdims=True)
    out = np.where((np.arccos(c) <= max_angle)[:, None], t, bent)
    return np.where(n > 1e-6, out, q)


def _velocity_after(vel: np.ndarray, act: np.ndarray, p: dict) -> np.ndarray:
    """The velocity u' q' an action gives (Eq. 2: the clamps of the kinematics)."""
    u = np.clip(vel[:, 3] + np.clip(act[:, 0], -p["du_max"], p["du_max"]), 0.0, p["u_max"])
    return u[:, None] * _turn(vel[:, :3].astype(np.float64), act[:, 1:].astype(np.float64),
                              np.deg2rad(p["dq_max_deg"]))


def eq19_by_scale(pos: np.ndarray, p: dict, scales) -> list:
    """Eq. 19's term (w_dist - mean over the neighbours within r_coh of
    (d - d_target)^2; 0 without neighbours) averaged over the followers of
    one frame with the swarm scaled by s about its centroid, for each s."""
    d_t = p["dist_target"] if p["dist_target"] > 0 else 0.5 * (p["r_ali"] - p["r_sep"])
    x = pos - pos.mean(axis=0)
    d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
    np.fill_diagonal(d, np.inf)
    out = []
    for sc in scales:
        ds = d * sc
        nb = ds <= p["r_coh"]
        nn = nb.sum(1)
        e = (np.where(nb, ds - d_t, 0.0) ** 2).sum(1)
        out.append(float(np.where(nn > 0, p["w_dist"] - e / np.maximum(nn, 1), 0.0).mean()))
    return out


def crowding_test(ctx, policy, args) -> dict:
    """Why learned swarms crowd (issue 28): `worlds` x `agents` followers
    behind a straight joystick leader; every 10 steps after the warm-up, the
    followers whose nearest neighbour is within r_sep ("crowded": Table 4's
    repulsion occurrences are these) and, for them, how fast the action they
    take moves them away from that neighbour, (v' - v) . e with e the unit
    vector from the neighbour, beside the rule-based action at the same
    state; at the last frame, Eq. 19's term of world 0 with the swarm scaled
    about its centroid (does the reward ask for a denser or sparser swarm?)."""
    W, N = args.worlds, args.agents
    env = RlEnv(ctx, W, N, scenario="roaming", max_steps=10**6, efs=policy is None or policy["efs"])
    try:
        obs = env.reset(args.seed)
        prm = env.params
        crowded, own, rule, nearest = [], [], [], []
        for t in range(args.warmup + args.record):
            act = actions(env, obs, policy)
            if t >= args.warmup and (t - args.warmup) % 10 == 0:
                st = env.read_state()
                rag = env.rag_actions()
                for w in range(W):
                    sl = slice(w * N, (w + 1) * N)
                    x = st["positions"][sl, :3].astype(np.float64)
                    d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
                    np.fill_diagonal(d, np.inf)
                    j = d.argmin(axis=1)
                    dn = d[np.arange(N), j]
                    nearest.append(float(np.median(dn)))
                    c = np.flatnonzero(dn <= prm["r_sep"])
                    crowded.append(len(c) / N)
                    if len(c):
                        e = (x[c] - x[j[c]]) / dn[c, None]
                        vel = st["velocities"][sl][c].astype(np.float64)
                        v0 = vel[:, :3] * vel[:, 3:4]
                        for a, out in ((act[sl][c], own), (rag[sl][c], rule)):
                            out.extend(np.einsum("ik,ik->i", _velocity_after(vel, a, prm) - v0, e).tolist())
            obs, _, _, _ = env.step(act)
        st = env.read_state()
        scales = [round(float(v), 2) for v in np.arange(0.5, 2.01, 0.1)]
        r19 = eq19_by_scale(st["positions"][:N, :3].astype(np.float64), prm, scales)
        best = int(np.argmax(r19))
        return {"crowded": float(np.mean(crowded)), "nearest_median": float(np.mean(nearest)),
                "away_own": float(np.mean(own)) if own else 0.0, "away_rule": float(np.mean(rule)) if rule else 0.0,
                "samples": len(own), "eq19_scales": scales, "eq19": r19, "eq19_best_scale": scales[best],
                "eq19_at_1": r19[scales.index(1.0)], "eq19_best": r19[best]}
    finally:
        env.close()


def leader_plan(steps: int, seed: int) -> np.ndarray:
    """The joystick plan of the scalability runs: a new slow turn every 6 s
    (as in scripts/train_policy_bc.py's roaming data), constant speed."""
    rng = np.random.default_rng(seed)
    plan = np.zeros((steps, 3), np.float32)
    for t in range(0, steps, 60):
        turn = rng.normal(0.0, 0.03, 3)
        turn[2] *= 0.3
        plan[t:t + 60] = turn
    return plan


def _sampled_reward(s, rows) -> float:
    """Eq. 14-19 of the sampled followers of a policy-model swarm, averaged."""
    p, v = s.read_positions(), s.read_velocities()
    lp, _, _ = s.policy_leader()
    u = np.linalg.norm(v, axis=1)
    to_l = lp[None, :] - p
    q = np.where(u[:, None] > 0, v / np.maximum(u, 1e-30)[:, None],
                 to_l / np.maximum(np.linalg.norm(to_l, axis=1, keepdims=True), 1e-30))
    return float(swarm_rewards(p, q, u, lp, rows=rows).mean())


def scalability_run(ctx, weights: Path, n: int, args) -> dict:
    """A policy-model swarm of n agents behind a joystick leader; Eq. 14-19
    rewards of up to `reward_rows` sampled followers at the placement (before
    the first step), every 50 steps, and every 10 steps after the settling
    time `settle_steps`; the measure is the mean of those after settling
    (every size runs the same steps: `big_steps` above 10,000 agents)."""
    steps = args.big_steps if n > 10_000 else args.scal_steps
    radius = 15.0 * (n / 200.0) ** (1.0 / 3.0)  # a 200-agent swarm in a ball of 15 (~4 m spacing), same density
    rng = np.random.default_rng(args.seed)
    x = rng.normal(size=(n, 3))
    x *= (radius * rng.uniform(size=(n, 1)) ** (1 / 3)) / np.linalg.norm(x, axis=1, keepdims=True)
    x[:, 0] -= radius + 2.0
    reach = radius + 0.75 * steps * 0.1 + 60.0
    with swarmcl.Swarm(ctx, agent_count=n, seed=args.seed, domain=((-reach, -reach, -reach), (reach, reach, reach)),
                       interaction_radius=6.17, dt=0.1) as s:
        s.write_positions(x.astype(np.float32))
        s.write_velocities(np.tile(np.float32([0.75, 0, 0]), (n, 1)))
        s.set_policy_model(swarmcl.PolicyModel(weights=str(weights), leader_speed=0.75))
        plan = leader_plan(steps, args.seed)
        rows = None if n <= args.reward_rows else np.sort(rng.choice(n, args.reward_rows, replace=False))
        t0 = time.perf_counter()
        start = _sampled_reward(s, rows)
        series, settled = [], []
        for t in range(steps):
            s.set_policy_leader_controls(0.0, plan[t])
            s.step(1)
            after = t + 1 > args.settle_steps
            if (t + 1) % 50 == 0 or (after and (t + 1) % 10 == 0):
                r = _sampled_reward(s, rows)
                series.append({"step": t + 1, "reward": r})
                if after:
                    settled.append(r)
        return {"agents": n, "steps": steps, "settle_steps": args.settle_steps, "start_reward": start,
                "mean_reward": float(np.mean(settled)), "rewards": series,
                "sampled_rows": n if rows is None else len(rows), "seconds": time.perf_counter() - t0}


def plot_series(control: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for method, color in zip(control, COLORS):
        for key, style in (("90 left", "-"), ("180 top", "--")):
            ser = control[method][key]["series"]
            t = [e["t"] for e in ser]
            name = f"{label(method).strip('`')}, {key.replace(' ', '° ')}"
            axes[0].plot(t, [e["mu"] for e in ser], style, color=color, label=name)
            axes[1].plot(t, [e["sigma"] for e in ser], style, color=color, label=name)
    for ax, name in zip(axes, ("mean inter-agent distance μ (Eq. 20)", "standard deviation σ (Eq. 21)")):
        ax.set_xlabel("time (s); the turn starts at 15 s")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Fig. 10 analogue: 200 followers, neighbours within R_coh = 18")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_scenarios(nav: dict, path: Path) -> None:
    """Fig. 9 analogue: the leader's path, the obstacles and world 0's
    followers every 20 s, rule-based against the learned policy."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    names = list(PAPER_T3)
    fig, axes = plt.subplots(len(nav), len(names), figsize=(5 * len(names), 4 * len(nav)), squeeze=False)
    for row, (method, color) in enumerate(zip(nav, COLORS)):
        for col, name in enumerate(names):
            ax, fig_data = axes[row, col], nav[method][name]["_figure"]
            a, b = (0, 2) if name == "stairway" else (0, 1)  # side view of the stairs, top view else
            for box in fig_data["layout"]["obstacles"]:
                ax.add_patch(Rectangle((box[a] - box[3 + a], box[b] - box[3 + b]), 2 * box[3 + a], 2 * box[3 + b],
                                       color="0.75"))
            wp = fig_data["layout"]["waypoints"]
            ax.plot(wp[:, a], wp[:, b], "g--", lw=1, label="waypoints")
            tr = fig_data["track"]
            ax.plot(tr[:, a], tr[:, b], "k-", lw=1, label="leader")
            for snap in fig_data["snapshots"]:
                ax.plot(snap[:, a], snap[:, b], ".", ms=1.5, color=color)
            ax.set_aspect("equal")
            ax.set_title(f"{name}, {label(method).strip('`')}")
            ax.set_xlabel("x")
            ax.set_ylabel("z" if name == "stairway" else "y")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_scalability(scal: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    xs = [r["agents"] for r in scal["efs"]]
    for key, color in (("efs", "tab:blue"), ("no_efs", "tab:red")):
        name = "with EFS" if key == "efs" else "without EFS"
        ax.plot(range(len(xs)), [r["mean_reward"] for r in scal[key]], "-o", color=color,
                label=f"{name}, after settling")
        if all("start_reward" in r for r in scal[key]):
            ax.plot(range(len(xs)), [r["start_reward"] for r in scal[key]], ":", marker="x", color=color,
                    label=f"{name}, at the placement")
    ax.set_xticks(range(len(xs)), [f"{x:,}" for x in xs])
    ax.set_xlabel("agents (policies trained at 200)")
    ax.set_ylabel("average reward per agent-step (Eq. 14)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.suptitle("Fig. 11 analogue: average reward of policies trained at 200")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def wins(table: dict, keys: list, learned: list) -> dict:
    """For each learned policy, in how many of `keys` its speed differential
    is below the rule-based one's."""
    return {m: sum(table[m][k]["speed_diff"] < table["rule"][k]["speed_diff"] for k in keys) for m in learned}


def scalability_summary(efs: list, no_efs: list) -> str:
    """The Fig. 11 summary sentence, from the numbers alone: rows of the EFS
    and the no-EFS policy ({"agents", "mean_reward"}, one per size, paired by
    size).  Says at how many sizes EFS has the higher reward, whether the gap
    |EFS - no EFS| narrows, widens or neither as the swarm grows (strictly at
    every larger size), and whether both rewards fall with size."""
    if len(efs) != len(no_efs) or any(e["agents"] != n["agents"] for e, n in zip(efs, no_efs)):
        raise ValueError("scalability_summary: the EFS and no-EFS rows must name the same sizes in the same order")
    if not efs:
        raise ValueError("scalability_summary: no sizes")
    rows = sorted(zip(efs, no_efs), key=lambda r: r[0]["agents"])
    sizes = [e["agents"] for e, _ in rows]
    gap = [e["mean_reward"] - n["mean_reward"] for e, n in rows]
    won = sum(g > 0 for g in gap)
    text = (f"the EFS policy has the higher average reward at {won} of {len(gap)} sizes; EFS − no EFS is " +
            ", ".join(f"{g:+.3f} at {n:,}" for g, n in zip(gap, sizes)))
    if len(gap) < 2:
        return text + " (one size: no trend)."
    step = np.diff(np.abs(gap))
    if (step < 0).all():
        trend = "the gap narrows at every larger size"
    elif (step > 0).all():
        trend = "the gap widens at every larger size"
    else:
        trend = "the gap neither narrows nor widens steadily with size"
    if min(gap) < 0 < max(gap):
        trend += " and changes sign"
    falls = all((np.diff([r[k]["mean_reward"] for r in rows]) < 0).all() for k in (0, 1))
    rises = all((np.diff([r[k]["mean_reward"] for r in rows]) > 0).all() for k in (0, 1))
    both = ("; both policies' rewards fall at every larger size" if falls else
            "; both policies' rewards rise at every larger size" if rises else "")
    return f"{text}: {trend}{both}."


def rag_coupling_text(rag) -> str:
    """The RAG's leader coupling as the results recorded it."""
    if not rag:
        return "leader coupling not recorded"
    if rag["rag_leader_pd"]:
        return (f"with the PD leader coupling (k_p {rag['rag_leader_kp']:g}, k_d {rag['rag_leader_kd']:g}; "
                "docs/rl-swarm.md, \"The leader coupling\")")
    return "with the leader as one more Eq. 8 term (the first coupling)"


def placement_summary(efs: list, no_efs: list) -> str:
    """The sentence on what the policies changed from the placement, from the
    numbers: the change per size, and at the largest size whether the settled
    reward is within 5 % of the placement's."""
    parts = []
    for key, rows in (("EFS", efs), ("no EFS", no_efs)):
        parts.append(f"{key} " + ", ".join(f"{r['mean_reward'] - r['start_reward']:+.1f} at {r['agents']:,}"
                                            for r in rows))
    text = "Settled reward minus the placement's: " + "; ".join(parts) + "."
    big = max(efs, key=lambda r: r["agents"])
    big_n = next(r for r in no_efs if r["agents"] == big["agents"])
    rel = max(abs(r["mean_reward"] - r["start_reward"]) / max(abs(r["start_reward"]), 1e-9) for r in (big, big_n))
    if rel < 0.05:
        text += (f"  At {big['agents']:,} agents both settled rewards are within {100 * rel:.1f} % of the placement's "
                 f"({big['start_reward']:.1f} / {big_n['start_reward']:.1f}): at that size the measure is still the "
                 "placement's, not the policy's.")
    else:
        text += (f"  At {big['agents']:,} agents the policies moved the reward by up to {100 * rel:.0f} % of the "
                 "placement's.")
    return text


def crowding_markdown(crowd: dict, a: dict) -> list:
    """The crowding section (issue 28 item 5): the table and the sentences,
    from the numbers."""
    L = ["## Why the learned swarms crowd (Table 4)", "",
         f"{a['worlds']} worlds × {a['agents']} followers behind a straight joystick leader, every 10 steps of the "
         f"{a['record'] * 0.1:g} s after a {a['warmup'] * 0.1:g} s warm-up: the followers whose nearest neighbour "
         "is within R_sep (crowded; Table 4's repulsion occurrences are these), and for them the speed at which "
         "the action they take moves them away from that neighbour in one step, (v' − v) · e with e the unit "
         "vector from the neighbour (Eq. 2's clamps applied), beside the rule-based action at the same states.  "
         "Then Eq. 19's term (w_dist − mean over the neighbours within R_coh of (d − 4)²) of world 0's last "
         "frame with the swarm scaled about its centroid: the scale at which it is highest says whether the "
         "reward asks for a denser (< 1) or sparser (> 1) swarm.", "",
         "| method | crowded followers | median nearest neighbour (m) | away speed, own action | away speed, "
         "rule-based action | Eq. 19 highest at scale (there / at 1) |",
         "|---|---|---|---|---|---|"]
    for m, r in crowd.items():
        L.append(f"| {label(m)} | {100 * r['crowded']:.1f} % | {r['nearest_median']:.2f} | "
                 + (f"{r['away_own']:+.4f} | {r['away_rule']:+.4f}" if r["samples"] else "none crowded | –")
                 + f" | {r['eq19_best_scale']:g} ({r['eq19_best']:.1f} / {r['eq19_at_1']:.1f}) |")
    L.append("")
    for m, r in crowd.items():
        if m == "rule" or not r["samples"]:
            continue
        share = round(100 * r["away_own"] / r["away_rule"]) if r["away_rule"] > 0 else float("nan")
        L.append(f"* {label(m)}: {100 * r['crowded']:.0f} % of its followers are crowded; their own actions move "
                 f"them away from the nearest neighbour at {r['away_own']:+.4f} m/s per step, "
                 f"{share + 0:.0f} % of what the rule-based action does at the same states "
                 f"({r['away_rule']:+.4f}); Eq. 19 is highest at scale {r['eq19_best_scale']:g} of its swarm.")
    rule = crowd.get("rule")
    if rule:
        L.append(f"* rule-based: {100 * rule['crowded']:.1f} % crowded; Eq. 19 is highest at scale "
                 f"{rule['eq19_best_scale']:g} of its swarm ({rule['eq19_best']:.1f} against {rule['eq19_at_1']:.1f} "
                 "as it is).")
    learned = [(m, r) for m, r in crowd.items() if m != "rule" and r["samples"] and r["away_rule"] > 0]
    if learned and rule:
        if all(r["away_own"] < 0.5 * r["away_rule"] for _, r in learned):
            ratios = [r["away_rule"] / r["away_own"] for _, r in learned if r["away_own"] > 0]
            how = (f"{min(ratios):.0f}-{max(ratios):.0f} times as fast as the learned policies' own actions do"
                   if len(ratios) == len(learned) else
                   "where the own actions of " + ", ".join(label(m) for m, r in learned if r["away_own"] <= 0) +
                   " do not move them apart at all (and the others' at under half the speed)")
            kind = lambda x: "denser" if x < 1 else ("sparser" if x > 1 else "as it is")  # noqa: E731
            scales = [r["eq19_best_scale"] for _, r in learned]
            L += ["", f"Reading: at the same states the rule-based action moves crowded followers apart {how}: the "
                  "learned policies have not learned Eq. 8's separation, and nothing in their training asks for it "
                  "strongly.  Behaviour cloning fits the RAG's actions in mean square over all followers, of which "
                  f"few are crowded in a rule-based swarm ({100 * rule['crowded']:.1f} % here; the actors in "
                  "`models/` were trained with the RAG's first leader coupling); DDPG's rewards "
                  "(Eq. 14-19) have no term within R_sep (r_obs is for obstacles), and Eq. 19 over the neighbours "
                  "within R_coh is highest at scale " +
                  ", ".join(f"{r['eq19_best_scale']:g} of {label(m)}'s swarm ({kind(r['eq19_best_scale'])})"
                            for m, r in learned) +
                  (": the reward does not push them apart." if all(x <= 1 for x in scales) else
                   (": a pull apart that the policies do not follow." if all(x > 1 for x in scales) else
                    ": it does not push all of them apart."))]
        else:
            L += ["", "Reading: at least one learned policy separates crowded followers at half the rule-based "
                  "speed or more; the crowding is not explained by a missing separation response alone."]
    L.append("")
    return L


def write_markdown(res: dict, path: Path) -> None:
    c, nav, sc = res["control"], res["navigation"], res["scalability"]
    a = res["args"]
    learned = [m for m in c if m != "rule"]
    L = ["# Evaluation of the DRL swarm against the paper's §IV (issue 15 item 8)", "",
         f"Written by `scripts/rl_evaluation.py` on {res['date']} ({res['cpu']}, {res['device']}); "
         "every number is in `bench/results/rl/evaluation.json`.  Rule-based: the RAG's actions (Eq. 8-10) fed "
         f"to the environment, {rag_coupling_text(res.get('rag'))}.  Learned policies (files in `models/`):", ""]
    L += [f"* {label(m)}: {res['policies'][m]}" for m in learned]
    if res.get("commands"):
        L += ["", "Made by (from the repository root, after the build; each part merges its results into the JSON):",
              ""]
        by_command: dict = {}
        for part, cmd in res["commands"].items():
            by_command.setdefault(cmd, []).append(part)
        L += [f"* {', '.join(parts)}: `{cmd}`" for cmd, parts in by_command.items()]
    L += ["", "Definitions and choices: docs/rl-swarm.md, \"Evaluation (§IV)\".", "",
          "## Control accuracy (Table 2): average speed differential |u_i − u_leader|", "",
          f"{a['worlds']} recordings per test (worlds with their own starts: leader speed in [0.5, 1], "
          f"heading, follower ball), {a['agents']} followers each; {a['warmup'] * 0.1:g} s straight, then the turn "
          f"(4°/step: 2.25 s for 90°, 4.5 s for 180°), measured over the {a['record'] * 0.1:g} s from the turn's "
          "start; then the mean distance to the leader in the same frames.", "",
          "| turn | direction | " + " | ".join(label(m) for m in c) + " | paper: rule-based | paper: proposed | "
          "distance to the leader (" + " / ".join(label(m) for m in c) + ") |",
          "|---|---|" + "---|" * (len(c) + 3)]
    better = wins(c, [" ".join(key) for key in PAPER_T2], learned)
    for key, (pr, pp) in PAPER_T2.items():
        k = " ".join(key)
        L.append(f"| {key[0]}° | {key[1]} | " + " | ".join(f"{c[m][k]['speed_diff']:.4f}" for m in c) +
                 f" | {pr} | {pp} | " + " / ".join(f"{c[m][k]['leader_distance']:.1f}" for m in c) + " |")
    L += ["", "Tests in which a learned policy has the smaller differential than the rule-based one (the paper: "
          "8 of 8): " + ", ".join(f"{label(m)} {better[m]} of 8" for m in learned) + ".", "",
          "## The navigation scenarios (Table 3)", "",
          f"{a['nav_worlds']} worlds of {a['agents']} followers, the whole path (until the leader passes its last "
          "waypoint); speed differential per step over the worlds not yet finished.", "",
          "| scenario | " + " | ".join(label(m) for m in nav) + " | paper: rule-based | paper: proposed | "
          "distance to the leader (" + " / ".join(label(m) for m in nav) + ") | steps |",
          "|---|" + "---|" * (len(nav) + 4)]
    nbetter = wins(nav, list(PAPER_T3), learned)
    for name, (pr, pp) in PAPER_T3.items():
        L.append(f"| {name} | " + " | ".join(f"{nav[m][name]['speed_diff']:.4f}" for m in nav) + f" | {pr} | {pp} | " +
                 " / ".join(f"{nav[m][name]['leader_distance']:.1f}" for m in nav) + f" | {nav['rule'][name]['steps']} |")
    L += ["", "Scenarios in which a learned policy has the smaller differential (the paper: 3 of 3): " +
          ", ".join(f"{label(m)} {nbetter[m]} of 3" for m in learned) + ".", "",
          "![scenarios](images/rl_eval_scenarios.png)", "",
          "The leader's path (black), the waypoints (green) and world 0's followers every 20 s; the stairway "
          "from the side (x-z), the others from above (x-y).  Obstacle meshes: `examples/meshes/rl_stairway.obj`, "
          "`examples/meshes/rl_maze.obj`.", "",
          "## Swarm quality (Table 4): cohesion / repulsion occurrences", "",
          f"Agents per frame (of {a['agents']}) whose repulsion vector (Eq. 8's separation term) is longer than their cohesion "
          "vector (the attraction term), and the reverse, as repulsion / cohesion; mean over the recorded frames "
          "and recordings.", "",
          "| turn | direction | " + " | ".join(label(m) for m in c) + " | paper: rule-based | paper: proposed |",
          "|---|---|" + "---|" * (len(c) + 2)]
    for key, (a1, a2, a3, a4) in PAPER_T4.items():
        k = " ".join(key)
        L.append(f"| {key[0]}° | {key[1]} | " +
                 " | ".join(f"{c[m][k]['repulsion']:.1f} / {c[m][k]['cohesion']:.1f}" for m in c) +
                 f" | {a1} / {a2} | {a3} / {a4} |")
    L += ["", "Navigation scenarios (every 10th frame, repulsion / cohesion): " + "; ".join(
        f"{n}: " + ", ".join(f"{label(m)} {nav[m][n]['repulsion']:.1f} / {nav[m][n]['cohesion']:.1f}" for m in nav)
        for n in PAPER_T3) + ".", "",
          "## Inter-agent distance over time (Eq. 20-21, Fig. 10)", "",
          "![inter-agent distance](images/rl_eval_interagent.png)", "",
          "## Scalability (Fig. 11)", "",
          f"Two policies trained at 200 agents ({sc['trained_by']}), one with EFS and one without, run by the "
          "library's policy model (`swcl_swarm_policy_set_model`, the neighbour grid) at each size: a ball of the "
          "same density (radius 15 m for 200), a joystick leader turning every 6 s; the Eq. 14-19 reward of "
          f"up to {a['reward_rows']:,} sampled followers.  Measured after a settling time: every size runs "
          f"{a['scal_steps']} steps ({a['big_steps']} above 10,000 agents) and the reward is the mean of the "
          f"samples every 10 steps after step {a.get('settle_steps', 50)} "
          f"({a.get('settle_steps', 50) * 0.1:g} s); the reward of the placement itself (before the first step) "
          "beside it, so the table shows what the policy changed.", "",
          "| agents | reward, EFS | reward, no EFS | EFS − no EFS | at the placement (EFS / no EFS) | "
          "seconds (EFS / no EFS) |",
          "|---|---|---|---|---|---|"]
    for e, n in zip(sc["efs"], sc["no_efs"]):
        start = (f"{e['start_reward']:.3f} / {n['start_reward']:.3f}" if "start_reward" in e else "not recorded")
        L.append(f"| {e['agents']:,} | {e['mean_reward']:.3f} | {n['mean_reward']:.3f} | "
                 f"{e['mean_reward'] - n['mean_reward']:+.3f} | {start} | {e['seconds']:.0f} / {n['seconds']:.0f} |")
    L += ["", "![scalability](images/rl_eval_scalability.png)", ""]
    if all("start_reward" in r for r in sc["efs"] + sc["no_efs"]):
        L += [placement_summary(sc["efs"], sc["no_efs"]), ""]
    if "crowding" in res:
        L += crowding_markdown(res["crowding"], a)
    L += [
          "## Summary: does the paper's ordering hold?", "",
          "The paper's ordering: the learned policy beats the rule-based one on control accuracy (8 of 8 turns, "
          "3 of 3 scenarios)."]
    for m in learned:
        holds = better[m] == 8 and nbetter[m] == 3
        L.append(f"* {label(m)}: smaller differential in {better[m]} of 8 turns and {nbetter[m]} of 3 scenarios: "
                 f"the ordering {'holds' if holds else 'does not hold in full'}.")
    L += [f"* Scalability (Fig. 11): {scalability_summary(sc['efs'], sc['no_efs'])}", ""]
    path.write_text("\n".join(L) + "\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--policies", type=Path, nargs="+",
                    default=[ROOT / "models" / "policy_roaming.safetensors",
                             ROOT / "models" / "policy_roaming_ddpg.safetensors"],
                    help="learned policies compared with the rule-based one (each named by its file's stem)")
    ap.add_argument("--policy-efs", type=Path, default=ROOT / "models" / "eval" / "policy_bc200_efs.safetensors")
    ap.add_argument("--policy-no-efs", type=Path, default=ROOT / "models" / "eval" / "policy_bc200_noefs.safetensors")
    ap.add_argument("--worlds", type=int, default=10)
    ap.add_argument("--agents", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=150)
    ap.add_argument("--record", type=int, default=100)
    ap.add_argument("--series-every", type=int, default=5)
    ap.add_argument("--nav-worlds", type=int, default=4)
    ap.add_argument("--nav-max-steps", type=int, default=4000)
    ap.add_argument("--sizes", type=int, nargs="+", default=[200, 600, 1000, 100_000])
    ap.add_argument("--scal-steps", type=int, default=300)
    ap.add_argument("--big-steps", type=int, default=300,
                    help="steps of the runs above 10,000 agents (the same as --scal-steps by default)")
    ap.add_argument("--settle-steps", type=int, default=200,
                    help="scalability: the reward is averaged over the samples after this many steps")
    ap.add_argument("--reward-rows", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--parts", nargs="+", default=["control", "navigation", "scalability", "crowding"],
                    choices=["control", "navigation", "scalability", "crowding"])
    ap.add_argument("--out-json", type=Path, default=ROOT / "bench" / "results" / "rl" / "evaluation.json")
    ap.add_argument("--out-md", type=Path, default=ROOT / "docs" / "rl-evaluation.md")
    ap.add_argument("--figures-dir", type=Path, default=ROOT / "docs" / "images")
    ap.add_argument("--meshes-dir", type=Path, default=ROOT / "examples" / "meshes")
    ap.add_argument("--markdown-only", action="store_true",
                    help="only rewrite --out-md from the results already in --out-json (runs nothing)")
    args = ap.parse_args()
    if "scalability" in args.parts and not args.settle_steps + 10 <= min(args.scal_steps, args.big_steps):
        ap.error(f"--settle-steps {args.settle_steps} leaves no reward sample: it must be at most "
                 f"--scal-steps and --big-steps ({args.scal_steps}, {args.big_steps}) minus 10")

    if args.markdown_only:
        write_markdown(json.loads(args.out_json.read_text()), args.out_md)
        print(f"wrote {args.out_md}")
        return 0
    methods = {"rule": None}
    for path in args.policies:
        pol = load_policy(path)
        pol["efs"] = pol["metadata"].get("swarmcl.efs", "1") == "1"
        methods[path.stem] = pol
    res = json.loads(args.out_json.read_text()) if args.out_json.is_file() else {}
    res.update(date=dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d"), cpu=cpu_model(),
               args=shown_value(vars(args)),
               policies={m: p["metadata"].get("swarmcl.trained_by", "?") for m, p in methods.items() if p})
    command = ("PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python scripts/" +
               shown_command([Path(__file__).name, *sys.argv[1:]]))
    res["commands"] = {**res.get("commands", {}), **{part: command for part in args.parts}}
    if {"control", "navigation", "crowding"} & set(args.parts):
        d = default_params()
        res["rag"] = {k: d[k] for k in ("rag_leader_pd", "rag_leader_kp", "rag_leader_kd")}
    with swarmcl.Context() as ctx:
        dev = ctx.device
        res["device"] = f"{dev.platform_name} {dev.device_name}, {dev.compute_units} compute units"
        if "control" in args.parts:
            res["control"] = {}
            for method, policy in methods.items():
                res["control"][method] = {}
                for angle, direction in PAPER_T2:
                    t0 = time.perf_counter()
                    r = control_test(ctx, policy, angle, direction, args)
                    res["control"][method][f"{angle} {direction}"] = r
                    print(f"control {method:20s} {angle:>3s}° {direction:6s}: speed diff {r['speed_diff']:.4f}, "
                          f"repulsion {r['repulsion']:.1f}, cohesion {r['cohesion']:.1f}, leader distance "
                          f"{r['leader_distance']:.1f}, leader turned "
                          f"{r['leader_turned_deg']:.0f}° ({time.perf_counter() - t0:.0f} s)", flush=True)
        if "navigation" in args.parts:
            res["navigation"] = {}
            for method, policy in methods.items():
                res["navigation"][method] = {}
                for name in PAPER_T3:
                    t0 = time.perf_counter()
                    r = navigation_test(ctx, policy, name, args)
                    res["navigation"][method][name] = r
                    print(f"navigation {method:20s} {name:13s}: speed diff {r['speed_diff']:.4f}, leader distance "
                          f"{r['leader_distance']:.1f}, {r['steps']} steps, finished {r['finished']} "
                          f"({time.perf_counter() - t0:.0f} s)", flush=True)
            plot_scenarios(res["navigation"], args.figures_dir / "rl_eval_scenarios.png")
            for name in PAPER_T3:
                lay = res["navigation"]["rule"][name]["_figure"]["layout"]
                if len(lay["obstacles"]):
                    out = args.meshes_dir / f"rl_{name}.obj"
                    boxes_to_obj(lay["obstacles"], out, comment=f"swarmcl RL scenario '{name}': its box obstacles "
                                 "(swcl_rl_env_get_layout), written by scripts/rl_evaluation.py")
            for method in res["navigation"]:
                for r in res["navigation"][method].values():
                    r.pop("_figure")
        if "crowding" in args.parts:
            res["crowding"] = {}
            for method, policy in methods.items():
                t0 = time.perf_counter()
                r = crowding_test(ctx, policy, args)
                res["crowding"][method] = r
                print(f"crowding {method:20s}: crowded {r['crowded']:.3f}, nearest (median) {r['nearest_median']:.2f}, "
                      f"away speed change own {r['away_own']:+.4f} / rule-based {r['away_rule']:+.4f} "
                      f"({r['samples']} samples), Eq. 19 best at scale {r['eq19_best_scale']} "
                      f"({r['eq19_best']:.1f} against {r['eq19_at_1']:.1f}) ({time.perf_counter() - t0:.0f} s)",
                      flush=True)
        if "scalability" in args.parts:
            tb = load_policy(args.policy_efs)["metadata"].get("swarmcl.trained_by", "?")
            res["scalability"] = {"trained_by": tb, "efs": [], "no_efs": []}
            for key, path in (("efs", args.policy_efs), ("no_efs", args.policy_no_efs)):
                for n in args.sizes:
                    r = scalability_run(ctx, path, n, args)
                    res["scalability"][key].append(r)
                    print(f"scalability {key:6s} {n:>7d} agents: mean reward {r['mean_reward']:.3f} "
                          f"({r['seconds']:.0f} s)", flush=True)
    args.out_json.parent.mkdir(parents=True, exist_ok=True)
    args.out_json.write_text(json.dumps(res, indent=1) + "\n")
    if "control" in args.parts:
        plot_series(res["control"], args.figures_dir / "rl_eval_interagent.png")
    if "scalability" in args.parts:
        plot_scalability(res["scalability"], args.figures_dir / "rl_eval_scalability.png")
    if all(k in res for k in ("control", "navigation", "scalability")):
        write_markdown(res, args.out_md)
        print(f"wrote {args.out_md}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

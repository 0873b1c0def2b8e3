#!/usr/bin/env python3
"""The learning demonstration of issue 15 item 6 (docs/rl-swarm.md, "Training").

Trains the shared follower policy twice on the same budget and seeds, with
the rule-based action generator (Algorithm 1) and without it (noise-only
DDPG), as two processes side by side (one PyTorch thread each, so both see
the same machine), then writes the reward curves (PNG), a JSON record under
bench/results/rl/ and the actors (policy-mlp/1 safetensors).

  PYTHONPATH=bindings/python python scripts/train_rl.py --budget-seconds 600

The budget is each run's wall time of training (evaluations excluded): on
a machine with fewer free cores than runs, use --sequential (one run after
the other, each with the cores alone).  The configuration that learns
(docs/rl-swarm.md, "The learning demonstration"):

  PYTHONPATH=bindings/python taskset -c 1 python scripts/train_rl.py --budget-seconds 600 \
      --sequential --worlds 128 --agents 1 --reward-scale 0.1 --train-args '--buffer-size 200000 \
      --noise 0.2 --tau 0.005 --twin-critics --target-noise 0.2 --policy-delay 2 --n-step 5 --leader-shaping 3'
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

from machine_info import cpu_model  # scripts/machine_info.py
from result_paths import shown_command, shown_path, shown_value  # no machine's absolute path in results

ROOT = Path(__file__).resolve().parents[1]


def reference_rewards(cfg: dict, eval_episodes: int) -> dict:
    """The greedy evaluation's reward for the RAG itself and for the untrained
    actor (the same evaluation starts as the training runs' evaluations)."""
    import torch

    import swarmcl
    from swarmcl.rl.ddpg import DDPGConfig
    from swarmcl.rl.train import TrainConfig, Trainer

    torch.set_num_threads(1)
    with swarmcl.Context() as ctx:
        t = Trainer(ctx, TrainConfig(**cfg), DDPGConfig())
        try:
            return {"rag": t.evaluate("rag", eval_episodes), "untrained_actor": t.evaluate("greedy", eval_episodes)}
        finally:
            t.close()


def swarm_check(cfg: dict, ckpts: dict, worlds: int, agents: int, eval_episodes: int) -> dict:
    """Each trained actor (greedy) and the RAG on the evaluation starts of a
    worlds x agents swarm: whether a policy trained with few followers per
    world still follows the leader among more neighbours."""
    import torch

    import swarmcl
    from swarmcl.rl.ddpg import DDPGConfig
    from swarmcl.rl.train import TrainConfig, Trainer

    torch.set_num_threads(1)
    out = {"worlds": worlds, "agents": agents}
    with swarmcl.Context() as ctx:
        t = Trainer(ctx, TrainConfig(**dict(cfg, worlds=worlds, agents=agents)), DDPGConfig())
        try:
            out["rag_actions"] = t.evaluate("rag", eval_episodes)
            out["untrained_actor"] = t.evaluate("greedy", eval_episodes)
            for name, path in ckpts.items():
                t.agent.actor.load_state_dict(torch.load(path, map_location="cpu", weights_only=False)["agent"]["actor"])
                out[f"actor_{name}"] = t.evaluate("greedy", eval_episodes)
        finally:
            t.close()
    return out


def plot(results: dict, refs: dict, path: Path, title: str, extra: str = "") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for name, color in (("rag", "tab:blue"), ("no_rag", "tab:orange")):
        ev = results[name]["evals"]
        t = [e["train_seconds"] for e in ev]
        label = "DDPG + RAG (Algorithm 1)" if name == "rag" else "DDPG, noise only"
        axes[0].plot(t, [e["mean_reward"] for e in ev], "-o", ms=3, color=color, label=label)
        axes[1].plot(t, [e["mean_leader_distance"] for e in ev], "-o", ms=3, color=color, label=label)
    for key, style, label in (("rag", "--", "RAG actions (reference)"), ("untrained_actor", ":", "untrained actor")):
        axes[0].axhline(refs[key]["mean_reward"], ls=style, color="gray", label=label)
        axes[1].axhline(refs[key]["mean_leader_distance"], ls=style, color="gray", label=label)
    axes[0].set_ylabel("reward per agent-step (Eq. 14), greedy evaluation")
    axes[1].set_ylabel("mean follower-leader distance")
    for ax in axes:
        ax.set_xlabel("training time [s] (evaluations excluded)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    if extra:  # the options both runs share, wrapped under the title
        title += "\n" + "\n".join(textwrap.wrap("both runs: " + extra, 150))
    fig.suptitle(title, fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--budget-seconds", type=float, default=600)
    p.add_argument("--worlds", type=int, default=4)
    p.add_argument("--agents", type=int, default=32)
    p.add_argument("--max-steps", type=int, default=200)
    p.add_argument("--episodes-per-leader", type=int, default=4)
    p.add_argument("--eval-every", type=int, default=4)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--png", default=str(ROOT / "docs/images/rl_reward_curve.png"))
    p.add_argument("--json", default=str(ROOT / f"bench/results/rl/train_{dt.date.today().isoformat()}.json"))
    p.add_argument("--models", default=str(ROOT / "models"), help="folder for the two exported actors")
    p.add_argument("--sequential", action="store_true", help="one run after the other instead of side by side")
    p.add_argument("--reward-scale", type=float, default=0.1, help="DDPGConfig.reward_scale (ours)")
    p.add_argument("--swarm-check", type=int, nargs=2, metavar=("W", "N"), default=(4, 32),
                   help="also evaluate both trained actors (greedy) in W worlds x N followers")
    p.add_argument("--train-args", default="", help="more options for both runs of python -m swarmcl.rl train")
    p.add_argument("--replot", metavar="JSON", help="only redraw --png from a record this script wrote")
    args = p.parse_args()
    if args.replot:
        rec = json.loads(Path(args.replot).read_text())
        plot(rec["runs"], rec["references"], Path(args.png), rec["title"], rec.get("train_args", ""))
        print(f"wrote {args.png}")
        return 0

    common = ["--worlds", str(args.worlds), "--agents", str(args.agents), "--max-steps", str(args.max_steps),
              "--episodes-per-leader", str(args.episodes_per_leader), "--seed", str(args.seed),
              "--budget-seconds", str(args.budget_seconds), "--eval-every", str(args.eval_every), "--threads", "1",
              "--reward-scale", str(args.reward_scale), *args.train_args.split()]
    Path(args.models).mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "bindings/python"), os.environ.get("PYTHONPATH", "")]))
    started = dt.datetime.now(dt.timezone.utc)
    with tempfile.TemporaryDirectory() as tmp:
        runs, procs = {}, {}
        for name, extra in (("rag", []), ("no_rag", ["--no-rag"])):
            out = Path(tmp) / f"{name}.json"
            model = Path(args.models) / f"policy_roaming_ddpg_{name}.safetensors"
            cmd = [sys.executable, "-m", "swarmcl.rl", "train", *common, *extra, "--json", str(out),
                   "--export", str(model), "--checkpoint", str(Path(tmp) / f"{name}.ckpt")]
            runs[name] = (cmd, out, model)
            log = open(Path(tmp) / f"{name}.log", "w")
            procs[name] = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT)
            if args.sequential:
                procs[name].wait()
        for name, proc in procs.items():
            if proc.wait() != 0:
                print(open(Path(tmp) / f"{name}.log").read()[-4000:], file=sys.stderr)
                print(f"train_rl: the {name} run failed ({proc.returncode})", file=sys.stderr)
                return 1
        results = {name: json.loads(out.read_text()) for name, (cmd, out, model) in runs.items()}
        cfg = dict(results["rag"]["train"])
        refs = reference_rewards(cfg, 1)
        swarm = None
        if args.swarm_check and (args.worlds, args.agents) != tuple(args.swarm_check):
            swarm = swarm_check(cfg, {name: Path(tmp) / f"{name}.ckpt" for name in runs}, *args.swarm_check, 1)
    title = (f"roaming, {args.worlds} worlds x {args.agents} followers, M={args.max_steps}, K={args.episodes_per_leader}, "
             f"reward scale {args.reward_scale}, seed {args.seed}, {args.budget_seconds:.0f} s each ({'sequential' if args.sequential else 'side by side'})")
    plot(results, refs, Path(args.png), title, args.train_args.strip())
    record = {
        "what": "scripts/train_rl.py: DDPG with RAG vs noise-only DDPG, same seeds and training-time budget",
        "command": shown_command(sys.argv),
        "cpu": cpu_model(), "cores": os.cpu_count(), "started_utc": started.isoformat(timespec="seconds"),
        "budget_seconds": args.budget_seconds, "references": refs, "swarm_check": swarm, "title": title,
        "train_args": args.train_args.strip(),
        "budget_measure": "wall time of the training episodes (evaluations excluded), per run; "
                          + ("the runs one after the other" if args.sequential else "the two runs side by side"),
        "runs": {name: {"command": " ".join(shown_value(a) for a in runs[name][0][1:]),
                        "model": shown_path(runs[name][2]),
                        **results[name]} for name in runs},
    }
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(record, indent=1))
    for name in ("rag", "no_rag"):
        ev = results[name]["evals"]
        print(f"{name}: {len(results[name]['episodes'])} episodes, {results[name]['updates']} updates; greedy reward "
              f"{ev[0]['mean_reward']:.3f} -> {ev[-1]['mean_reward']:.3f} (best {max(e['mean_reward'] for e in ev):.3f}), "
              f"leader distance {ev[0]['mean_leader_distance']:.2f} -> {ev[-1]['mean_leader_distance']:.2f}")
    print(f"references: RAG {refs['rag']}, untrained actor {refs['untrained_actor']}")
    if swarm:
        print(f"swarm check ({swarm['worlds']} x {swarm['agents']}, greedy): "
              + ", ".join(f"{k} {v['mean_reward']:.3f} / distance {v['mean_leader_distance']:.2f}"
                          for k, v in swarm.items() if isinstance(v, dict)))
    print(f"wrote {args.png}, {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

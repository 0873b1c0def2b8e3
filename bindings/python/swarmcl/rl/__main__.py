"""``python -m swarmcl.rl train ...``: Algorithm 1 (DDPG with RAG) from the
command line, with checkpoints that resume and a policy export
(docs/rl-swarm.md, "Training").  Needs swarmcl[rl] (PyTorch)."""

from __future__ import annotations

import argparse
import json
import os
import sys


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m swarmcl.rl", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)
    t = sub.add_parser("train", help="train a shared follower policy (Algorithm 1)")
    t.add_argument("--worlds", type=int, default=4)
    t.add_argument("--agents", type=int, default=32)
    t.add_argument("--scenario", default="roaming")
    t.add_argument("--max-steps", type=int, default=1200, help="M, steps per episode (Table 1: 1200)")
    t.add_argument("--episodes-per-leader", type=int, default=500, help="K (Table 1: 500)")
    t.add_argument("--no-rag", action="store_true", help="exploration noise only (no rule-based action generator)")
    t.add_argument("--no-efs", action="store_true", help="51 observations (the EFS ablation)")
    t.add_argument("--seed", type=int, default=1)
    t.add_argument("--episodes", type=int, help="stop after this many episodes in total")
    t.add_argument("--budget-seconds", type=float, help="stop when the training time reaches this")
    t.add_argument("--eval-every", type=int, default=0, help="evaluate the greedy actor every this many episodes")
    t.add_argument("--buffer-size", type=int, default=10_000)
    t.add_argument("--batch-size", type=int, default=300)
    t.add_argument("--max-protected-fraction", type=float, default=1.0)
    t.add_argument("--reward-scale", type=float, default=1.0)
    t.add_argument("--preact-penalty", type=float, default=0.0)
    t.add_argument("--tau", type=float, default=1e-3)
    t.add_argument("--lr-actor", type=float, default=1e-4)
    t.add_argument("--lr-critic", type=float, default=1e-3)
    t.add_argument("--actor-delay", type=int, default=0)
    t.add_argument("--bc-weight", type=float, default=0.0)
    t.add_argument("--noise", type=float, default=0.05, help="exploration noise std (Table 1: 0.05)")
    t.add_argument("--gamma", type=float, default=0.98, help="discount factor (Table 1: 0.98)")
    t.add_argument("--twin-critics", action="store_true", help="TD3's clipped double Q (ours)")
    t.add_argument("--target-noise", type=float, default=0.0, help="TD3's target policy smoothing std (ours)")
    t.add_argument("--target-noise-clip", type=float, default=0.5)
    t.add_argument("--policy-delay", type=int, default=1, help="actor and targets every d-th update (TD3: 2)")
    t.add_argument("--n-step", type=int, default=1, help="n-step returns (ours; 1 = Eq. 5)")
    t.add_argument("--grad-clip", type=float, default=0.0, help="gradient norm clip per network (ours; 0 = off)")
    t.add_argument("--updates-per-step", type=int, default=1, help="DDPG updates per env step (Algorithm 1: 1)")
    t.add_argument("--leader-shaping", type=float, default=0.0,
                   help="potential-based shaping -beta * leader distance of the training reward (ours; 0 = off)")
    t.add_argument("--reward-floor", type=float, default=None,
                   help="clip each step's env reward from below at this for learning (ours; default off)")
    t.add_argument("--env", action="append", default=[], metavar="KEY=VALUE",
                   help="an RlEnv parameter (e.g. w_leader=20, l_leader=0.05); repeatable")
    t.add_argument("--checkpoint", help="checkpoint file (written at the end and every --checkpoint-every episodes)")
    t.add_argument("--checkpoint-every", type=int, default=0)
    t.add_argument("--resume", action="store_true", help="continue from --checkpoint")
    t.add_argument("--export", help="write the actor here (policy-mlp/1 safetensors)")
    t.add_argument("--json", help="write the configuration, episode and evaluation records here")
    t.add_argument("--threads", type=int, default=1, help="PyTorch CPU threads")
    t.add_argument("--device", help="OpenCL device (index or name part)")
    t.add_argument("--quiet", action="store_true")
    return p


def _env_params(items) -> dict:
    """--env KEY=VALUE pairs as RlEnv keywords (numbers; RlEnv names a bad key)."""
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise SystemExit(f"swarmcl.rl: --env expects KEY=VALUE, got {item!r}")
        try:
            out[key] = int(value) if key == "max_steps" else float(value)
        except ValueError:
            raise SystemExit(f"swarmcl.rl: --env {key}: not a number: {value!r}") from None
    return out


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    import torch

    from .. import Context
    from .ddpg import DDPGConfig
    from .train import TrainConfig, Trainer

    torch.set_num_threads(max(1, args.threads))
    log = None if args.quiet else (lambda s: print(s, flush=True))
    with Context(args.device) as ctx:
        if args.resume:
            if not args.checkpoint or not os.path.isfile(args.checkpoint):
                print(f"swarmcl.rl: --resume needs an existing --checkpoint (got {args.checkpoint!r})", file=sys.stderr)
                return 2
            trainer = Trainer.load(ctx, args.checkpoint)
        else:
            tc = TrainConfig(worlds=args.worlds, agents=args.agents, scenario=args.scenario, max_steps=args.max_steps,
                             episodes_per_leader=args.episodes_per_leader, rag=not args.no_rag, efs=not args.no_efs,
                             seed=args.seed, updates_per_step=args.updates_per_step,
                             leader_shaping=args.leader_shaping, reward_floor=args.reward_floor, env=_env_params(args.env))
            dc = DDPGConfig(buffer_size=args.buffer_size, batch_size=args.batch_size,
                            max_protected_fraction=args.max_protected_fraction, reward_scale=args.reward_scale,
                            preact_penalty=args.preact_penalty, tau=args.tau,
                            actor_delay=args.actor_delay, bc_weight=args.bc_weight,
                            lr_actor=args.lr_actor, lr_critic=args.lr_critic, noise=args.noise, gamma=args.gamma,
                            twin_critics=args.twin_critics, target_noise=args.target_noise,
                            target_noise_clip=args.target_noise_clip, policy_delay=args.policy_delay,
                            n_step=args.n_step, grad_clip=args.grad_clip)
            trainer = Trainer(ctx, tc, dc)
        try:
            trainer.train(episodes=args.episodes, budget_seconds=args.budget_seconds, eval_every=args.eval_every,
                          checkpoint=args.checkpoint, checkpoint_every=args.checkpoint_every, log=log)
            if args.export:
                trainer.export(args.export)
            if args.json:
                with open(args.json, "w") as f:
                    json.dump({"train": trainer.config.to_dict(), "ddpg": trainer.agent.config.to_dict(),
                               "episodes": trainer.history, "evals": trainer.evals,
                               "updates": trainer.agent.updates, "env_steps": trainer.env_steps,
                               "train_seconds": trainer.train_seconds, "torch_threads": torch.get_num_threads()},
                              f, indent=1)
        finally:
            trainer.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Behaviour cloning of the rule-based action generator (RAG, Eq. 8-10 of
drl-swarm-animation-rule-based-action-generator) into the paper's actor MLP
(§IV-A, Fig. 6: 54 -> 128 (relu) -> 256 (relu) -> 64 (linear) -> 4 (tanh)),
saved as a policy weights file (docs/rl-swarm.md, "Policy model").

This is NOT the paper's DDPG training (issue 15 item 6): it exists so the
policy model works out of the box; the shipped file
models/policy_roaming.safetensors imitates the RAG and is to be replaced by a
DDPG-trained actor.

Data: the batched environment (swcl_rl_env_* through cffi) rolled out with
RAG actions plus exploration noise (so states off the rule-based path are
seen), labelled with the clean RAG action of each state; roaming (joystick
leader with random slow turns and speed changes) and quadrilateral
(navigation).  Fit: NumPy, Adam, minibatches, MSE on the actions divided by
the action scale (the tanh range).

    PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build \\
        nice -n 10 build/venv/bin/python scripts/train_policy_bc.py --out models/policy_roaming.safetensors

(build/venv is the virtual environment scripts/test.sh makes; any Python with
NumPy and the package's dependencies does.)
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np
from safetensors.numpy import save_file

from swarmcl._native import ffi, lib
from swarmcl.errors import check

ACTION_SCALE = np.array([0.1, 0.0699, 0.0699, 0.0699], np.float32)  # du_max; 2 sin(2 deg) ~ |q'' - q| at 4 deg
WIDTHS = [128, 256, 64, 4]
ACTS = ["relu", "relu", "linear", "tanh"]


def fptr(a):
    return ffi.cast("float*", a.ctypes.data)


def rollout(ctx, scenario, worlds, agents, steps, every, noise, seed, rng, efs=True):
    d = ffi.new("swcl_rl_env_desc*", lib.swcl_rl_env_desc_default())
    d.worlds, d.agents = worlds, agents
    d.efs = 1 if efs else 0
    dim = 54 if efs else 51
    name = ffi.new("char[]", scenario.encode())
    d.scenario = name
    env = ffi.new("swcl_rl_env*")
    check(lib.swcl_rl_env_create(ctx[0], d, env))
    try:
        n = worlds * agents
        obs = np.zeros((n, dim), np.float32)
        act = np.zeros((n, 4), np.float32)
        ctl = np.zeros((worlds, 4), np.float32)
        check(lib.swcl_rl_env_reset(env[0], seed, fptr(obs), obs.size))
        xs, ys = [], []
        turn = np.zeros((worlds, 3), np.float32)
        for t in range(steps):
            if scenario == "roaming":
                if t % 60 == 0:  # a new slow turn and speed target every 6 s
                    turn = rng.normal(0.0, 0.03, (worlds, 3)).astype(np.float32)
                    turn[:, 2] *= 0.3
                    target = rng.uniform(0.4, 1.6, worlds).astype(np.float32)
                st_l = np.zeros((worlds, 4), np.float32)
                lv = np.zeros((worlds, 4), np.float32)
                check(lib.swcl_rl_env_read_state(env[0], ffi.NULL, 0, ffi.NULL, 0, ffi.NULL, fptr(lv), lv.size))
                ctl[:, 0] = np.clip(target - lv[:, 3], -0.1, 0.1)
                ctl[:, 1:] = turn
                check(lib.swcl_rl_env_set_leader_controls(env[0], fptr(ctl), ctl.size))
            check(lib.swcl_rl_env_rag_actions(env[0], fptr(act), act.size))
            if t % every == 0:
                xs.append(obs.copy())
                ys.append(act.copy())
            noisy = act + rng.normal(0.0, 1.0, act.shape).astype(np.float32) * noise * ACTION_SCALE
            term = np.zeros(worlds, np.uint8)
            trunc = np.zeros(worlds, np.uint8)
            check(lib.swcl_rl_env_step(env[0], fptr(noisy), noisy.size, fptr(obs), obs.size, ffi.NULL, 0,
                                       ffi.cast("uint8_t*", term.ctypes.data), ffi.cast("uint8_t*", trunc.ctypes.data),
                                       worlds))
            if term.any() or trunc.any():
                mask = (term | trunc).astype(np.uint8)
                check(lib.swcl_rl_env_reset_worlds(env[0], ffi.cast("uint8_t*", mask.ctypes.data), worlds,
                                                   fptr(obs), obs.size))
        return np.concatenate(xs), np.concatenate(ys)
    finally:
        lib.swcl_rl_env_destroy(env[0])


class Mlp:
    def __init__(self, sizes, rng):
        self.W, self.b = [], []
        for i in range(len(sizes) - 1):
            fan_in = sizes[i]
            self.W.append((rng.normal(0, np.sqrt(2.0 / fan_in), (sizes[i + 1], fan_in))).astype(np.float32))
            self.b.append(np.zeros(sizes[i + 1], np.float32))

    def forward(self, x):
        hs = [x]
        for i, (W, b) in enumerate(zip(self.W, self.b)):
            z = hs[-1] @ W.T + b
            a = ACTS[i]
            hs.append(np.maximum(z, 0) if a == "relu" else (np.tanh(z) if a == "tanh" else z))
        return hs

    def grads(self, x, y):
        hs = self.forward(x)
        out = hs[-1]
        g = 2.0 * (out - y) / y.size
        gW, gb = [None] * len(self.W), [None] * len(self.W)
        for i in reversed(range(len(self.W))):
            a = ACTS[i]
            if a == "tanh":
                g = g * (1.0 - hs[i + 1] ** 2)
            elif a == "relu":
                g = g * (hs[i + 1] > 0)
            gW[i] = g.T @ hs[i]
            gb[i] = g.sum(0)
            g = g @ self.W[i]
        return float(np.mean((out - y) ** 2)), gW, gb


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="models/policy_roaming.safetensors")
    ap.add_argument("--worlds", type=int, default=24)
    ap.add_argument("--agents", type=int, default=100)
    ap.add_argument("--steps", type=int, default=900)
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--noise", type=float, default=0.6, help="exploration noise, in action-scale units")
    ap.add_argument("--epochs", type=int, default=12)
    ap.add_argument("--batch", type=int, default=512)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-efs", action="store_true",
                    help="observations without the embedded swarm features (51 floats; the ablation of Fig. 11)")
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    ctx = ffi.new("swcl_context*")
    cd = ffi.new("swcl_context_desc*", lib.swcl_context_desc_default())
    check(lib.swcl_context_create(cd, ctx))
    t0 = time.time()
    efs = not args.no_efs
    data = [rollout(ctx, "roaming", args.worlds, args.agents, args.steps, args.every, args.noise, args.seed, rng, efs),
            rollout(ctx, "quadrilateral", args.worlds // 2, args.agents, args.steps, args.every, args.noise,
                    args.seed + 1, rng, efs)]
    X = np.concatenate([d[0] for d in data])
    Y = np.clip(np.concatenate([d[1] for d in data]) / ACTION_SCALE, -0.995, 0.995).astype(np.float32)
    print(f"{len(X)} samples in {time.time() - t0:.0f} s")
    mean = X.mean(0).astype(np.float32)
    std = np.maximum(X.std(0), 1e-2).astype(np.float32)
    Xn = ((X - mean) / std).astype(np.float32)
    perm = rng.permutation(len(Xn))
    hold = perm[: len(Xn) // 20]
    train = perm[len(Xn) // 20:]
    net = Mlp([X.shape[1]] + WIDTHS, rng)
    m = [np.zeros_like(p) for p in net.W + net.b]
    v = [np.zeros_like(p) for p in net.W + net.b]
    step = 0
    b1, b2, eps = 0.9, 0.999, 1e-8
    for epoch in range(args.epochs):
        lr = args.lr * (0.5 ** (epoch // 4))
        rng.shuffle(train)
        losses = []
        for k in range(0, len(train), args.batch):
            idx = train[k:k + args.batch]
            loss, gW, gb = net.grads(Xn[idx], Y[idx])
            losses.append(loss)
            step += 1
            params = net.W + net.b
            for j, g in enumerate(gW + gb):
                m[j] = b1 * m[j] + (1 - b1) * g
                v[j] = b2 * v[j] + (1 - b2) * g * g
                mh = m[j] / (1 - b1 ** step)
                vh = v[j] / (1 - b2 ** step)
                params[j] -= (lr * mh / (np.sqrt(vh) + eps)).astype(np.float32)
        held = float(np.mean((net.forward(Xn[hold])[-1] - Y[hold]) ** 2))
        print(f"epoch {epoch}: train mse {np.mean(losses):.5f}, held-out mse {held:.5f} "
              f"(target variance {float(Y[hold].var()):.5f})", flush=True)
    tensors = {}
    for i, (W, b) in enumerate(zip(net.W, net.b)):
        tensors[f"layers.{i}.weight"] = np.ascontiguousarray(W, np.float32)
        tensors[f"layers.{i}.bias"] = np.ascontiguousarray(b, np.float32)
    tensors["obs_mean"] = mean
    tensors["obs_std"] = std
    env = {"scenarios": ["roaming", "quadrilateral"], "r_sep": 1, "r_ali": 9, "r_coh": 18, "dt": 0.1,
           "du_max": 0.1, "dq_max_deg": 4, "u_max": 3, "body_radius": 0.5, "agents": args.agents}
    meta = {
        "swarmcl.format": "policy-mlp/1",
        "swarmcl.activations": ",".join(ACTS),
        "swarmcl.action_scale": ",".join(f"{s:g}" for s in ACTION_SCALE),
        "swarmcl.efs": "1" if efs else "0",
        "swarmcl.env": json.dumps(env),
        "swarmcl.trained_by": (f"behaviour cloning of RAG (Eq. 8-10), scripts/train_policy_bc.py: "
                               f"{len(X)} samples ({args.worlds} roaming + {args.worlds // 2} quadrilateral worlds x "
                               f"{args.agents} agents x {args.steps} steps, noise {args.noise}), {args.epochs} epochs "
                               f"Adam, seed {args.seed}, EFS {'on' if efs else 'off'}"),
    }
    save_file(tensors, args.out, metadata=meta)
    print(f"wrote {args.out}")
    lib.swcl_context_destroy(ctx[0])


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The policy model's MLP on a GPU against cuBLAS (issue 29's MLP peer, on the
device): the shipped actor's layers (shapes, weights, activations,
normalisation and action scale from models/policy_roaming.safetensors) on N
observations resident on the GPU, run by PyTorch in float32 with TF32 off
(cuBLAS sgemm, the same arithmetic class as the library's fma chains), timed
with CUDA events.  Two figures per N: the whole forward pass (normalise,
x W^T + b and the activation per layer, scale) and the layers' matrix
products alone.  policy_bench, in the same GPU run (scripts/gpu-check.sh),
times the library's MLP on the device (`mlp_ms`).

    python3 bench/policy_mlp_gpu_peer.py --out FILE [--agents 100000,1000000] [--repeats 10]

Needs torch with CUDA (the GPU machine's image has it); exits 77 without.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))

from policy_mlp_bench import read_policy  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--agents", default="100000,1000000")
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--weights", default=os.path.join(ROOT, "models", "policy_roaming.safetensors"))
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    try:
        import torch
    except ImportError:
        print("policy_mlp_gpu_peer: no torch here", file=sys.stderr)
        return 77
    if not torch.cuda.is_available():
        print("policy_mlp_gpu_peer: torch sees no CUDA device", file=sys.stderr)
        return 77
    torch.backends.cuda.matmul.allow_tf32 = False
    torch.backends.cudnn.allow_tf32 = False
    dev = torch.device("cuda")
    p = read_policy(args.weights)
    layers = [(torch.tensor(w.copy(), device=dev), torch.tensor(b.copy(), device=dev)) for w, b in p["layers"]]
    acts = p["activations"]
    scale = torch.tensor(p["scale"].copy(), device=dev)
    norm = None if p["norm"] is None else tuple(torch.tensor(a.copy(), device=dev) for a in p["norm"])
    macs = sum(w.shape[0] * w.shape[1] for w, _ in layers)
    obs_dim = layers[0][0].shape[1]

    def forward(x):
        if norm is not None:
            x = (x - norm[0]) / norm[1]
        for (w, b), act in zip(layers, acts):
            x = torch.addmm(b, x, w.t())
            if act == "relu":
                x = torch.relu(x)
            elif act == "tanh":
                x = torch.tanh(x)
        return x * scale

    def products(x):
        for w, _ in layers:
            x = x @ w.t()
        return x

    def timed(fn, x):
        fn(x)  # warm-up (cuBLAS picks its kernels)
        torch.cuda.synchronize()
        ms = []
        for _ in range(args.repeats):
            a, b = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
            a.record()
            fn(x)
            b.record()
            torch.cuda.synchronize()
            ms.append(a.elapsed_time(b))
        ms.sort()
        return ms[len(ms) // 2]

    rows = []
    name = torch.cuda.get_device_name(0)
    print(f"policy_mlp_gpu_peer on {name}: torch {torch.__version__}, float32 (TF32 off), "
          f"{macs} multiply-adds per agent")
    for n in [int(s) for s in args.agents.split(",")]:
        x = torch.randn(n, obs_dim, device=dev, dtype=torch.float32)
        with torch.no_grad():
            f_ms, g_ms = timed(forward, x), timed(products, x)
        row = {"agents": n, "torch_forward_ms": f_ms, "torch_forward_gflops": 2 * macs * n / f_ms * 1e-6,
               "torch_sgemm_only_ms": g_ms, "torch_sgemm_only_gflops": 2 * macs * n / g_ms * 1e-6}
        rows.append(row)
        print(f"  N {n:8d}: forward {f_ms:.3f} ms = {row['torch_forward_gflops']:.0f} GFLOP/s; "
              f"matrix products alone {g_ms:.3f} ms = {row['torch_sgemm_only_gflops']:.0f} GFLOP/s")
    with open(args.out, "w") as f:
        json.dump({"benchmark": "policy_mlp_gpu_peer", "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                   "device": name, "torch": torch.__version__, "tf32": False, "macs_per_agent": macs,
                   "weights": os.path.relpath(args.weights, ROOT), "rows": rows}, f, indent=2)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

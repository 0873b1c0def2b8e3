"""The trained actor as a safetensors file (helpers' policy contract
"policy-mlp/1", read by the library's policy loader): layers.{i}.weight
[out, in] and layers.{i}.bias [out] as F32, obs_mean / obs_std, and the
metadata format, activations, action_scale, efs, env, trained_by."""

from __future__ import annotations

import json
import os

import numpy as np

__all__ = ["export_actor", "load_policy", "policy_actions"]

FORMAT = "policy-mlp/1"


def export_actor(actor, path: str | os.PathLike, action_scale, efs: bool, env_params: dict | None = None,
                 trained_by: str = "") -> dict:
    """Writes ``actor`` (swarmcl.rl.ddpg.Actor) to ``path``; returns the metadata.
    Actions in env units are tanh(last layer) * action_scale (Eq. 2's {v, omega})."""
    from safetensors.numpy import save_file

    tensors = {}
    linears = list(actor.net)
    for i, layer in enumerate(linears):
        tensors[f"layers.{i}.weight"] = layer.weight.detach().cpu().numpy().astype(np.float32).copy()
        tensors[f"layers.{i}.bias"] = layer.bias.detach().cpu().numpy().astype(np.float32).copy()
    obs_dim = linears[0].in_features
    tensors["obs_mean"] = np.zeros(obs_dim, np.float32)
    tensors["obs_std"] = actor.obs_std.detach().cpu().numpy().astype(np.float32).copy()
    scale = np.asarray(action_scale, dtype=np.float32).reshape(4)
    meta = {
        "swarmcl.format": FORMAT,
        "swarmcl.activations": ",".join(actor.activations()),
        "swarmcl.action_scale": ",".join(f"{float(v):.6g}" for v in scale),
        "swarmcl.efs": "1" if efs else "0",
    }
    if env_params is not None:
        meta["swarmcl.env"] = json.dumps(env_params, sort_keys=True)
    if trained_by:
        meta["swarmcl.trained_by"] = trained_by
    save_file(tensors, os.fspath(path), metadata=meta)
    return meta


def load_policy(path: str | os.PathLike) -> dict:
    """Reads an exported policy back with NumPy only (checks the contract):
    {"weights": [...], "biases": [...], "activations": [...],
    "action_scale": (4,), "obs_mean", "obs_std", "metadata"}."""
    from safetensors import safe_open

    with safe_open(os.fspath(path), framework="numpy") as f:
        meta = f.metadata() or {}
        keys = set(f.keys())
        tensors = {k: f.get_tensor(k) for k in keys}
    if meta.get("swarmcl.format") != FORMAT:
        raise ValueError(f"{path}: swarmcl.format is {meta.get('swarmcl.format')!r}, expected {FORMAT!r}")
    n = 0
    while f"layers.{n}.weight" in tensors:
        n += 1
    weights = [tensors[f"layers.{i}.weight"] for i in range(n)]
    biases = [tensors[f"layers.{i}.bias"] for i in range(n)]
    acts = meta["swarmcl.activations"].split(",")
    if not 1 <= n <= 8 or len(acts) != n:
        raise ValueError(f"{path}: {n} layers and {len(acts)} activations")
    for i, (w, b) in enumerate(zip(weights, biases)):
        if w.dtype != np.float32 or b.dtype != np.float32 or w.ndim != 2 or b.shape != (w.shape[0],):
            raise ValueError(f"{path}: layer {i} has bad dtype or shape {w.shape} / {b.shape}")
        if i and w.shape[1] != weights[i - 1].shape[0]:
            raise ValueError(f"{path}: layer {i} input {w.shape[1]} != previous output {weights[i - 1].shape[0]}")
    if weights[-1].shape[0] != 4:
        raise ValueError(f"{path}: the last layer has {weights[-1].shape[0]} outputs, expected 4")
    obs_dim = weights[0].shape[1]
    return {"weights": weights, "biases": biases, "activations": acts,
            "action_scale": np.array([float(v) for v in meta["swarmcl.action_scale"].split(",")], np.float32),
            "obs_mean": tensors.get("obs_mean", np.zeros(obs_dim, np.float32)),
            "obs_std": tensors.get("obs_std", np.ones(obs_dim, np.float32)), "metadata": meta}


def policy_actions(policy: dict, obs: np.ndarray) -> np.ndarray:
    """Env-unit actions of a loaded policy for (B, obs_dim) observations
    (NumPy; what the library's policy kernel computes)."""
    x = (np.asarray(obs, np.float32) - policy["obs_mean"]) / policy["obs_std"]
    for w, b, a in zip(policy["weights"], policy["biases"], policy["activations"]):
        x = x @ w.T + b
        if a == "relu":
            x = np.maximum(x, 0)
        elif a == "tanh":
            x = np.tanh(x)
    return (x * policy["action_scale"]).astype(np.float32)

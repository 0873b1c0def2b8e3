"""The trained actor as a safetensors file (helpers' policy contract
"policy-mlp/1", read by the library's policy loader): layers.{i}.weight
[out, in] and layers.{i}.bias [out] as F32, obs_mean / obs_std, and the
metadata format, activations, action_scale, efs, env, trained_by."""

from __future__ import annotations

import json
import os
import pathlib

import numpy as np

__all__ = ["export_actor", "load_policy", "policy_actions"]

FORMAT = "policy-mlp/1"
OBS_DIM_EFS, OBS_DIM_NO_EFS = 54, 51  # Eq. 11-13, with and without the embedded swarm features
ACTIONS = 4  # {v, omega.xyz} (Eq. 2)


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


def _read_safetensors(path: str | os.PathLike):
    """(tensors, metadata) of a safetensors file, read with NumPy only: the
    8-byte little-endian header length, the JSON header, F32 tensors.  A
    ValueError naming the file and the problem for anything else."""
    data = pathlib.Path(path).read_bytes()
    if len(data) < 8:
        raise ValueError(f"{path}: file truncated ({len(data)} bytes, shorter than the 8-byte header length)")
    n = int.from_bytes(data[:8], "little")
    if n > len(data) - 8:
        raise ValueError(f"{path}: header length {n} is beyond the end of the file ({len(data)} bytes; truncated?)")
    try:
        header = json.loads(data[8:8 + n])
    except ValueError as e:
        raise ValueError(f"{path}: header is not valid JSON: {e}") from None
    if not isinstance(header, dict):
        raise ValueError(f"{path}: header is not a JSON object")
    body = data[8 + n:]
    meta = header.pop("__metadata__", None) or {}
    tensors = {}
    for name, e in header.items():
        if not isinstance(e, dict) or not {"dtype", "shape", "data_offsets"} <= set(e):
            raise ValueError(f"{path}: tensor '{name}': header entry needs dtype, shape and data_offsets")
        if e["dtype"] != "F32":
            raise ValueError(f"{path}: tensor '{name}': dtype {e['dtype']}, expected F32 (float32)")
        try:
            shape, (begin, end) = tuple(int(d) for d in e["shape"]), (int(v) for v in e["data_offsets"])
        except (TypeError, ValueError):
            raise ValueError(f"{path}: tensor '{name}': shape and data_offsets must be lists of integers") from None
        if not 0 <= begin <= end <= len(body) or end - begin != 4 * int(np.prod(shape, dtype=np.int64)):
            raise ValueError(f"{path}: tensor '{name}': data_offsets {[begin, end]} do not hold shape {shape} "
                             f"in {len(body)} data bytes")
        tensors[name] = np.frombuffer(body[begin:end], dtype="<f4").reshape(shape).astype(np.float32)
    return tensors, meta


def _shape(t) -> str:
    return "[" + ", ".join(str(d) for d in t.shape) + "]"


def load_policy(path: str | os.PathLike) -> dict:
    """Reads an exported policy back with NumPy only and checks it against
    the contract, as the library's loader does (host/rl/policy_weights.cpp),
    with a ValueError naming the file, the tensor, the shape expected and the
    shape found: the first layer must take the observation (obs_dim 54 with
    EFS, 51 without, by swarmcl.efs), each layer the previous one's outputs,
    the last give the 4 actions; obs_mean / obs_std obs_dim long.  Returns
    {"weights": [...], "biases": [...], "activations": [...],
    "action_scale": (4,), "obs_mean", "obs_std", "obs_dim", "efs", "metadata"}."""
    tensors, meta = _read_safetensors(path)
    for key in ("swarmcl.format", "swarmcl.activations", "swarmcl.action_scale", "swarmcl.efs"):
        if key not in meta:
            raise ValueError(f'{path}: __metadata__ has no "{key}"')
    if meta["swarmcl.format"] != FORMAT:
        raise ValueError(f"{path}: swarmcl.format is {meta['swarmcl.format']!r}, expected {FORMAT!r}")
    if meta["swarmcl.efs"] not in ("0", "1"):
        raise ValueError(f'{path}: swarmcl.efs is {meta["swarmcl.efs"]!r}, expected "1" or "0"')
    efs = meta["swarmcl.efs"] == "1"
    obs_dim = OBS_DIM_EFS if efs else OBS_DIM_NO_EFS
    n = 0
    while f"layers.{n}.weight" in tensors or f"layers.{n}.bias" in tensors:
        n += 1
    acts = [a.strip() for a in meta["swarmcl.activations"].split(",")]
    if not 1 <= n <= 8 or len(acts) != n:
        raise ValueError(f"{path}: {n} layers (1 to 8 expected) and {len(acts)} activations")
    weights, biases = [], []
    fan_in = obs_dim
    for i in range(n):
        wn, bn = f"layers.{i}.weight", f"layers.{i}.bias"
        for name in (wn, bn):
            if name not in tensors:
                raise ValueError(f"{path}: tensor '{name}' is missing")
        w, b = tensors[wn], tensors[bn]
        if w.ndim != 2 or w.shape[1] != fan_in or w.shape[0] == 0:
            why = (f"the first layer takes the observation: {obs_dim} entries, as swarmcl.efs is "
                   f"\"{meta['swarmcl.efs']}\" (54 with EFS, 51 without)" if i == 0
                   else "in = the previous layer's out")
            raise ValueError(f"{path}: tensor '{wn}' has shape {_shape(w)}, expected [out, {fan_in}] ({why})")
        if i == n - 1 and w.shape[0] != ACTIONS:
            raise ValueError(f"{path}: tensor '{wn}' has shape {_shape(w)}, expected [{ACTIONS}, {fan_in}] "
                             f"(the last layer gives the {ACTIONS} actions; it has {w.shape[0]} outputs)")
        if b.shape != (w.shape[0],):
            raise ValueError(f"{path}: tensor '{bn}' has shape {_shape(b)}, expected [{w.shape[0]}]")
        if acts[i] not in ("relu", "linear", "tanh"):
            raise ValueError(f"{path}: swarmcl.activations entry {i} is {acts[i]!r} (relu, linear or tanh)")
        weights.append(w)
        biases.append(b)
        fan_in = w.shape[0]
    if ("obs_mean" in tensors) != ("obs_std" in tensors):
        raise ValueError(f"{path}: obs_mean and obs_std must be given together")
    for name in ("obs_mean", "obs_std"):
        if name in tensors and tensors[name].shape != (obs_dim,):
            raise ValueError(f"{path}: {name} has shape {_shape(tensors[name])}, expected [{obs_dim}]")
    extra = sorted(set(tensors) - {f"layers.{i}.{k}" for i in range(n) for k in ("weight", "bias")}
                   - {"obs_mean", "obs_std"})
    if extra:
        raise ValueError(f"{path}: unexpected tensor '{extra[0]}' (expected layers.{{i}}.weight/bias, obs_mean, "
                         f"obs_std)")
    scale = meta["swarmcl.action_scale"].split(",")
    if len(scale) != ACTIONS:
        raise ValueError(f"{path}: swarmcl.action_scale must hold {ACTIONS} comma-separated numbers")
    return {"weights": weights, "biases": biases, "activations": acts,
            "action_scale": np.array([float(v) for v in scale], np.float32),
            "obs_mean": tensors.get("obs_mean", np.zeros(obs_dim, np.float32)),
            "obs_std": tensors.get("obs_std", np.ones(obs_dim, np.float32)),
            "obs_dim": obs_dim, "efs": efs, "metadata": meta}


def policy_actions(policy: dict, obs: np.ndarray) -> np.ndarray:
    """Env-unit actions of a loaded policy for (..., obs_dim) observations
    (NumPy; what the library's policy kernel computes).  Observations of
    another width (an env with efs=False gives 51, with EFS 54) are a
    ValueError naming both; nothing else is touched."""
    x = np.asarray(obs, np.float32)
    d = policy.get("obs_dim", policy["weights"][0].shape[1])
    if x.ndim < 1 or x.shape[-1] != d:
        raise ValueError(f"policy_actions: the policy takes {d} observations per agent "
                         f"({'with' if d == OBS_DIM_EFS else 'without'} EFS), got observations of shape {x.shape} "
                         f"(an env made with efs={d == OBS_DIM_EFS} gives {d})")
    x = (x - policy["obs_mean"]) / policy["obs_std"]
    for w, b, a in zip(policy["weights"], policy["biases"], policy["activations"]):
        x = x @ w.T + b
        if a == "relu":
            x = np.maximum(x, 0)
        elif a == "tanh":
            x = np.tanh(x)
    return (x * policy["action_scale"]).astype(np.float32)

"""The policy model (docs/rl-swarm.md, "Policy model"): a trained actor MLP in
a safetensors file drives the swarm's agents as followers of a leader.
``PolicyModel`` mirrors ``swcl_policy_model_desc`` (defaults from
``swcl_policy_model_desc_default()``: Table 1 of the DRL paper).

>>> model = swarmcl.PolicyModel(weights=swarmcl.SHIPPED_POLICY, leader_mode="tour",
...                             waypoints=[(30, 0, 0, 0.8), (30, 30, 0, 1.0), (0, 30, 0, 0.8)])
>>> swarm.set_policy_model(model)
>>> swarm.step(100)
"""

from __future__ import annotations

import os
from dataclasses import field, make_dataclass
from pathlib import Path
from typing import Optional, Sequence, Union

import numpy as np

from ._native import ffi, lib
from .params import c_ordered_fields, copy_scalars_to_c, parameter_doc

__all__ = ["PolicyModel", "SHIPPED_POLICY", "DDPG_POLICY"]

_DEFAULT = lib.swcl_policy_model_desc_default()
_MODES = {"joystick": lib.SWCL_POLICY_LEADER_JOYSTICK, "navigation": lib.SWCL_POLICY_LEADER_NAVIGATION,
          "tour": lib.SWCL_POLICY_LEADER_TOUR}


def _shipped(name: str = "policy_roaming.safetensors") -> str:
    """models/<name>: in the package, else the checkout."""
    here = Path(__file__).resolve().parent
    for p in (here / "models" / name, here.parents[2] / "models" / name):
        if p.is_file():
            return str(p)
    return str(here / "models" / name)


#: The policy that ships with swarmcl (behaviour cloning of the rule-based
#: action generator; docs/rl-swarm.md).
SHIPPED_POLICY = _shipped()
#: The DDPG-trained actor of the learning demonstration (DDPG + RAG, 32 worlds
#: x 4 followers; follows its leader more closely than the shipped policy,
#: docs/rl-swarm.md "The learning demonstration").
DDPG_POLICY = _shipped("policy_roaming_ddpg.safetensors")


def _vec3_default(name: str):
    return field(default_factory=lambda: tuple(float(x) for x in getattr(_DEFAULT, name)))


def _policy_model_to_c(self):
    """The C descriptor and the objects it points into (keep them alive)."""
    d = ffi.new("swcl_policy_model_desc*", _DEFAULT)
    keep: list = []
    if isinstance(self.weights, (bytes, bytearray)):
        buf = ffi.from_buffer(bytes(self.weights))
        keep.append(buf)
        d.weights_data = buf
        d.weights_size = len(self.weights)
    else:
        path = ffi.new("char[]", os.fsencode(self.weights))
        keep.append(path)
        d.weights_path = path
    if self.leader_mode not in _MODES:
        raise ValueError(f"PolicyModel.leader_mode: expected one of {sorted(_MODES)}, got {self.leader_mode!r}")
    d.leader_mode = _MODES[self.leader_mode]
    if self.waypoints is not None:
        w = np.ascontiguousarray(self.waypoints, dtype=np.float32).reshape(-1, 4)
        keep.append(w)
        d.waypoints = ffi.cast("float*", w.ctypes.data)
        d.waypoint_count = len(w)
    if self.obstacles is not None:
        o = np.ascontiguousarray(self.obstacles, dtype=np.float32).reshape(-1, 6)
        keep.append(o)
        d.obstacles = ffi.cast("float*", o.ctypes.data)
        d.obstacle_count = len(o)
    for a in range(3):
        d.leader_position[a] = float(self.leader_position[a])
        d.leader_heading[a] = float(self.leader_heading[a])
    copy_scalars_to_c(self, d, "policy")
    return d, keep


# The fields in the C descriptor's order (positional arguments as before):
# the weights, the leader's mode, waypoints and start by hand, every scalar
# parameter from the library's table (swcl_model_parameters("policy")), the
# obstacle boxes by hand.
PolicyModel = make_dataclass("PolicyModel", c_ordered_fields("swcl_policy_model_desc", "policy", {
    "weights_path": ("weights", Union[str, os.PathLike, bytes], field(default_factory=lambda: SHIPPED_POLICY)),
    "leader_mode": ("leader_mode", str, field(default="joystick")),
    "waypoints": ("waypoints", Optional[Sequence], field(default=None)),
    "leader_position": ("leader_position", Sequence[float], _vec3_default("leader_position")),
    "leader_heading": ("leader_heading", Sequence[float], _vec3_default("leader_heading")),
    "obstacles": ("obstacles", Optional[Sequence], field(default=None)),
}), namespace={"to_c": _policy_model_to_c, "__module__": __name__})
PolicyModel.__doc__ = (
    "swcl_policy_model_desc.  ``weights``: a path, or the file's bytes.  ``leader_mode``: \"joystick\"\n"
    "(``Swarm.set_policy_leader_controls``), \"navigation\" (stops after the last waypoint) or \"tour\"\n"
    "(starts over); ``waypoints``: (K, 4) x, y, z, target speed.  ``obstacles``: boxes (B, 6) centre xyz,\n"
    "half extents xyz.  Defaults are the library's (swcl_model_parameters('policy')):\n" + parameter_doc("policy"))

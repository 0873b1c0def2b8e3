"""The force model of the shape-constrained flying insects paper
(docs/force-model.md): ``ForceModel`` mirrors ``swcl_force_model_desc`` (its
scalar fields, defaults and docs come from the library's parameter table,
``swcl_model_parameters("force")``; Table 1 of the paper), ``Keyframe`` mirrors ``swcl_keyframe``.

>>> model = swarmcl.ForceModel(keyframes=[swarmcl.Keyframe(0, "sphere"),
...                                      swarmcl.Keyframe(600, "mammoth")])
>>> swarm.set_force_model(model)
"""

from __future__ import annotations

from dataclasses import dataclass, field, make_dataclass
from typing import Optional, Sequence, Union

import numpy as np

from ._native import ffi, lib
from .descriptors import Box, Sphere, Vec3, _boundary_to_c, _f32, _vec3
from .params import copy_scalars_to_c, parameter_doc, scalar_fields
from .path import (BoxObstacle, CylinderObstacle, MeshObstacle, ObjObstacle, SphereObstacle,
                   _obstacle_to_c)

__all__ = ["ForceModel", "Keyframe", "SHAPES"]

#: Generated shapes a keyframe may name (plus "horse:<phase>", phase in [0, 1)).
SHAPES = ("sphere", "torus", "moon", "star", "heart", "mammoth", "shark", "horse")

_DEFAULT = lib.swcl_force_model_desc_default()
_ASSIGN = {"nearest": lib.SWCL_ASSIGN_NEAREST, "curve": lib.SWCL_ASSIGN_CURVE}


def _default(name: str):
    def factory():
        v = getattr(_DEFAULT, name)
        return int(v) if name.endswith("seed") or name == "neighbor_sample" else _f32(v)
    return field(default_factory=factory)


@dataclass
class Keyframe:
    """A target mesh from ``frame`` (step) on: a generated shape by name, or a
    mesh given as ``vertices`` (V, 3) and ``triangles`` (T, 3); scaled by
    ``scale`` then moved by ``offset``."""
    frame: int
    shape: Optional[str] = None
    vertices: Optional[np.ndarray] = None
    triangles: Optional[np.ndarray] = None
    scale: float = 1.0
    offset: Vec3 = (0.0, 0.0, 0.0)

    def _to_c(self, dst, keep: list) -> None:
        dst.frame = int(self.frame)
        if (self.shape is None) == (self.vertices is None):
            raise ValueError("Keyframe: give either shape (a name) or vertices and triangles")
        if self.shape is not None:
            name = ffi.new("char[]", str(self.shape).encode())
            keep.append(name)
            dst.shape = name
        else:
            v = np.ascontiguousarray(self.vertices, dtype=np.float32).reshape(-1, 3)
            t = np.ascontiguousarray(self.triangles, dtype=np.uint32).reshape(-1, 3)
            keep.extend((v, t))
            dst.vertices = ffi.cast("const float*", ffi.from_buffer(v))
            dst.vertex_count = len(v)
            dst.triangles = ffi.cast("const uint32_t*", ffi.from_buffer(t))
            dst.triangle_count = len(t)
        dst.scale = self.scale
        dst.offset = _vec3(self.offset, "Keyframe.offset")


def keyframes_to_c(keyframes: Sequence[Keyframe], keep: list):
    """A ``swcl_keyframe[]`` (kept alive by ``keep``) and its length."""
    arr = ffi.new("swcl_keyframe[]", max(len(keyframes), 1))
    keep.append(arr)
    for i, k in enumerate(keyframes):
        if not isinstance(k, Keyframe):
            raise TypeError(f"keyframes[{i}] must be a Keyframe, got {type(k).__name__}")
        k._to_c(arr[i], keep)
    return arr, len(keyframes)


def path_to_c(path, keep: list):
    if path is None:
        return ffi.NULL, 0
    p = np.ascontiguousarray(path, dtype=np.float32).reshape(-1, 3)
    keep.append(p)
    return ffi.cast("const float*", ffi.from_buffer(p)), len(p)


# The force model's fields: eta (Eq. 4's magnitude: the library keeps
# gain = eta / rho), the assignment by name, keyframes, path points and
# obstacles by hand; every other parameter (names, defaults, docs) from the
# library's table (swcl_model_parameters("force"); rho is its noise.scale,
# noise_seed its noise.seed).  "terms" is not in the C descriptor.
_FORCE_STRUCTURED = ("terms",)


def _force_model_to_c(self):
    """A new ``swcl_force_model_desc*`` and the objects it points into."""
    keep: list = []
    p = ffi.new("swcl_force_model_desc*", lib.swcl_force_model_desc_default())
    copy_scalars_to_c(self, p, "force", _FORCE_STRUCTURED)
    p.eta = float(self.eta)
    if self.assignment not in _ASSIGN:
        raise ValueError(f"ForceModel.assignment must be 'nearest' or 'curve', got {self.assignment!r}")
    p.assignment = _ASSIGN[self.assignment]
    p.keyframes, p.keyframe_count = keyframes_to_c(self.keyframes, keep)
    p.path, p.path_point_count = path_to_c(self.path, keep)
    obs = ffi.new("swcl_obstacle[]", max(len(self.obstacles), 1))
    keep.append(obs)
    for i, b in enumerate(self.obstacles):
        if not isinstance(b, (Sphere, Box)):
            raise TypeError(f"ForceModel.obstacles[{i}] must be a Sphere or Box, got {type(b).__name__}")
        _boundary_to_c(b, obs[i])
    p.obstacles = obs
    p.obstacle_count = len(self.obstacles)
    meshes = ffi.new("swcl_obstacle[]", max(len(self.mesh_obstacles), 1))
    keep.append(meshes)
    kinds = (MeshObstacle, ObjObstacle, BoxObstacle, SphereObstacle, CylinderObstacle)
    for i, o in enumerate(self.mesh_obstacles):
        if not isinstance(o, kinds):
            raise TypeError(f"ForceModel.mesh_obstacles[{i}] must be a Mesh, Obj, Box, Sphere or "
                            f"CylinderObstacle, got {type(o).__name__}")
        _obstacle_to_c(o, meshes[i], keep)
    p.mesh_obstacles = meshes
    p.mesh_obstacle_count = len(self.mesh_obstacles)
    return p, keep


ForceModel = make_dataclass(
    "ForceModel",
    scalar_fields("force", _FORCE_STRUCTURED)
    + [("eta", float, _default("eta")),
       ("assignment", str, field(default="nearest")),
       ("keyframes", list, field(default_factory=list)),
       ("path", Optional[np.ndarray], field(default=None)),
       ("obstacles", list, field(default_factory=list)),
       ("mesh_obstacles", list, field(default_factory=list))],
    namespace={"to_c": _force_model_to_c, "__module__": __name__})
ForceModel.__doc__ = (
    "swcl_force_model_desc: zone radii and weights (Eq. 2-3), curl noise\n"
    "(eta, rho: Eq. 4), shape forces (Eq. 5-7), the union weight alpha (Eq. 1),\n"
    "speeds, MDE, keyframes, path and obstacles (spheres and boxes, Eq. 8-9).\n"
    "``assignment``: 'nearest' or 'curve'.  ``mesh_obstacles``: the path module's\n"
    "obstacles (MeshObstacle, ObjObstacle, BoxObstacle, SphereObstacle,\n"
    "CylinderObstacle), avoided like ``obstacles`` through a signed distance grid.\n"
    "``eta``: Eq. 4's noise magnitude (m/s^2; the library's noise gain is eta / rho).\n"
    "Defaults are the library's (swcl_model_parameters('force')):\n" + parameter_doc("force", _FORCE_STRUCTURED))

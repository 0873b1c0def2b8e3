"""The force model of the shape-constrained flying insects paper
(docs/force-model.md): ``ForceModel`` mirrors ``swcl_force_model_desc`` (its
defaults are read from ``swcl_force_model_desc_default()``, Table 1 of the
paper), ``Keyframe`` mirrors ``swcl_keyframe``.

>>> model = swarmcl.ForceModel(keyframes=[swarmcl.Keyframe(0, "sphere"),
...                                      swarmcl.Keyframe(600, "mammoth")])
>>> swarm.set_force_model(model)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Sequence, Union

import numpy as np

from ._native import ffi, lib
from .descriptors import Box, Sphere, Vec3, _boundary_to_c, _f32, _vec3
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


@dataclass
class ForceModel:
    """swcl_force_model_desc: zone radii and weights (Eq. 2-3), curl noise
    (eta, rho: Eq. 4), shape forces (Eq. 5-7), the union weight alpha (Eq. 1),
    speeds, MDE, keyframes, path and obstacles (spheres and boxes, Eq. 8-9).
    ``assignment``: 'nearest' or 'curve'.  ``path_orient`` (default True):
    the shape's frame turns with the path (forward +x along the tangent);
    False: it is translated only.  ``mesh_obstacles``: the path module's
    obstacles (MeshObstacle, ObjObstacle, BoxObstacle, SphereObstacle,
    CylinderObstacle), avoided like ``obstacles`` through a signed distance
    grid of cells ``mesh_cell`` m (0: obstacle_range / 4)."""
    r_rep: float = _default("r_rep")
    r_ali: float = _default("r_ali")
    r_att: float = _default("r_att")
    w_rep: float = _default("w_rep")
    w_ali: float = _default("w_ali")
    w_att: float = _default("w_att")
    w_dis: float = _default("w_dis")
    w_con: float = _default("w_con")
    omega: float = _default("omega")
    neighbor_k: float = _default("neighbor_k")
    distance_scale: float = _default("distance_scale")
    neighbor_sample: int = _default("neighbor_sample")
    eta: float = _default("eta")
    rho: float = _default("rho")
    noise_seed: int = _default("noise_seed")
    alpha: float = _default("alpha")
    max_speed: float = _default("max_speed")
    cruise_speed: float = _default("cruise_speed")
    min_distance: float = _default("min_distance")
    min_spacing: float = _default("min_spacing")
    assignment: str = "nearest"
    sample_seed: int = _default("sample_seed")
    keyframes: list = field(default_factory=list)
    keyframe_period: int = 0
    path: Optional[np.ndarray] = None
    path_speed: float = 0.0
    obstacles: list = field(default_factory=list)
    obstacle_range: float = _default("obstacle_range")
    path_orient: bool = field(default_factory=lambda: bool(_DEFAULT.path_orient))
    mesh_obstacles: list = field(default_factory=list)
    mesh_cell: float = _default("mesh_cell")

    def to_c(self):
        """A new ``swcl_force_model_desc*`` and the objects it points into."""
        keep: list = []
        p = ffi.new("swcl_force_model_desc*", lib.swcl_force_model_desc_default())
        for name in ("r_rep", "r_ali", "r_att", "w_rep", "w_ali", "w_att", "w_dis", "w_con", "omega",
                     "neighbor_k", "distance_scale", "eta", "rho", "alpha", "max_speed", "cruise_speed",
                     "min_distance", "min_spacing", "path_speed", "obstacle_range"):
            setattr(p, name, float(getattr(self, name)))
        p.neighbor_sample = int(self.neighbor_sample)
        p.noise_seed = int(self.noise_seed)
        p.sample_seed = int(self.sample_seed)
        if self.assignment not in _ASSIGN:
            raise ValueError(f"ForceModel.assignment must be 'nearest' or 'curve', got {self.assignment!r}")
        p.assignment = _ASSIGN[self.assignment]
        p.keyframes, p.keyframe_count = keyframes_to_c(self.keyframes, keep)
        p.keyframe_period = int(self.keyframe_period)
        p.path, p.path_point_count = path_to_c(self.path, keep)
        obs = ffi.new("swcl_obstacle[]", max(len(self.obstacles), 1))
        keep.append(obs)
        for i, b in enumerate(self.obstacles):
            if not isinstance(b, (Sphere, Box)):
                raise TypeError(f"ForceModel.obstacles[{i}] must be a Sphere or Box, got {type(b).__name__}")
            _boundary_to_c(b, obs[i])
        p.obstacles = obs
        p.obstacle_count = len(self.obstacles)
        p.path_orient = 1 if self.path_orient else 0
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
        p.mesh_cell = float(self.mesh_cell)
        return p, keep

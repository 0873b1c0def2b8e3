"""The path model (swcl_path_model_desc, docs/path-field.md): obstacle meshes,
goals, groups, and the descriptor: its scalar fields, defaults and docs from
the library's parameter table (swcl_model_parameters("path")), the noise and
resolution from swcl_path_model_desc_default() (the curl-noise paper's values)."""

from __future__ import annotations

from dataclasses import dataclass, field, make_dataclass
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

from ._native import ffi, lib
from .descriptors import NoiseDesc, Vec3, _f32, _vec3
from .params import copy_scalars_to_c, parameter_doc, scalar_fields

__all__ = ["Goal", "MeshObstacle", "ObjObstacle", "BoxObstacle", "SphereObstacle", "CylinderObstacle",
           "PathGroup", "PathModel", "PathInfo", "PathTarget", "Lamp"]

_DEFAULT = lib.swcl_path_model_desc_default()


@dataclass
class Goal:
    """A goal region: kind 'point' | 'sphere' (radius) | 'box' (half_extents)."""
    center: Vec3
    kind: str = "point"
    radius: float = 0.0
    half_extents: Vec3 = (0.0, 0.0, 0.0)

    def _to_c(self, dst) -> None:
        kinds = {"point": lib.SWCL_GOAL_POINT, "sphere": lib.SWCL_GOAL_SPHERE, "box": lib.SWCL_GOAL_BOX}
        if self.kind not in kinds:
            raise ValueError(f"Goal.kind must be 'point', 'sphere' or 'box', got {self.kind!r}")
        dst.type = kinds[self.kind]
        dst.center = _vec3(self.center, "Goal.center")
        dst.radius = self.radius
        dst.half_extents = _vec3(self.half_extents, "Goal.half_extents")


@dataclass
class MeshObstacle:
    """A triangle mesh: vertices (V, 3) and triangle indices (T, 3), copied by the call."""
    vertices: np.ndarray
    indices: np.ndarray


@dataclass
class ObjObstacle:
    """A Wavefront OBJ file."""
    path: str


@dataclass
class BoxObstacle:
    center: Vec3
    half_extents: Vec3


@dataclass
class SphereObstacle:
    center: Vec3
    radius: float


@dataclass
class CylinderObstacle:
    """Along +z from ``base`` (the bottom cap's centre)."""
    base: Vec3
    radius: float
    height: float


Obstacle = Union[MeshObstacle, ObjObstacle, BoxObstacle, SphereObstacle, CylinderObstacle]


def _obstacle_to_c(o: Obstacle, dst, keep: list) -> None:
    if isinstance(o, MeshObstacle):
        v = np.ascontiguousarray(o.vertices, dtype=np.float32).reshape(-1, 3)
        i = np.ascontiguousarray(o.indices, dtype=np.uint32).reshape(-1, 3)
        keep += [v, i]
        dst.type = lib.SWCL_OBSTACLE_MESH
        dst.vertices = ffi.cast("const float*", v.ctypes.data)
        dst.vertex_count = len(v)
        dst.indices = ffi.cast("const uint32_t*", i.ctypes.data)
        dst.triangle_count = len(i)
    elif isinstance(o, ObjObstacle):
        path = ffi.new("char[]", str(o.path).encode())
        keep.append(path)
        dst.type = lib.SWCL_OBSTACLE_OBJ
        dst.path = path
    elif isinstance(o, BoxObstacle):
        dst.type = lib.SWCL_OBSTACLE_BOX
        dst.center = _vec3(o.center, "BoxObstacle.center")
        dst.half_extents = _vec3(o.half_extents, "BoxObstacle.half_extents")
    elif isinstance(o, SphereObstacle):
        dst.type = lib.SWCL_OBSTACLE_SPHERE
        dst.center = _vec3(o.center, "SphereObstacle.center")
        dst.radius = o.radius
    elif isinstance(o, CylinderObstacle):
        dst.type = lib.SWCL_OBSTACLE_CYLINDER
        dst.center = _vec3(o.base, "CylinderObstacle.base")
        dst.radius = o.radius
        dst.height = o.height
    else:
        raise TypeError(f"unknown obstacle {type(o).__name__}")


def _goals_to_c(goals: Sequence[Goal], keep: list):
    goals = list(goals)
    if not goals:
        return ffi.NULL, 0
    arr = ffi.new("swcl_goal[]", len(goals))
    for k, g in enumerate(goals):
        if not isinstance(g, Goal):
            raise TypeError(f"goals[{k}] must be a Goal, got {type(g).__name__}")
        g._to_c(arr[k])
    keep.append(arr)
    return arr, len(goals)


@dataclass
class PathGroup:
    """Agents with consecutive ids (the last group takes the rest) and their goals."""
    agents: int
    goals: List[Goal]


def _path_model_to_c(self):
    """A new ``swcl_path_model_desc*`` and the objects it points into."""
    keep: list = []
    p = ffi.new("swcl_path_model_desc*", lib.swcl_path_model_desc_default())
    noise = self.noise if self.noise is not None else NoiseDesc()
    noise._to_c(p.noise, keep)
    if self.obstacles:
        arr = ffi.new("swcl_obstacle[]", len(self.obstacles))
        for k, o in enumerate(self.obstacles):
            _obstacle_to_c(o, arr[k], keep)
        keep.append(arr)
        p.obstacles, p.obstacle_count = arr, len(self.obstacles)
    if self.grid is not None:
        p.grid_min = _vec3(self.grid[0], "PathModel.grid[0]")
        p.grid_max = _vec3(self.grid[1], "PathModel.grid[1]")
    p.resolution = tuple(int(r) for r in self.resolution)
    copy_scalars_to_c(self, p, "path", _PATH_STRUCTURED)
    p.goals, p.goal_count = _goals_to_c(self.goals, keep)
    if self.groups:
        arr = ffi.new("swcl_path_group[]", len(self.groups))
        for k, g in enumerate(self.groups):
            arr[k].agents = int(g.agents)
            arr[k].goals, arr[k].goal_count = _goals_to_c(g.goals, keep)
        keep.append(arr)
        p.groups, p.group_count = arr, len(self.groups)
    return p, keep


# The path model's fields: goals, groups, obstacles, the noise, the grid box
# (None or (min, max)) and its resolution by hand; the scalar parameters
# (cost_a, cost_b, second_order, speed, goal_falloff, min_distance: names,
# defaults, docs) from the library's table (swcl_model_parameters("path")).
# has_grid_box and waypoint_every are not in the C descriptor (the lamp's and
# targets' rows are set through Swarm.set_path_lamp / targets).
_PATH_STRUCTURED = ("has_grid_box", "waypoint_every")
PathModel = make_dataclass(
    "PathModel",
    [("goals", List[Goal], field(default_factory=list)),
     ("groups", List[PathGroup], field(default_factory=list)),
     ("obstacles", List[Obstacle], field(default_factory=list)),
     ("noise", NoiseDesc, field(default_factory=lambda: NoiseDesc._from_c(_DEFAULT.noise))),
     ("grid", Optional[Tuple[Vec3, Vec3]], field(default=None)),  # None: the swarm's domain
     ("resolution", Tuple[int, int, int], field(default=tuple(int(r) for r in _DEFAULT.resolution)))]
    + scalar_fields("path", _PATH_STRUCTURED),
    namespace={"to_c": _path_model_to_c, "__module__": __name__})
PathModel.__doc__ = (
    "swcl_path_model_desc: noise + obstacles + goals (one group) or groups; ``grid``: None (the\n"
    "swarm's domain) or (min, max); ``resolution``: cells per axis at most.\n"
    "Defaults are the library's (swcl_model_parameters('path')):\n" + parameter_doc("path", _PATH_STRUCTURED))


@dataclass(frozen=True)
class PathInfo:
    """swcl_path_info: the path grid and preprocessing times."""
    grid: Tuple[int, int, int]
    cell: float
    grid_min: Vec3
    preprocess_seconds: float
    groups: int
    recomputes: int
    recompute_seconds: float


@dataclass
class PathTarget:
    """swcl_path_target: a chasing target (curl-noise paper §7), a ball that is a goal of
    ``group`` and a boundary of the curl noise (Eq. 2).  Move it with Swarm.set_path_target."""
    center: Vec3
    radius: float
    group: int = 0

    def _to_c(self):
        t = ffi.new("swcl_path_target*")
        t.group = int(self.group)
        t.center = _vec3(self.center, "PathTarget.center")
        t.radius = self.radius
        return t


_LAMP_DEFAULT = lib.swcl_path_lamp_default()


@dataclass
class Lamp:
    """swcl_path_lamp: positive phototaxis (§7).  Each step each insect, with ``probability``,
    gets ``speed`` m/s towards ``center``, turned by ``angle`` rad counter-clockwise about +z;
    the radial part fades to 0 over ``keep_out`` m above the bulb (``radius``)."""
    center: Vec3
    radius: float = _f32(_LAMP_DEFAULT.radius)
    probability: float = _f32(_LAMP_DEFAULT.probability)
    speed: float = _f32(_LAMP_DEFAULT.speed)
    angle: float = _f32(_LAMP_DEFAULT.angle)
    keep_out: float = _f32(_LAMP_DEFAULT.keep_out)
    enabled: bool = True

    def _to_c(self):
        p = ffi.new("swcl_path_lamp*", lib.swcl_path_lamp_default())
        p.enabled = 1 if self.enabled else 0
        p.center = _vec3(self.center, "Lamp.center")
        p.radius, p.probability, p.speed = self.radius, self.probability, self.speed
        p.angle, p.keep_out = self.angle, self.keep_out
        return p

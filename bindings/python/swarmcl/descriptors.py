"""Descriptor dataclasses mirroring the C descriptor structs.

Every default is read from the C library's ``*_default()`` function at import
time, so Python and C always agree; nothing is duplicated here.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field, make_dataclass
from typing import Optional, Tuple, Union

import numpy as np

from ._native import enum_members, ffi, lib
from .params import copy_scalars_to_c, parameter_doc, scalar_fields

__all__ = [
    "NoiseType", "DeviceType", "Sphere", "Box", "Plane", "NoiseDesc", "FieldModel",
    "DeviceInfo", "StepStats",
]

Vec3 = Tuple[float, float, float]
Bounds = Tuple[Vec3, Vec3]


def _enum(name: str, ctype: str, prefix: str) -> type:
    elements = enum_members(ctype)  # name -> value, from the header
    return enum.IntEnum(name, {k[len(prefix):]: v for k, v in sorted(elements.items(), key=lambda kv: kv[1])})


NoiseType = _enum("NoiseType", "swcl_noise_type", "SWCL_NOISE_")
NoiseType.__doc__ = "swcl_noise_type: CURL, PERLIN, WHITE, GAUSSIAN (a str such as 'curl' works too)."
DeviceType = _enum("DeviceType", "swcl_device_type", "SWCL_DEVICE_TYPE_")
ObstacleType = _enum("ObstacleType", "swcl_obstacle_type", "SWCL_OBSTACLE_")
ObstacleType.__doc__ = "swcl_obstacle_type: the C API's one obstacle type (MESH, OBJ, BOX, SPHERE, CYLINDER, PLANE)."


def noise_type(value: Union[str, int, "NoiseType"]) -> "NoiseType":
    if isinstance(value, str):
        try:
            return NoiseType[value.strip().upper()]
        except KeyError:
            raise ValueError(f"unknown noise type {value!r}; one of "
                             + ", ".join(t.name.lower() for t in NoiseType)) from None
    return NoiseType(value)


def _vec3(v, what: str) -> Vec3:
    try:
        x, y, z = (float(c) for c in v)
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be three numbers, got {v!r}") from None
    return (x, y, z)


def _f32(v) -> float:
    """A C float as the shortest Python float that rounds to it (0.4, not
    0.4000000059604645), so defaults read well and convert back exactly."""
    return float(str(np.float32(v)))


def _tuple3(arr) -> Vec3:
    return (_f32(arr[0]), _f32(arr[1]), _f32(arr[2]))


# ---- C defaults, read once -------------------------------------------------------

_NOISE_DEFAULT = lib.swcl_noise_desc_default()
_MODEL_DEFAULT = lib.swcl_field_model_desc_default()


def _noise_default(name: str):
    def factory():
        c = _NOISE_DEFAULT
        if name == "type":
            return NoiseType(c.type)
        if name in ("domain_walls", "baked", "finite_difference"):
            return bool(getattr(c, name))
        if name == "region":
            lo, hi = _tuple3(c.region_min), _tuple3(c.region_max)
            return None if lo == hi == (0.0, 0.0, 0.0) else (lo, hi)
        if name == "bake_resolution":
            return tuple(int(c.bake_resolution[a]) for a in range(3))
        if name == "seed":
            return int(c.seed)
        return _f32(getattr(c, name))
    return field(default_factory=factory)


def _model_default(name: str):
    def factory():
        c = _MODEL_DEFAULT
        if name == "noise":
            return NoiseDesc._from_c(c.noise)
        if name == "goal":
            return _tuple3(c.goal) if c.has_goal else None
        return _f32(getattr(c, name))
    return field(default_factory=factory)


# ---- boundaries -------------------------------------------------------------------

@dataclass
class Sphere:
    """A spherical obstacle."""
    center: Vec3
    radius: float


@dataclass
class Box:
    """A box obstacle; ``radius`` rounds its edges (0: a small default)."""
    center: Vec3
    half_extents: Vec3
    radius: float = 0.0


@dataclass
class Plane:
    """The half space dot(normal, x) >= offset is free."""
    normal: Vec3
    offset: float = 0.0


def _boundary_to_c(b, dst) -> None:
    if isinstance(b, Sphere):
        dst.type = ObstacleType.SPHERE
        dst.center = _vec3(b.center, "Sphere.center")
        dst.radius = b.radius
    elif isinstance(b, Box):
        dst.type = ObstacleType.BOX
        dst.center = _vec3(b.center, "Box.center")
        dst.half_extents = _vec3(b.half_extents, "Box.half_extents")
        dst.radius = b.radius
    elif isinstance(b, Plane):
        dst.type = ObstacleType.PLANE
        dst.normal = _vec3(b.normal, "Plane.normal")
        dst.offset = b.offset
    else:
        raise TypeError(f"a boundary must be a Sphere, Box or Plane, got {type(b).__name__}")


def _boundary_from_c(c):
    t = ObstacleType(c.type)
    if t == ObstacleType.SPHERE:
        return Sphere(_tuple3(c.center), _f32(c.radius))
    if t == ObstacleType.BOX:
        return Box(_tuple3(c.center), _tuple3(c.half_extents), _f32(c.radius))
    return Plane(_tuple3(c.normal), _f32(c.offset))


# ---- noise ------------------------------------------------------------------------

@dataclass
class NoiseDesc:
    """swcl_noise_desc (docs/noise.md).  Defaults are swcl_noise_desc_default()'s.

    ``type``: 'curl' | 'perlin' | 'white' | 'gaussian' (or NoiseType);
    ``region``: None (the swarm's domain) or ((x0, y0, z0), (x1, y1, z1));
    ``boundaries``: Sphere / Box / Plane obstacles."""
    type: Union[str, "NoiseType"] = _noise_default("type")
    scale: float = _noise_default("scale")
    gain: float = _noise_default("gain")
    seed: int = _noise_default("seed")
    time_scale: float = _noise_default("time_scale")
    boundary_distance: float = _noise_default("boundary_distance")
    domain_walls: bool = _noise_default("domain_walls")
    region: Optional[Bounds] = _noise_default("region")
    boundaries: list = field(default_factory=list)
    baked: bool = _noise_default("baked")
    bake_resolution: Tuple[int, int, int] = _noise_default("bake_resolution")
    finite_difference: bool = _noise_default("finite_difference")
    fd_step: float = _noise_default("fd_step")

    def __post_init__(self):
        self.type = noise_type(self.type)

    def _to_c(self, dst, keep: list) -> None:
        """Fills a swcl_noise_desc (already holding the C defaults); appends
        what must outlive the call to ``keep``."""
        dst.type = noise_type(self.type)
        dst.scale = self.scale
        dst.gain = self.gain
        seed = int(self.seed)
        if not 0 <= seed < 2**64:
            raise ValueError(f"NoiseDesc.seed must be in [0, 2**64), got {seed}")
        dst.seed = seed
        dst.time_scale = self.time_scale
        dst.boundary_distance = self.boundary_distance
        dst.domain_walls = 1 if self.domain_walls else 0
        if self.region is None:
            dst.region_min = (0.0, 0.0, 0.0)
            dst.region_max = (0.0, 0.0, 0.0)
        else:
            lo, hi = self.region
            dst.region_min = _vec3(lo, "NoiseDesc.region[0]")
            dst.region_max = _vec3(hi, "NoiseDesc.region[1]")
        bounds = list(self.boundaries or [])
        if bounds:
            arr = ffi.new("swcl_obstacle[]", len(bounds))
            for i, b in enumerate(bounds):
                _boundary_to_c(b, arr[i])
            keep.append(arr)
            dst.boundaries = arr
        else:
            dst.boundaries = ffi.NULL
        dst.boundary_count = len(bounds)
        dst.baked = 1 if self.baked else 0
        res = tuple(int(r) for r in self.bake_resolution)
        if len(res) != 3 or min(res) < 0:
            raise ValueError(f"NoiseDesc.bake_resolution must be three counts, got {self.bake_resolution!r}")
        dst.bake_resolution = res
        dst.finite_difference = 1 if self.finite_difference else 0
        dst.fd_step = self.fd_step

    def to_c(self):
        """A new ``swcl_noise_desc*`` and the objects it points into (keep both)."""
        keep: list = []
        p = ffi.new("swcl_noise_desc*", lib.swcl_noise_desc_default())
        self._to_c(p, keep)
        return p, keep

    @classmethod
    def _from_c(cls, c) -> "NoiseDesc":
        lo, hi = _tuple3(c.region_min), _tuple3(c.region_max)
        return cls(
            type=NoiseType(c.type), scale=_f32(c.scale), gain=_f32(c.gain), seed=int(c.seed),
            time_scale=_f32(c.time_scale), boundary_distance=_f32(c.boundary_distance),
            domain_walls=bool(c.domain_walls),
            region=None if lo == hi == (0.0, 0.0, 0.0) else (lo, hi),
            boundaries=[_boundary_from_c(c.boundaries[i]) for i in range(c.boundary_count)]
            if c.boundaries != ffi.NULL else [],
            baked=bool(c.baked), bake_resolution=tuple(int(c.bake_resolution[a]) for a in range(3)),
            finite_difference=bool(c.finite_difference), fd_step=_f32(c.fd_step))


# ---- the field model -----------------------------------------------------------------

def _field_model_to_c(self):
    """A new ``swcl_field_model_desc*`` and the objects it points into."""
    keep: list = []
    p = ffi.new("swcl_field_model_desc*", lib.swcl_field_model_desc_default())
    noise = self.noise if self.noise is not None else NoiseDesc()
    if not isinstance(noise, NoiseDesc):
        raise TypeError(f"FieldModel.noise must be a NoiseDesc, got {type(noise).__name__}")
    noise._to_c(p.noise, keep)
    if self.goal is None:
        p.has_goal = 0
    else:
        p.has_goal = 1
        p.goal = _vec3(self.goal, "FieldModel.goal")
    copy_scalars_to_c(self, p, "field", _FIELD_STRUCTURED)
    return p, keep


# The field model's fields: the noise and the goal by hand (a NoiseDesc; None
# or (x, y, z) for has_goal + goal), every other parameter from the library's
# table (swcl_model_parameters("field")).
_FIELD_STRUCTURED = ("has_goal", "goal")
FieldModel = make_dataclass(
    "FieldModel",
    [("noise", NoiseDesc, _model_default("noise")), ("goal", Optional[Vec3], _model_default("goal"))]
    + scalar_fields("field", _FIELD_STRUCTURED),
    namespace={"to_c": _field_model_to_c, "__module__": __name__})
FieldModel.__doc__ = (
    "swcl_field_model_desc (docs/field-model.md): the noise, an optional goal\n"
    "(None or (x, y, z)) with its pull, and minimum distance enforcement.\n"
    "Defaults are the library's (swcl_model_parameters('field')):\n" + parameter_doc("field", _FIELD_STRUCTURED))


# ---- results ------------------------------------------------------------------------

@dataclass(frozen=True)
class DeviceInfo:
    """swcl_device_info; ``index`` is usable as a device selector."""
    index: int
    type: "DeviceType"
    compute_units: int
    global_memory_bytes: int
    platform_name: str
    device_name: str
    version: str

    @classmethod
    def _from_c(cls, c) -> "DeviceInfo":
        return cls(index=int(c.index), type=DeviceType(c.type), compute_units=int(c.compute_units),
                   global_memory_bytes=int(c.global_memory_bytes),
                   platform_name=ffi.string(c.platform_name).decode("utf-8", "replace"),
                   device_name=ffi.string(c.device_name).decode("utf-8", "replace"),
                   version=ffi.string(c.version).decode("utf-8", "replace"))

    def __str__(self) -> str:
        return f"{self.platform_name} / {self.device_name}"


@dataclass(frozen=True)
class StepStats:
    """swcl_step_stats: what the model did since the last take_step_stats()."""
    agents: int
    mde_moved_last: int
    mde_moved_total: int
    steps: int

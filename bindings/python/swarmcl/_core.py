"""Context, Swarm and the free functions over the C API."""

from __future__ import annotations

import operator
import os
import weakref
from typing import Optional

import numpy as np

from ._native import constants, enum_members, ffi, lib
from .descriptors import DeviceInfo, FieldModel, NoiseDesc, StepStats
from .errors import check, error_for

__all__ = ["Context", "Swarm", "Scenario", "Recorder", "devices", "noise_sample", "version", "NO_AGENT"]

NO_AGENT: int = constants["SWCL_NO_AGENT"]
_POSITION = int(lib.SWCL_ATTRIBUTE_POSITION)
_VELOCITY = int(lib.SWCL_ATTRIBUTE_VELOCITY)
_SWARM_DEFAULT = lib.swcl_swarm_desc_default()


def version() -> str:
    """The version of the loaded library, e.g. '0.2.0'."""
    return ffi.string(lib.swcl_version_string()).decode()


def _device_info_from(fill) -> DeviceInfo:
    info = ffi.new("swcl_device_info*")
    info.struct_size = ffi.sizeof("swcl_device_info")
    check(fill(info))
    return DeviceInfo._from_c(info)


def devices() -> list:
    """Every OpenCL device of every platform (NoDeviceError without OpenCL)."""
    n = ffi.new("uint32_t*")
    check(lib.swcl_device_count(n))
    return [_device_info_from(lambda p, i=i: lib.swcl_device_get_info(i, p)) for i in range(n[0])]


# ---- arrays ----------------------------------------------------------------------

def _out_array(out, shape, dtype, what: str) -> np.ndarray:
    """``out`` if it is a writeable C-contiguous array of the shape and dtype
    (filled in place, no copy), else a new one when out is None."""
    if out is None:
        return np.empty(shape, dtype=dtype)
    if not isinstance(out, np.ndarray):
        raise TypeError(f"{what}: out must be a numpy.ndarray, got {type(out).__name__}")
    if out.dtype != dtype or out.shape != shape:
        raise ValueError(f"{what}: out must be {np.dtype(dtype).name} of shape {shape}, "
                         f"got {out.dtype.name} of shape {out.shape}")
    if not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError(f"{what}: out must be C-contiguous and writeable")
    return out


def _xyz_in(values, what: str) -> np.ndarray:
    """Any array-like of shape (N, 3) as C-contiguous float32 (one conversion,
    none when it already is)."""
    a = np.ascontiguousarray(values, dtype=np.float32)
    if a.ndim == 1 and a.size == 0:
        a = a.reshape(0, 3)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what}: expected shape (N, 3), got {a.shape}")
    return a


def _fptr(a: np.ndarray):
    return ffi.from_buffer("float[]", a) if a.size else ffi.NULL


def _uptr(a: np.ndarray):
    return ffi.from_buffer("uint32_t[]", a) if a.size else ffi.NULL


# ---- lifetime --------------------------------------------------------------------

def _destroy(fn, ctype: str, handle_id: int) -> None:
    # Runs from close(), a with-block exit, garbage collection or interpreter
    # exit; never raises (a handle already gone is fine).
    try:
        fn(ffi.new(ctype, [handle_id])[0])
    except Exception:  # pragma: no cover - interpreter shutdown
        pass


class _Handle:
    _kind = ""

    def _adopt(self, handle_ptr, destroy, ctype: str) -> None:
        self._hp = handle_ptr           # owns the memory the handle struct views
        self._h = handle_ptr[0]         # passed by value to every call
        self._finalizer = weakref.finalize(self, _destroy, destroy, ctype, int(handle_ptr[0].id))

    @property
    def handle_id(self) -> int:
        """The C handle's id (never reused by the library)."""
        return int(self._h.id)

    @property
    def closed(self) -> bool:
        return not self._finalizer.alive

    def close(self) -> None:
        """Releases the C object now (also done by ``with`` and garbage
        collection).  Later calls raise InvalidHandleError."""
        self._finalizer()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self.closed else f"id={self.handle_id}"
        return f"<swarmcl.{type(self).__name__} {state}>"


class Context(_Handle):
    """An OpenCL device with swarmcl's kernels built for it.

    ``device``: None (``$SWARMCL_DEVICE``, else the first GPU, else the first
    CPU), an index (``0``) or a case-insensitive part of the platform or device
    name (``"pthread"``, ``"nvidia"``)."""

    def __init__(self, device=None, build_options: Optional[str] = None):
        desc = ffi.new("swcl_context_desc*", lib.swcl_context_desc_default())
        keep = []
        if device is not None:
            keep.append(ffi.new("char[]", str(device).encode()))
            desc.device = keep[-1]
        if build_options:
            keep.append(ffi.new("char[]", str(build_options).encode()))
            desc.build_options = keep[-1]
        out = ffi.new("swcl_context*")
        check(lib.swcl_context_create(desc, out))
        self._adopt(out, lib.swcl_context_destroy, "swcl_context*")

    @property
    def device(self) -> DeviceInfo:
        """The device the context runs on."""
        return _device_info_from(lambda p: lib.swcl_context_device_info(self._h, p))


class Swarm(_Handle):
    """A swarm of agents on a context's device.

    Arguments left at None take swcl_swarm_desc_default()'s values, except that
    ``capacity`` grows to ``agent_count`` when only the latter is given.
    ``domain`` is ((x0, y0, z0), (x1, y1, z1)) in metres.  Swarms stay usable
    after their context is closed.

    ``worlds=W`` holds W independent swarms of ``agent_count`` agents each,
    stepped by the same launches (docs/architecture.md, "Worlds"): world k is
    seeded with ``world_seeds[k]`` (default ``seed + k``) and runs bitwise as
    the same swarm alone; positions, velocities and query results are then
    shaped (W, N, ...), and ``set_world_param`` gives the model's parameters
    one value per world.  ``world_domains`` (shape (W, 2, 3): world k's
    minimum and maximum corner) gives each world a domain of its own, in
    place of ``domain``: world k is then placed in, and its grid and noise
    cover, its own box, as the same swarm alone with that domain."""

    def __init__(self, context: Context, capacity: Optional[int] = None,
                 agent_count: Optional[int] = None, seed: Optional[int] = None,
                 domain=None, interaction_radius: Optional[float] = None,
                 dt: Optional[float] = None, worlds: Optional[int] = None, world_seeds=None,
                 world_domains=None):
        if not isinstance(context, Context):
            raise TypeError(f"context must be a swarmcl.Context, got {type(context).__name__}")
        desc = ffi.new("swcl_swarm_desc*", _SWARM_DEFAULT)
        if capacity is None and agent_count is not None:
            capacity = max(int(desc.capacity), operator.index(agent_count))
        for name, value in (("capacity", capacity), ("agent_count", agent_count), ("seed", seed)):
            if value is not None:
                value = operator.index(value)
                limit = 2**64 if name == "seed" else 2**32
                if not 0 <= value < limit:
                    raise ValueError(f"Swarm: {name} must be in [0, {limit}), got {value}")
                setattr(desc, name, value)
        if domain is not None:
            lo, hi = domain
            desc.domain_min = tuple(float(v) for v in lo)
            desc.domain_max = tuple(float(v) for v in hi)
        if interaction_radius is not None:
            desc.interaction_radius = interaction_radius
        if dt is not None:
            desc.dt = dt
        keep = None
        if worlds is not None:
            w = operator.index(worlds)
            if not 1 <= w < 2**32:
                raise ValueError(f"Swarm: worlds must be in [1, 2**32), got {w}")
            desc.worlds = w
        if world_seeds is not None:
            seeds = np.asarray(world_seeds)
            if seeds.ndim != 1 or seeds.shape[0] != int(desc.worlds) or not np.issubdtype(seeds.dtype, np.integer):
                raise ValueError(f"Swarm: world_seeds must be {int(desc.worlds)} integers (one per world), "
                                 f"got shape {seeds.shape} of {seeds.dtype}")
            if (seeds < 0).any():
                raise ValueError("Swarm: world_seeds must be >= 0")
            keep = np.ascontiguousarray(seeds, dtype=np.uint64)
            desc.world_seeds = ffi.cast("const uint64_t*", keep.ctypes.data)
        keep_domains = None
        if world_domains is not None:
            boxes = np.asarray(world_domains, dtype=np.float64)
            if boxes.shape != (int(desc.worlds), 2, 3):
                raise ValueError(f"Swarm: world_domains must be shaped ({int(desc.worlds)}, 2, 3) (a minimum and a "
                                 f"maximum corner per world), got {boxes.shape}")
            keep_domains = np.ascontiguousarray(boxes, dtype=np.float32)
            desc.world_domains = ffi.cast("const float*", keep_domains.ctypes.data)
        out = ffi.new("swcl_swarm*")
        check(lib.swcl_swarm_create(context._h, desc, out))
        self._init_handle(out, context)

    def _init_handle(self, handle_ptr, context: Context) -> None:
        self._adopt(handle_ptr, lib.swcl_swarm_destroy, "swcl_swarm*")
        self.context = context
        self._u32 = ffi.new("uint32_t*")
        self._u64 = ffi.new("uint64_t*")

    @classmethod
    def _wrap(cls, handle_ptr, context: Context) -> "Swarm":
        """A Swarm object owning a handle made elsewhere (a scenario)."""
        s = cls.__new__(cls)
        s._init_handle(handle_ptr, context)
        return s

    # ---- counts --------------------------------------------------------------

    @property
    def agent_count(self) -> int:
        """Agents of each world (of the swarm, with one world)."""
        check(lib.swcl_swarm_agent_count(self._h, self._u32))
        return int(self._u32[0])

    @property
    def worlds(self) -> int:
        """Independent worlds in the swarm (1 unless created with ``worlds``)."""
        check(lib.swcl_swarm_worlds(self._h, self._u32))
        return int(self._u32[0])

    @property
    def world_domains(self) -> np.ndarray:
        """Each world's domain, shaped (W, 2, 3): its minimum and maximum
        corner (every world's is the swarm's unless created with
        ``world_domains``)."""
        out = np.empty((self.worlds, 2, 3), dtype=np.float32)
        check(lib.swcl_swarm_world_domains(self._h, ffi.cast("float*", out.ctypes.data), out.shape[0]))
        return out.astype(np.float64)

    def _shape(self, *tail):
        """(N, *tail) with one world, (W, N, *tail) with several, and the
        total count of agents."""
        n, w = self.agent_count, self.worlds
        return ((n, *tail) if w == 1 else (w, n, *tail)), n * w

    def __len__(self) -> int:
        return self.agent_count

    @property
    def step_count(self) -> int:
        """Steps simulated so far."""
        check(lib.swcl_swarm_step_count(self._h, self._u64))
        return int(self._u64[0])

    # ---- state -----------------------------------------------------------------

    def _read(self, attribute: int, out, what: str) -> np.ndarray:
        shape, total = self._shape(3)
        out = _out_array(out, shape, np.float32, what)
        check(lib.swcl_swarm_read(self._h, attribute, _fptr(out), total))
        return out

    def _write(self, attribute: int, values, what: str) -> None:
        v = np.asarray(values)
        if v.ndim == 3:  # (W, N, 3): the worlds one after another
            v = v.reshape(-1, 3) if v.shape[2] == 3 else v
        a = _xyz_in(v, what)
        check(lib.swcl_swarm_write(self._h, attribute, _fptr(a), a.shape[0]))

    def read_positions(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Positions (N, 3) float32 in agent-id order, written straight into
        ``out`` (a C-contiguous float32 array, returned) or a new array."""
        return self._read(_POSITION, out, "read_positions")

    def step_frames(self, frames: int, every: int = 1, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Steps ``frames`` x ``every`` steps and returns the positions after
        each ``every`` steps, shaped (frames, N, 3) (with worlds (frames, W,
        N, 3)): the frames step(every) then read_positions() would give,
        gathered on the device without waiting for it after each.  ``out``:
        a C-contiguous float32 array of that shape, written in place and
        returned (checked before any step)."""
        f, e = operator.index(frames), operator.index(every)
        if not 0 <= f < 2**32 or not 1 <= e < 2**32:
            raise ValueError(f"step_frames: frames must be >= 0 and every >= 1, got {frames}, {every}")
        shape, total = self._shape(3)
        out = _out_array(out, (f,) + shape, np.float32, "step_frames")
        check(lib.swcl_swarm_step_frames(self._h, f, e, _fptr(out), f * total))
        return out

    def read_velocities(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Velocities (N, 3) float32, like read_positions."""
        return self._read(_VELOCITY, out, "read_velocities")

    def write_positions(self, positions) -> None:
        """Sets positions from any (N, 3) array-like; the agent count becomes N
        (<= capacity); new agents start at rest."""
        self._write(_POSITION, positions, "write_positions")

    def write_velocities(self, velocities) -> None:
        """Sets velocities from any (N, 3) array-like, N = agent_count."""
        self._write(_VELOCITY, velocities, "write_velocities")

    positions = property(lambda self: self.read_positions(), write_positions,
                         doc="Positions as a new (N, 3) float32 array; assigning writes them.")
    velocities = property(lambda self: self.read_velocities(), write_velocities,
                          doc="Velocities as a new (N, 3) float32 array; assigning writes them.")

    # ---- stepping ----------------------------------------------------------------

    def step(self, steps: int = 1) -> None:
        """Advances ``steps`` time steps of dt (ballistic without a model)."""
        try:
            status = lib.swcl_swarm_step(self._h, steps)
        except (OverflowError, TypeError) as exc:
            raise ValueError(f"step: steps must be an integer in [0, 2**32), got {steps!r}") from exc
        if status:
            raise error_for(status)

    # ---- checkpoints ---------------------------------------------------------------

    def save(self, path) -> None:
        """Saves the swarm with its model to ``path`` (swcl_swarm_save,
        docs/checkpoint-format.md), atomically: a failed save leaves an earlier
        file at ``path`` as it was."""
        check(lib.swcl_swarm_save(self._h, os.fsencode(path)))

    @classmethod
    def load(cls, context: Context, path) -> "Swarm":
        """A new swarm in ``context`` from a file ``save`` wrote: stepping it
        goes on bit for bit as the saved swarm would.  A truncated, corrupted
        or foreign file raises ParseError with the reason; an unreadable one
        IOError_."""
        if not isinstance(context, Context):
            raise TypeError(f"context must be a swarmcl.Context, got {type(context).__name__}")
        out = ffi.new("swcl_swarm*")
        check(lib.swcl_swarm_load(context._h, os.fsencode(path), out))
        return cls._wrap(out, context)

    def set_field_model(self, model: FieldModel) -> None:
        """Moves the swarm with the curl-noise paper's field model from the next step."""
        if not isinstance(model, FieldModel):
            raise TypeError(f"set_field_model: expected a FieldModel, got {type(model).__name__}")
        desc, _keep = model.to_c()
        check(lib.swcl_swarm_field_set_model(self._h, desc))

    # ---- the force model (docs/force-model.md) -----------------------------------------

    def set_force_model(self, model) -> None:
        """Moves the swarm with the shape-constrained force model from the next step."""
        from .force import ForceModel
        if not isinstance(model, ForceModel):
            raise TypeError(f"set_force_model: expected a ForceModel, got {type(model).__name__}")
        desc, _keep = model.to_c()
        check(lib.swcl_swarm_force_set_model(self._h, desc))

    def set_force_keyframes(self, keyframes, period: int = 0) -> None:
        """Replaces the force model's keyframes (a list of Keyframe)."""
        from .force import keyframes_to_c
        keep: list = []
        arr, count = keyframes_to_c(list(keyframes), keep)
        check(lib.swcl_swarm_force_set_keyframes(self._h, arr, count, int(period)))

    def set_force_path(self, points, speed: float) -> None:
        """Replaces the force model's path: B-spline control points (K >= 4, 3), m/s."""
        from .force import path_to_c
        keep: list = []
        ptr, count = path_to_c(points, keep)
        check(lib.swcl_swarm_force_set_path(self._h, ptr, count, float(speed)))

    def force_targets(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Each agent's current target point (N, 3) float32, agent-id order."""
        n = self.agent_count
        out = _out_array(out, (n, 3), np.float32, "force_targets")
        check(lib.swcl_swarm_force_get_targets(self._h, _fptr(out), n))
        return out
    # ---- the policy model (bindings/python/swarmcl/policy.py) -------------------------

    def set_policy_model(self, model=None) -> None:
        """Moves the swarm with a trained policy (a PolicyModel; default: the
        shipped policy with a joystick leader) from the next step."""
        from .policy import PolicyModel
        model = PolicyModel() if model is None else model
        if not isinstance(model, PolicyModel):
            raise TypeError(f"set_policy_model: expected a PolicyModel, got {type(model).__name__}")
        desc, _keep = model.to_c()
        check(lib.swcl_swarm_policy_set_model(self._h, desc))

    def set_policy_leader_controls(self, du: float, dq) -> None:
        """Joystick leader: speed change and heading change (3,) per step."""
        c = np.asarray([du, *np.asarray(dq, dtype=np.float32).reshape(3)], dtype=np.float32)
        check(lib.swcl_swarm_policy_set_leader_controls(self._h, _fptr(c)))

    def policy_leader(self):
        """The leader now: (position (3,), heading (3,), speed)."""
        p = np.zeros(3, np.float32)
        v = np.zeros(4, np.float32)
        check(lib.swcl_swarm_policy_get_leader(self._h, _fptr(p), _fptr(v)))
        return p, v[:3].copy(), float(v[3])

    def policy_observe(self):
        """Observations (N, obs_dim) of the current state and the policy's
        actions (N, 4) on them, agent-id order ((W, N, ...) with worlds)."""
        dim = ffi.new("uint32_t*")
        check(lib.swcl_swarm_policy_get_info(self._h, dim, ffi.NULL, ffi.NULL))
        n = self.agent_count * self.worlds
        obs = np.zeros((n, int(dim[0])), np.float32)
        act = np.zeros((n, 4), np.float32)
        check(lib.swcl_swarm_policy_observe(self._h, _fptr(obs), _fptr(act), n))
        return obs.reshape(self._shape(int(dim[0]))[0]), act.reshape(self._shape(4)[0])

    def policy_infer(self, obs) -> np.ndarray:
        """The policy's MLP alone on observations (N, obs_dim) (or (W, N,
        obs_dim)): its actions (N, 4) (same leading shape), as a step
        computes them.  Non-finite observations are refused."""
        dim = ffi.new("uint32_t*")
        check(lib.swcl_swarm_policy_get_info(self._h, dim, ffi.NULL, ffi.NULL))
        x = np.ascontiguousarray(obs, dtype=np.float32)
        if x.ndim < 1 or x.shape[-1] != int(dim[0]):
            raise ValueError(f"policy_infer: expected observations (..., {int(dim[0])}), got shape {x.shape}")
        n = x.size // int(dim[0])
        act = np.zeros((n, 4), np.float32)
        check(lib.swcl_swarm_policy_infer(self._h, _fptr(x), n, _fptr(act)))
        return act.reshape(x.shape[:-1] + (4,))

    # ---- the path model (bindings/python/swarmcl/path.py) -----------------------------

    def set_path_model(self, model) -> None:
        """Preprocesses and moves the swarm with the curl-noise paper's path model."""
        from .path import PathModel
        if not isinstance(model, PathModel):
            raise TypeError(f"set_path_model: expected a PathModel, got {type(model).__name__}")
        desc, _keep = model.to_c()
        check(lib.swcl_swarm_path_set_model(self._h, desc))

    def set_path_goals(self, group: int, goals) -> float:
        """Moves a group's goals (its cost field is recomputed); returns the seconds it took."""
        from .path import _goals_to_c
        keep: list = []
        arr, n = _goals_to_c(goals, keep)
        seconds = ffi.new("double*")
        check(lib.swcl_swarm_path_set_goals(self._h, group, arr, n, seconds))
        return float(seconds[0])

    def path_info(self):
        """The path grid and preprocessing times (PathInfo)."""
        from .path import PathInfo
        out = ffi.new("swcl_path_info*")
        out.struct_size = ffi.sizeof("swcl_path_info")
        check(lib.swcl_swarm_path_get_info(self._h, out))
        return PathInfo(grid=tuple(int(out.grid[a]) for a in range(3)), cell=float(out.cell),
                        grid_min=tuple(float(out.grid_min[a]) for a in range(3)),
                        preprocess_seconds=float(out.preprocess_seconds), groups=int(out.groups),
                        recomputes=int(out.recomputes), recompute_seconds=float(out.recompute_seconds))

    # ---- the path model's chasing targets and lamp (curl-noise paper §7) ----------------

    def add_path_target(self, target) -> int:
        """Adds a chasing target (PathTarget); returns its index."""
        from .path import PathTarget
        if not isinstance(target, PathTarget):
            raise TypeError(f"add_path_target: expected a PathTarget, got {type(target).__name__}")
        index = ffi.new("uint32_t*")
        check(lib.swcl_swarm_path_add_target(self._h, target._to_c(), index))
        return int(index[0])

    def set_path_target(self, index: int, center) -> float:
        """Moves target ``index`` (e.g. each step, as a user drags it); its group's cost field
        and the noise boundaries are recomputed when it moved.  Returns the seconds it took."""
        from .descriptors import _vec3
        c = ffi.new("float[3]", list(_vec3(center, "center")))
        seconds = ffi.new("double*")
        check(lib.swcl_swarm_path_set_target(self._h, index, c, seconds))
        return float(seconds[0])

    def path_target(self, index: int):
        """Target ``index`` as a PathTarget."""
        from .path import PathTarget
        out = ffi.new("swcl_path_target*")
        check(lib.swcl_swarm_path_get_target(self._h, index, out))
        return PathTarget(center=tuple(float(out.center[a]) for a in range(3)), radius=float(out.radius),
                          group=int(out.group))

    def path_target_count(self) -> int:
        out = ffi.new("uint32_t*")
        check(lib.swcl_swarm_path_target_count(self._h, out))
        return int(out[0])

    def set_path_lamp(self, lamp) -> None:
        """Sets the phototaxis lamp (Lamp; enabled=False turns it off)."""
        from .path import Lamp
        if not isinstance(lamp, Lamp):
            raise TypeError(f"set_path_lamp: expected a Lamp, got {type(lamp).__name__}")
        check(lib.swcl_swarm_path_set_lamp(self._h, lamp._to_c()))

    def clear_model(self) -> None:
        """Back to ballistic motion."""
        check(lib.swcl_swarm_clear_model(self._h))

    # FASTSWARM energy model (swarmcl/energy.py, docs/energy-model.md).
    def set_energy_model(self, dataset, model=None) -> None:
        """Moves the swarm with the FASTSWARM energy model over ``dataset`` (a
        Dataset) from the next step; ``model``: an EnergyModel (default: Table 1
        aggregation)."""
        from . import energy
        energy.set_energy_model(self, dataset, model)

    def set_energy_stimuli(self, stimuli) -> None:
        """Replaces the energy model's stimuli (a list of Stimulus)."""
        from . import energy
        energy.set_stimuli(self, stimuli)

    def set_energy_keypoints(self, keypoints, closed: bool = True) -> None:
        """Replaces the energy model's keypoint curve ((n >= 2, 3) array)."""
        from . import energy
        energy.set_keypoints(self, keypoints, closed)

    def start_from_tracks(self, tracks, **options) -> None:
        """Trajectory synthesis: one agent per track ``[(times, positions), ...]``
        at its last sample with its last velocity (options as Dataset.from_tracks:
        unit_scale, gap_factor, smoothing, ...); then step to continue them."""
        from . import energy
        energy.start_from_tracks(self, tracks, **options)

    def energy_goals(self) -> np.ndarray:
        """Each agent's goal keypoint index (int32, -1 before the first step)."""
        from . import energy
        return energy.goals(self)

    def take_step_stats(self) -> StepStats:
        """Model statistics since the last call (waits for the device), summed
        over the worlds."""
        out = ffi.new("swcl_step_stats*")
        out.struct_size = ffi.sizeof("swcl_step_stats")
        check(lib.swcl_swarm_take_step_stats(self._h, out))
        return StepStats(agents=int(out.agents), mde_moved_last=int(out.mde_moved_last),
                         mde_moved_total=int(out.mde_moved_total), steps=int(out.steps))

    def take_world_step_stats(self) -> list:
        """The same per world: a list of W StepStats."""
        w = self.worlds
        out = ffi.new("swcl_step_stats[]", w)
        for k in range(w):
            out[k].struct_size = ffi.sizeof("swcl_step_stats")
        check(lib.swcl_swarm_take_world_step_stats(self._h, out, w))
        return [StepStats(agents=int(o.agents), mde_moved_last=int(o.mde_moved_last),
                          mde_moved_total=int(o.mde_moved_total), steps=int(o.steps)) for o in out]

    # ---- worlds ----------------------------------------------------------------------

    def set_world_param(self, name: str, values) -> None:
        """Parameter ``name`` of the swarm's model (a key of its table, e.g.
        "noise.scale", "goal.speed"; swarmcl.model_parameters lists them) in
        every world: W values, or (W, 3) for a vector.  All are checked before
        any is set; a bad one raises InvalidArgumentError naming the
        parameter, the world and the valid range, and nothing changes."""
        if not isinstance(name, str):
            raise TypeError(f"set_world_param: name must be a str, got {type(name).__name__}")
        v = np.ascontiguousarray(np.asarray(values, dtype=np.float64).reshape(-1))
        check(lib.swcl_swarm_set_world_param(self._h, name.encode(), ffi.cast("const double*", v.ctypes.data),
                                             v.shape[0]))

    def world_param(self, name: str) -> np.ndarray:
        """Parameter ``name`` in every world: (W,) or (W, 3) float64."""
        if not isinstance(name, str):
            raise TypeError(f"world_param: name must be a str, got {type(name).__name__}")
        count = ffi.new("size_t*")
        check(lib.swcl_swarm_get_world_param(self._h, name.encode(), ffi.NULL, 0, count))
        out = np.zeros(int(count[0]), np.float64)
        check(lib.swcl_swarm_get_world_param(self._h, name.encode(), ffi.cast("double*", out.ctypes.data),
                                             out.shape[0], ffi.NULL))
        w = self.worlds
        return out if out.shape[0] == w else out.reshape(w, -1)

    # ---- neighbour queries -----------------------------------------------------------

    def neighbor_count(self, radius: float, out: Optional[np.ndarray] = None) -> np.ndarray:
        """Number of other agents within ``radius`` of each agent, uint32 (N,)."""
        shape, n = self._shape()
        out = _out_array(out, shape, np.uint32, "neighbor_count")
        check(lib.swcl_swarm_neighbor_count(self._h, radius, _uptr(out), n))
        return out

    def nearest_neighbor(self):
        """(distances float32 (N,), ids uint32 (N,)) of each agent's nearest
        other agent; alone: (inf, NO_AGENT)."""
        shape, n = self._shape()
        dist = np.empty(shape, np.float32)
        ids = np.empty(shape, np.uint32)
        check(lib.swcl_swarm_nearest_neighbor(self._h, _fptr(dist), _uptr(ids), n))
        return dist, ids

    def neighbor_lists(self, radius: float, max_neighbors: int):
        """(ids uint32 (N, max_neighbors) nearest first, padded with NO_AGENT;
        counts uint32 (N,) full neighbour counts; number of truncated lists)."""
        shape, n = self._shape()
        cap = operator.index(max_neighbors)
        if cap < 0:
            raise ValueError(f"neighbor_lists: max_neighbors must be >= 0, got {cap}")
        ids = np.empty((*shape, cap), np.uint32)
        counts = np.empty(shape, np.uint32)
        truncated = ffi.new("uint32_t*")
        check(lib.swcl_swarm_neighbor_lists(self._h, radius, cap, _uptr(ids), _uptr(counts), n, truncated))
        return ids, counts, int(truncated[0])


def noise_sample(context: Context, desc: NoiseDesc, points, time: float = 0.0, step: int = 0,
                 out: Optional[np.ndarray] = None) -> np.ndarray:
    """Evaluates a noise field at (N, 3) points; returns (N, 3) float32
    velocities (into ``out`` when given).  Point i counts as agent i for WHITE
    and GAUSSIAN noise."""
    if not isinstance(context, Context):
        raise TypeError(f"context must be a swarmcl.Context, got {type(context).__name__}")
    if not isinstance(desc, NoiseDesc):
        raise TypeError(f"desc must be a NoiseDesc, got {type(desc).__name__}")
    pts = _xyz_in(points, "noise_sample")
    out = _out_array(out, pts.shape, np.float32, "noise_sample")
    cdesc, _keep = desc.to_c()
    check(lib.swcl_noise_sample(context._h, cdesc, _fptr(pts), pts.shape[0], time, step, _fptr(out)))
    return out


# ---- scenario files and recording ------------------------------------------------

def _export_formats(formats) -> int:
    """'csv' | 'npy' | 'vtp', a list of them, or the swcl_export_format bits."""
    if isinstance(formats, int):
        return formats
    if isinstance(formats, str):
        formats = [formats]
    bits = 0
    for f in formats:
        name = "SWCL_EXPORT_" + str(f).strip().upper()
        if name not in enum_members("swcl_export_format"):
            raise ValueError(f"unknown export format {f!r}; one of csv, npy, vtp")
        bits |= int(getattr(lib, name))
    return bits


def _format_names(bits: int) -> tuple:
    elements = enum_members("swcl_export_format")
    return tuple(k[len("SWCL_EXPORT_"):].lower() for k, v in sorted(elements.items(), key=lambda kv: kv[1])
                 if bits & v)


class Scenario(_Handle):
    """A validated scenario (docs/scenarios.md), from ``Scenario.load(path)``
    or ``Scenario.parse(json_text)``.  A malformed file raises ParseError
    naming the line and column or the key path ("model.noise.scale: ...");
    an unreadable one IOError_."""

    def __init__(self, _handle_ptr):
        """Use Scenario.load() or Scenario.parse()."""
        self._adopt(_handle_ptr, lib.swcl_scenario_destroy, "swcl_scenario*")

    @classmethod
    def load(cls, path) -> "Scenario":
        out = ffi.new("swcl_scenario*")
        check(lib.swcl_scenario_load(os.fsencode(path), out))
        return cls(out)

    @classmethod
    def parse(cls, text) -> "Scenario":
        data = text.encode("utf-8") if isinstance(text, str) else bytes(text)
        out = ffi.new("swcl_scenario*")
        check(lib.swcl_scenario_parse(data, len(data), out))
        return cls(out)

    @property
    def info(self) -> dict:
        """name, agents, steps, dt, seed, model, output_dir, output_every, output_formats."""
        p = ffi.new("swcl_scenario_info*")
        p.struct_size = ffi.sizeof("swcl_scenario_info")
        check(lib.swcl_scenario_get_info(self._h, p))
        return {
            "name": ffi.string(p.name).decode("utf-8", "replace"),
            "agents": int(p.agents), "steps": int(p.steps), "dt": float(p.dt), "seed": int(p.seed),
            "model": ffi.string(p.model).decode(),
            "output_dir": ffi.string(p.output_dir).decode("utf-8", "replace"),
            "output_every": int(p.output_every), "output_formats": _format_names(int(p.output_formats)),
        }

    def create_swarm(self, context: Context) -> "Swarm":
        """A swarm as the scenario describes it: agents placed, velocities set,
        model attached."""
        if not isinstance(context, Context):
            raise TypeError(f"context must be a swarmcl.Context, got {type(context).__name__}")
        out = ffi.new("swcl_swarm*")
        check(lib.swcl_scenario_create_swarm(self._h, context._h, out))
        return Swarm._wrap(out, context)

    def create_world_swarm(self, context: Context, worlds: int, world_seeds=None, world_domains=None) -> "Swarm":
        """The scenario as ``worlds`` worlds of one swarm (Swarm's ``worlds``):
        world k placed and seeded as the scenario alone with seed
        ``world_seeds[k]`` (default: the scenario's seed + k), each with the
        scenario's model; ``Swarm.set_world_param`` then varies it per world.
        ``world_domains`` (shape (worlds, 2, 3), as Swarm's): world k is the
        scenario alone in that domain (None: the scenario's in every world)."""
        if not isinstance(context, Context):
            raise TypeError(f"context must be a swarmcl.Context, got {type(context).__name__}")
        w = operator.index(worlds)
        if not 1 <= w < 2**32:
            raise ValueError(f"create_world_swarm: worlds must be in [1, 2**32), got {w}")
        seeds = ffi.NULL
        if world_seeds is not None:
            arr = np.asarray(world_seeds)
            if arr.shape != (w,) or not np.issubdtype(arr.dtype, np.integer) or (arr < 0).any():
                raise ValueError(f"create_world_swarm: world_seeds must be {w} integers >= 0")
            keep = np.ascontiguousarray(arr, dtype=np.uint64)
            seeds = ffi.cast("const uint64_t*", keep.ctypes.data)
        out = ffi.new("swcl_swarm*")
        if world_domains is None:
            check(lib.swcl_scenario_create_world_swarm(self._h, context._h, w, seeds, out))
        else:
            boxes = np.asarray(world_domains, dtype=np.float64)
            if boxes.shape != (w, 2, 3):
                raise ValueError(f"create_world_swarm: world_domains must be shaped ({w}, 2, 3) (a minimum and a "
                                 f"maximum corner per world), got {boxes.shape}")
            keep_domains = np.ascontiguousarray(boxes, dtype=np.float32)
            check(lib.swcl_scenario_create_world_swarm_in_domains(
                self._h, context._h, w, seeds, ffi.cast("const float*", keep_domains.ctypes.data), out))
        return Swarm._wrap(out, context)


class Recorder(_Handle):
    """Writes frames of a swarm to ``directory`` as ``formats`` ('csv', 'npy',
    'vtp' or a list).  Files appear complete on ``finish()``; closing without
    finishing discards the CSV, .npy and .pvd files."""

    def __init__(self, directory, basename: str = "swarm", formats=("csv",)):
        out = ffi.new("swcl_recorder*")
        check(lib.swcl_recorder_create(os.fsencode(directory), str(basename).encode(),
                                       _export_formats(formats), out))
        self._adopt(out, lib.swcl_recorder_destroy, "swcl_recorder*")

    def add_frame(self, swarm: Swarm, frame: int, time: float = 0.0) -> None:
        check(lib.swcl_recorder_add_frame(self._h, swarm._h, frame, time))

    def finish(self) -> None:
        check(lib.swcl_recorder_finish(self._h))

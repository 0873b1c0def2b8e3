"""FASTSWARM from Python: reference datasets and the energy model
(docs/energy-model.md).

>>> import swarmcl
>>> with swarmcl.Context() as ctx, swarmcl.Swarm(ctx, agent_count=37, dt=0.01) as s:
...     data = swarmcl.Dataset.synthetic(k=300)
...     s.set_energy_model(data, swarmcl.EnergyModel(centre=(0, 0, 0)))
...     s.step(100)

EnergyModel's and EnergyWeights' scalar fields, their defaults and docs come
from the library's parameter table (``swarmcl.model_parameters("energy")``);
the other defaults from the C library's ``*_default()``.
"""

from __future__ import annotations

import enum
import os
from dataclasses import dataclass, field, make_dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ._core import _Handle, _xyz_in
from ._native import ffi, lib
from .descriptors import NoiseDesc, _tuple3, _vec3
from .errors import check
from .params import c_ordered_fields, copy_scalars_to_c, parameter_doc, scalar_defaults, scalar_fields

__all__ = ["Dataset", "EnergyWeights", "EnergyModel", "Stimulus", "StimulusKind", "TimeFormat",
           "write_mixed_csv"]

Vec3 = Tuple[float, float, float]

_DATASET_DEFAULT = lib.swcl_dataset_desc_default()
_ENERGY_DEFAULT = lib.swcl_energy_model_desc_default()


class TimeFormat(enum.IntEnum):
    """swcl_time_format of a track CSV's time column."""
    AUTO = int(lib.SWCL_TIME_AUTO)
    SECONDS = int(lib.SWCL_TIME_SECONDS)
    FRAME = int(lib.SWCL_TIME_FRAME)
    DATETIME = int(lib.SWCL_TIME_DATETIME)


class StimulusKind(enum.IntEnum):
    ATTRACT = int(lib.SWCL_STIMULUS_ATTRACT)
    STARTLE = int(lib.SWCL_STIMULUS_STARTLE)


_ROLES = ("id", "time", "x", "y", "z")
_TRACK_OPTIONS = ("columns", "delimiter", "time_format", "frame_time", "unit_scale", "gap_factor", "smoothing", "k",
                  "groups", "seed", "mean_speed")
# What reading tracks for the evaluation takes (no dataset subsampling).
_METRIC_TRACK_OPTIONS = ("columns", "delimiter", "time_format", "frame_time", "unit_scale", "gap_factor", "smoothing")


def _columns(columns) -> dict:
    """The track columns as {role: name or index}: a dict of some roles, or
    all five in role order as "id,time,x,y,z" (the CLI's --columns) or a
    sequence."""
    if columns is None:
        return {}
    if isinstance(columns, str):
        columns = columns.split(",")
    if isinstance(columns, dict):
        for role in columns:
            if role not in _ROLES:
                raise ValueError(f"columns: unknown role {role!r} (id, time, x, y, z)")
        return dict(columns)
    names = list(columns)
    if len(names) != 5:
        raise ValueError(f"columns: expected five names, id,time,x,y,z, got {len(names)}: {names!r}")
    return dict(zip(_ROLES, names))


def _dataset_desc(columns=None, time_format="auto", frame_time=None, unit_scale=None, gap_factor=None,
                  smoothing=None, k=None, groups=None, seed=None, mean_speed=None, delimiter=None):
    d = ffi.new("swcl_dataset_desc*", lib.swcl_dataset_desc_default())
    keep = []
    for role, name in _columns(columns).items():
        c = ffi.new("char[]", str(name).encode())
        keep.append(c)
        setattr(d, "column_" + role, c)
    if delimiter is not None:
        text = "\t" if delimiter == "tab" else delimiter
        if not isinstance(text, str) or len(text) != 1 or text in "\r\n\0":
            raise ValueError(f"delimiter: one character such as ',', ';' or '\\t', or 'tab', got {delimiter!r}")
        d.delimiter = text.encode()
    if isinstance(time_format, str):
        try:
            time_format = TimeFormat[time_format.upper()]
        except KeyError:
            raise ValueError(f"time_format: one of auto, seconds, frame, datetime, got {time_format!r}") from None
    d.time_format = int(time_format)
    for name, value in (("frame_time", frame_time), ("unit_scale", unit_scale), ("gap_factor", gap_factor),
                        ("smoothing", smoothing), ("k", k), ("groups", groups), ("seed", seed),
                        ("synthetic_mean_speed", mean_speed)):
        if value is not None:
            setattr(d, name, value)
    return d, keep


def _track_desc(what: str, options: dict, allowed=_TRACK_OPTIONS):
    """_dataset_desc(**options) for the public function `what`, an unknown
    option named with the ones it takes."""
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise TypeError(f"{what}: unknown option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)} "
                        f"(it takes {', '.join(allowed)})")
    return _dataset_desc(**options)


def _track_arrays(tracks, what):
    counts, times, xyz = [], [], []
    for t, p in tracks:
        t = np.ascontiguousarray(t, dtype=np.float64).ravel()
        p = _xyz_in(p, what)
        if len(t) != len(p):
            raise ValueError(f"{what}: {len(t)} times but {len(p)} positions")
        counts.append(len(t))
        times.append(t)
        xyz.append(p)
    c = np.asarray(counts, dtype=np.uint32)
    t = np.ascontiguousarray(np.concatenate(times) if times else np.zeros(0), dtype=np.float64)
    p = np.ascontiguousarray(np.concatenate(xyz) if xyz else np.zeros((0, 3)), dtype=np.float32)
    return c, t, p


def _track_pointers(c, t, p):
    return (ffi.from_buffer("uint32_t[]", c) if c.size else ffi.NULL, len(c),
            ffi.from_buffer("double[]", t) if t.size else ffi.NULL,
            ffi.from_buffer("float[]", p) if p.size else ffi.NULL)


class Dataset(_Handle):
    """The reference dataset D: (velocity, acceleration) samples sorted by
    speed, in speed groups.  Build it with from_csv / from_tracks /
    synthetic, or load a file written by save."""

    _kind = "dataset"

    def __init__(self, _handle_ptr):
        self._adopt(_handle_ptr, lib.swcl_dataset_destroy, "swcl_dataset*")

    @classmethod
    def _make(cls, fn) -> "Dataset":
        h = ffi.new("swcl_dataset*")
        check(fn(h))
        return cls(h)

    @classmethod
    def from_csv(cls, path, **options) -> "Dataset":
        """From a track CSV: ``columns={"id": "id", "time": "datetime", "x": "x_cm", ...}``
        (names or 0-based indices; or all five as "id,time,x,y,z" or a list),
        ``delimiter`` (",", ";", "\\t" or "tab"), ``time_format``, ``frame_time``,
        ``unit_scale``, ``gap_factor``, ``smoothing``, ``k``, ``groups``, ``seed``."""
        d, _keep = _track_desc("Dataset.from_csv", options)
        return cls._make(lambda h: lib.swcl_dataset_from_csv(os.fsencode(path), d, h))

    @classmethod
    def from_tracks(cls, tracks: Sequence[Tuple[Sequence[float], Sequence[Sequence[float]]]],
                    **options) -> "Dataset":
        """From tracks given as ``[(times, positions), ...]`` (times in s, positions (n, 3))."""
        c, t, p = _track_arrays(tracks, "from_tracks")
        d, _keep = _track_desc("Dataset.from_tracks", options)
        return cls._make(lambda h: lib.swcl_dataset_from_tracks(*_track_pointers(c, t, p), d, h))

    @classmethod
    def synthetic(cls, k: Optional[int] = None, groups: Optional[int] = None, seed: Optional[int] = None,
                  frame_time: Optional[float] = None, mean_speed: Optional[float] = None) -> "Dataset":
        """From deterministic synthetic tracks (tests and examples without data)."""
        d, _keep = _dataset_desc(k=k, groups=groups, seed=seed, frame_time=frame_time, mean_speed=mean_speed)
        return cls._make(lambda h: lib.swcl_dataset_synthetic(d, h))

    @classmethod
    def load(cls, path) -> "Dataset":
        return cls._make(lambda h: lib.swcl_dataset_load(os.fsencode(path), h))

    def save(self, path) -> None:
        check(lib.swcl_dataset_save(self._h, os.fsencode(path)))

    def info(self) -> dict:
        out = ffi.new("swcl_dataset_info*")
        out.struct_size = ffi.sizeof("swcl_dataset_info")
        check(lib.swcl_dataset_get_info(self._h, out))
        return {"samples": int(out.samples), "groups": int(out.groups), "frame_time": float(out.frame_time)}

    def __len__(self) -> int:
        return self.info()["samples"]

    def samples(self) -> Tuple[np.ndarray, np.ndarray]:
        """(velocities, accelerations), each (k, 3) float32, sorted by speed."""
        n = len(self)
        v = np.empty((n, 3), dtype=np.float32)
        a = np.empty((n, 3), dtype=np.float32)
        check(lib.swcl_dataset_read(self._h, ffi.from_buffer("float[]", v), ffi.from_buffer("float[]", a), n))
        return v, a


def _weights_default(which: str):
    """The table's defaults of the weight set ``which`` ("weights",
    "danger_weights")."""
    def factory():
        return EnergyWeights(**scalar_defaults("energy", prefix=which + "."))
    return field(default_factory=factory)


def _weights_to_c(self, dst) -> None:
    copy_scalars_to_c(self, dst, "energy", prefix="weights.")


# swcl_energy_weights: its fields (rep, oa, cos, dir, acc, env, noise, user),
# their defaults (Table 1 aggregation) and docs from the table's "weights." rows.
EnergyWeights = make_dataclass("EnergyWeights", scalar_fields("energy", prefix="weights."),
                               namespace={"_to_c": _weights_to_c, "__module__": __name__})
EnergyWeights.__doc__ = ("Weights of the energy terms (Table 1 columns; scenario key 'n' for noise).\n"
                         "Defaults (Table 1 aggregation) are the library's:\n"
                         + parameter_doc("energy", prefix="weights."))


@dataclass
class Stimulus:
    """A stimulus moving as position + velocity * t: 'attract' (a female, a
    light) or 'startle' (a danger within d_danger)."""
    kind: str
    position: Vec3
    velocity: Vec3 = (0.0, 0.0, 0.0)
    d_danger: float = 0.3

    def _to_c(self, dst) -> None:
        kind = self.kind
        if isinstance(kind, str):
            try:
                kind = StimulusKind[kind.upper()]
            except KeyError:
                raise ValueError(f"Stimulus.kind: 'attract' or 'startle', got {self.kind!r}") from None
        dst.kind = int(kind)
        dst.position = _vec3(self.position, "Stimulus.position")
        dst.velocity = _vec3(self.velocity, "Stimulus.velocity")
        dst.d_danger = float(self.d_danger)


def _stimuli_c(stimuli):
    stimuli = list(stimuli or [])
    if not stimuli:
        return ffi.NULL, 0
    arr = ffi.new("swcl_stimulus[]", len(stimuli))
    for i, s in enumerate(stimuli):
        if not isinstance(s, Stimulus):
            raise TypeError(f"stimuli[{i}] must be a Stimulus, got {type(s).__name__}")
        s._to_c(arr[i])
    return arr, len(stimuli)


def _energy_to_c(self):
    """A new ``swcl_energy_model_desc*`` and the objects it points into."""
    keep: list = []
    p = ffi.new("swcl_energy_model_desc*", lib.swcl_energy_model_desc_default())
    self.weights._to_c(p.weights)
    self.danger_weights._to_c(p.danger_weights)
    copy_scalars_to_c(self, p, "energy", _ENERGY_HAND)
    if self.centre is None:
        p.has_fixed_centre = 0
    else:
        p.has_fixed_centre = 1
        p.fixed_centre = _vec3(self.centre, "EnergyModel.centre")
    noise = self.noise if self.noise is not None else NoiseDesc()
    noise._to_c(p.noise, keep)
    arr, n = _stimuli_c(self.stimuli)
    keep.append(arr)
    p.stimuli, p.stimulus_count = arr, n
    if self.keypoints is not None:
        kp = _xyz_in(self.keypoints, "EnergyModel.keypoints")
        keep.append(kp)
        p.keypoints = ffi.from_buffer("float[]", kp) if kp.size else ffi.NULL
        p.keypoint_count = len(kp)
    return p, keep


# The energy model's fields in swcl_energy_model_desc's order: the weights,
# the centre (None or (x, y, z) for has_fixed_centre + fixed_centre), the
# noise, the stimuli and the keypoints by hand; every other parameter from
# the library's table (swcl_model_parameters("energy")).
_ENERGY_HAND = {
    "weights": ("weights", EnergyWeights, _weights_default("weights")),
    "danger_weights": ("danger_weights", EnergyWeights, _weights_default("danger_weights")),
    "has_fixed_centre": ("centre", Optional[Vec3], field(default=None)),
    "noise": ("noise", NoiseDesc, field(default_factory=lambda: NoiseDesc._from_c(_ENERGY_DEFAULT.noise))),
    "stimuli": ("stimuli", List[Stimulus], field(default_factory=list)),
    "keypoints": ("keypoints", Optional[np.ndarray], field(default=None)),
}
EnergyModel = make_dataclass("EnergyModel", c_ordered_fields("swcl_energy_model_desc", "energy", _ENERGY_HAND),
                             namespace={"to_c": _energy_to_c, "__module__": __name__})
EnergyModel.__doc__ = (
    "swcl_energy_model_desc: the FASTSWARM energy model (defaults: Table 1\n"
    "aggregation, rho = 2.5).  ``weights``, ``danger_weights``: EnergyWeights;\n"
    "``centre``: None (the swarm's mean position) or a fixed (x, y, z);\n"
    "``noise``: a NoiseDesc (default curl, scale 0.2 m, time_scale 1 s);\n"
    "``stimuli``: Stimulus objects; ``keypoints``: None or an (n >= 2, 3) array.\n"
    "Defaults are the library's (swcl_model_parameters('energy')):\n" + parameter_doc("energy", _ENERGY_HAND))


# ---- swarm methods (bound onto Swarm in _core.py) ---------------------------------------

def set_energy_model(swarm, dataset: Dataset, model: Optional[EnergyModel] = None) -> None:
    if not isinstance(dataset, Dataset):
        raise TypeError(f"set_energy_model: expected a Dataset, got {type(dataset).__name__}")
    model = model if model is not None else EnergyModel()
    if not isinstance(model, EnergyModel):
        raise TypeError(f"set_energy_model: expected an EnergyModel, got {type(model).__name__}")
    desc, _keep = model.to_c()
    check(lib.swcl_swarm_energy_set_model(swarm._h, dataset._h, desc))


def set_stimuli(swarm, stimuli: Sequence[Stimulus]) -> None:
    arr, n = _stimuli_c(stimuli)
    check(lib.swcl_swarm_energy_set_stimuli(swarm._h, arr, n))


def set_keypoints(swarm, keypoints, closed: bool = True) -> None:
    kp = _xyz_in(keypoints, "set_keypoints")
    check(lib.swcl_swarm_energy_set_keypoints(swarm._h, ffi.from_buffer("float[]", kp) if kp.size else ffi.NULL,
                                              len(kp), 1 if closed else 0))


def goals(swarm) -> np.ndarray:
    n = swarm.agent_count * swarm.worlds  # world by world
    out = np.empty(n, dtype=np.int32)
    check(lib.swcl_swarm_energy_get_goals(swarm._h, ffi.from_buffer("int32_t[]", out) if n else ffi.NULL, n))
    return out


def start_from_tracks(swarm, tracks, **options) -> None:
    c, t, p = _track_arrays(tracks, "start_from_tracks")
    d, _keep = _track_desc("start_from_tracks", options)
    check(lib.swcl_swarm_start_from_tracks(swarm._h, *_track_pointers(c, t, p), d))


def write_mixed_csv(path, real_tracks, simulated, frame_time: float, start_time: float = 0.0,
                    simulated_velocities=None) -> int:
    """Trajectory synthesis (§5.2.3): real tracks and simulated agents in one
    CSV, in the recorder's layout (``id,frame,P.x,P.y,P.z,v.x,v.y,v.z``) plus
    a ``source`` column (1 real, 0 simulated).

    ``real_tracks``: ``[(times, positions), ...]`` (s, m); a sample at time t
    is frame round((t - start_time) / frame_time).  Real track k gets id k,
    velocities by forward difference (the last sample repeats the previous).
    ``simulated``: (frames, N, 3) positions from frame 0 on, ids after the real
    ones.  Returns the number of rows written."""
    if not frame_time > 0:
        raise ValueError("write_mixed_csv: frame_time must be > 0")
    sim = np.asarray(simulated, dtype=np.float64)
    if sim.ndim != 3 or sim.shape[2] != 3:
        raise ValueError(f"write_mixed_csv: simulated must be (frames, N, 3), got {sim.shape}")
    if simulated_velocities is None:
        sv = np.zeros_like(sim)
        if len(sim) > 1:
            sv[:-1] = np.diff(sim, axis=0) / frame_time
            sv[-1] = sv[-2]
    else:
        sv = np.asarray(simulated_velocities, dtype=np.float64)
        if sv.shape != sim.shape:
            raise ValueError("write_mixed_csv: simulated_velocities must match simulated")
    rows = []
    for k, (t, p) in enumerate(real_tracks):
        t = np.asarray(t, dtype=np.float64).ravel()
        p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
        v = np.zeros_like(p)
        if len(p) > 1:
            v[:-1] = np.diff(p, axis=0) / np.diff(t)[:, None]
            v[-1] = v[-2]
        for i in range(len(t)):
            rows.append((k, int(round((t[i] - start_time) / frame_time)), *p[i], *v[i], 1))
    base = len(real_tracks)
    for f in range(len(sim)):
        for a in range(sim.shape[1]):
            rows.append((base + a, f, *sim[f, a], *sv[f, a], 0))
    rows.sort(key=lambda r: (r[1], r[0]))
    tmp = os.fspath(path) + ".tmp"
    with open(tmp, "w") as out:
        out.write("id,frame,P.x,P.y,P.z,v.x,v.y,v.z,source\n")
        for r in rows:
            out.write("%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n" % r)
    os.replace(tmp, path)  # complete or absent, like the recorder's files
    return len(rows)

"""The leader-following environment of the C API (``swcl_rl_env_*``), as
whole NumPy arrays: W worlds x N followers, slot = world * N + agent.

Paper: drl-swarm-animation-rule-based-action-generator, §III (docs/rl-swarm.md).
Every call moves whole arrays through the C API; nothing loops over agents."""

from __future__ import annotations

import operator
import weakref
from typing import Optional

import numpy as np

from .._core import Context
from .._native import ffi, lib
from ..errors import check

__all__ = ["RlEnv", "SCENARIOS", "ACTION_DIM", "checked_actions", "flat_layout_only"]

SCENARIOS = ("roaming", "quadrilateral", "stairway", "maze")
ACTION_DIM = 4  # {v, omega.xyz} (Eq. 2)

# Descriptor fields a caller may set by keyword (the C names of swcl_rl_env_desc).
_FLOAT_FIELDS = ("dt", "du_max", "dq_max_deg", "r_sep", "r_ali", "r_coh", "u_max", "body_radius",
                 "neighbor_radius", "rag_w_sep", "rag_w_ali", "rag_w_coh", "w_spd", "w_dir", "w_leader",
                 "w_obs", "w_dist", "l_spd", "l_dir", "l_leader", "l_obs", "dist_target", "rag_leader_kp",
                 "rag_leader_kd")


def checked_actions(actions, shapes, what: str, meaning: str = "") -> np.ndarray:
    """actions as a contiguous float32 array, or a clear error: a real
    numeric dtype (float or integer; not bool, complex, strings or objects)
    and one of ``shapes`` (the first is the one named).  Finiteness is the
    caller's check (it knows the slots)."""
    expected = f"{shapes[0]}" + (f" {meaning}" if meaning else "")
    try:
        a = np.asarray(actions)
    except (ValueError, TypeError) as e:  # ragged nested lists
        raise ValueError(f"{what}: actions must be an array of shape {expected}, got {e}") from None
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{what}: actions must be real numbers (float32 expected), got dtype {a.dtype}")
    if a.shape not in tuple(shapes):
        raise ValueError(f"{what}: actions must have shape {expected}, got {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float32)


def flat_layout_only(env_kwargs: dict, who: str) -> None:
    """The wrappers' spaces are fixed (Gymnasium's (num_envs, D), a world's
    (N, D), PettingZoo's per agent): RlEnv's per_world layout is refused
    there with a ValueError saying where it is."""
    if env_kwargs.get("per_world"):
        raise ValueError(f"{who}: per_world=True is RlEnv's option (observations (W, N, D), rewards (W, N)); "
                         f"this wrapper's spaces have their own layout: use swarmcl.rl.RlEnv(..., per_world=True)")


def default_params() -> dict:
    """The C library's defaults (Table 1 and docs/rl-swarm.md's choices)."""
    d = lib.swcl_rl_env_desc_default()
    out = {name: float(getattr(d, name)) for name in _FLOAT_FIELDS}
    out.update(max_steps=int(d.max_steps), efs=bool(d.efs), rag_leader_pd=bool(d.rag_leader_pd))
    return out


def _destroy(handle_id: int) -> None:
    try:
        lib.swcl_rl_env_destroy(ffi.new("swcl_rl_env*", [handle_id])[0])
    except Exception:  # pragma: no cover - interpreter shutdown
        pass


class RlEnv:
    """``swcl_rl_env``: W independent worlds of N followers and a leader.

    ``scenario``: one of SCENARIOS; ``waypoints`` (K, 4) replaces its path,
    ``obstacles`` (B, 6) boxes are added; any name of _FLOAT_FIELDS plus
    ``max_steps``, ``efs`` and ``rag_leader_pd`` (the RAG's leader coupling:
    True, the PD pull, default; False, the leader as one more Eq. 8 term)
    overrides the default descriptor.

    ``per_world``: observations come back as (W, N, D), rewards as (W, N),
    the RAG's actions as (W, N, 4) and the followers' state as (W, N, 4),
    instead of the flat slot layout (W*N, ...); the same values in the same
    order (slot = world * N + agent), a view of one array.  Actions are
    taken in either layout, (W*N, 4) or (W, N, 4), whatever the flag."""

    def __init__(self, context: Context, worlds: int, agents: int, scenario: str = "roaming",
                 waypoints=None, obstacles=None, *, per_world: bool = False, **params):
        if not isinstance(context, Context):
            raise TypeError(f"RlEnv: context must be a swarmcl.Context, got {type(context).__name__}")
        if not isinstance(per_world, (bool, np.bool_)):
            raise TypeError(f"RlEnv: per_world must be True or False, got {per_world!r}")
        desc = ffi.new("swcl_rl_env_desc*", lib.swcl_rl_env_desc_default())
        for name, value in (("worlds", worlds), ("agents", agents)):
            value = operator.index(value)
            if not 0 <= value < 2**32:
                raise ValueError(f"RlEnv: {name} must be in [0, 2^32), got {value}")
            setattr(desc, name, value)
        keep = [ffi.new("char[]", str(scenario).encode())]
        desc.scenario = keep[0]
        if waypoints is not None:
            wp = np.ascontiguousarray(waypoints, dtype=np.float32).reshape(-1, 4)
            keep.append(wp)
            desc.waypoints = ffi.from_buffer("float[]", wp) if wp.size else ffi.NULL
            desc.waypoint_count = wp.shape[0]
        if obstacles is not None:
            ob = np.ascontiguousarray(obstacles, dtype=np.float32).reshape(-1, 6)
            keep.append(ob)
            desc.obstacles = ffi.from_buffer("float[]", ob) if ob.size else ffi.NULL
            desc.obstacle_count = ob.shape[0]
        for name, value in params.items():
            if name == "max_steps":
                desc.max_steps = operator.index(value)
            elif name in ("efs", "rag_leader_pd"):
                setattr(desc, name, 1 if value else 0)
            elif name in _FLOAT_FIELDS:
                setattr(desc, name, float(value))
            else:
                raise TypeError(f"RlEnv: unknown parameter {name!r}")
        out = ffi.new("swcl_rl_env*")
        check(lib.swcl_rl_env_create(context._h, desc, out))
        self._hp = out
        self._h = out[0]
        self._finalizer = weakref.finalize(self, _destroy, int(out[0].id))
        self.context = context
        self.scenario = str(scenario)
        self.params = dict(default_params(), **{k: (bool(v) if k in ("efs", "rag_leader_pd") else v)
                                                for k, v in params.items()})
        w, n, d = ffi.new("uint32_t*"), ffi.new("uint32_t*"), ffi.new("uint32_t*")
        check(lib.swcl_rl_env_get_info(self._h, w, n, d))
        self.worlds, self.agents, self.obs_dim = int(w[0]), int(n[0]), int(d[0])
        self.per_world = bool(per_world)

    # ---- lifetime ------------------------------------------------------------

    @property
    def closed(self) -> bool:
        return not self._finalizer.alive

    def close(self) -> None:
        self._finalizer()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ---- shapes --------------------------------------------------------------

    @property
    def slots(self) -> int:
        """W * N, the number of followers over all worlds."""
        return self.worlds * self.agents

    def action_scale(self) -> np.ndarray:
        """The largest useful |action| per component: Δu for v, and for ω the
        chord of the Δq turn (|q'' - q| = 2 sin(Δq / 2)); larger values are
        clamped by the kinematics (Eq. 2)."""
        dq = np.deg2rad(self.params["dq_max_deg"])
        w = 2.0 * np.sin(dq / 2.0)
        return np.array([self.params["du_max"], w, w, w], dtype=np.float32)

    def _shaped(self, a: np.ndarray) -> np.ndarray:
        """A flat per-slot array (W*N, ...) as the caller asked for it:
        (W, N, ...) with per_world, else as it is."""
        return a.reshape((self.worlds, self.agents) + a.shape[1:]) if self.per_world else a

    def _actions_in(self, actions, what: str) -> np.ndarray:
        a = checked_actions(actions, ((self.slots, ACTION_DIM), (self.slots * ACTION_DIM,),
                                      (self.worlds, self.agents, ACTION_DIM)), what,
                            "(worlds * agents, 4) or (worlds, agents, 4)")
        if not np.isfinite(a).all():
            bad = int(np.flatnonzero((~np.isfinite(a.reshape(self.slots, ACTION_DIM))).any(axis=1))[0])
            raise ValueError(f"{what}: actions must be finite (NaN or Inf at slot {bad}, "
                             f"world {bad // self.agents}, agent {bad % self.agents})")
        return a

    # ---- calls ---------------------------------------------------------------

    def reset(self, seed: int) -> np.ndarray:
        """Every world to its start (same seed: the same bits); returns (W*N, D)
        float32 ((W, N, D) with per_world)."""
        seed = operator.index(seed)
        if not 0 <= seed < 2**64:
            raise ValueError(f"RlEnv.reset: seed must be in [0, 2^64), got {seed}")
        obs = np.empty((self.slots, self.obs_dim), dtype=np.float32)
        check(lib.swcl_rl_env_reset(self._h, seed, ffi.from_buffer("float[]", obs), obs.size))
        return self._shaped(obs)

    def reset_seeds(self, seeds) -> np.ndarray:
        """Every world to its start with its own seed (W integers in [0, 2^64)):
        world w starts as ``reset(seeds[w])`` starts it; returns (W*N, D)
        ((W, N, D) with per_world)."""
        seeds = [operator.index(s) for s in seeds]
        if len(seeds) != self.worlds:
            raise ValueError(f"RlEnv.reset_seeds: one seed per world: {self.worlds} expected, got {len(seeds)}")
        bad = [s for s in seeds if not 0 <= s < 2**64]
        if bad:
            raise ValueError(f"RlEnv.reset_seeds: seeds must be in [0, 2^64), got {bad[0]}")
        arr = np.array(seeds, dtype=np.uint64)
        obs = np.empty((self.slots, self.obs_dim), dtype=np.float32)
        check(lib.swcl_rl_env_reset_seeds(self._h, ffi.from_buffer("uint64_t[]", arr), arr.size,
                                          ffi.from_buffer("float[]", obs), obs.size))
        return self._shaped(obs)

    def reset_worlds(self, mask) -> np.ndarray:
        """The worlds with mask[w] set, each to its next episode; returns the
        observations of all worlds, (W*N, D) ((W, N, D) with per_world)."""
        m = np.ascontiguousarray(np.asarray(mask).astype(bool), dtype=np.uint8)
        if m.shape != (self.worlds,):
            raise ValueError(f"RlEnv.reset_worlds: mask must have shape ({self.worlds},), got {m.shape}")
        obs = np.empty((self.slots, self.obs_dim), dtype=np.float32)
        check(lib.swcl_rl_env_reset_worlds(self._h, ffi.from_buffer("uint8_t[]", m), m.size,
                                           ffi.from_buffer("float[]", obs), obs.size))
        return self._shaped(obs)

    def step(self, actions):
        """One step of every world.  Returns (obs (W*N, D) float32, rewards
        (W*N,) float32, terminated (W,) bool, truncated (W,) bool); with
        per_world obs (W, N, D) and rewards (W, N)."""
        a = self._actions_in(actions, "RlEnv.step")
        obs = np.empty((self.slots, self.obs_dim), dtype=np.float32)
        rew = np.empty(self.slots, dtype=np.float32)
        term = np.empty(self.worlds, dtype=np.uint8)
        trunc = np.empty(self.worlds, dtype=np.uint8)
        check(lib.swcl_rl_env_step(self._h, ffi.from_buffer("float[]", a), a.size,
                                   ffi.from_buffer("float[]", obs), obs.size,
                                   ffi.from_buffer("float[]", rew), rew.size,
                                   ffi.from_buffer("uint8_t[]", term), ffi.from_buffer("uint8_t[]", trunc),
                                   self.worlds))
        return self._shaped(obs), self._shaped(rew), term.astype(bool), trunc.astype(bool)

    def rag_actions(self) -> np.ndarray:
        """The rule-based action generator's actions (Eq. 8-10), (W*N, 4)
        ((W, N, 4) with per_world)."""
        out = np.empty((self.slots, ACTION_DIM), dtype=np.float32)
        check(lib.swcl_rl_env_rag_actions(self._h, ffi.from_buffer("float[]", out), out.size))
        return self._shaped(out)

    def set_leader_controls(self, controls) -> None:
        """Joystick leaders: (W, 4) {Δu, Δq.xyz}, applied every step until changed."""
        c = np.ascontiguousarray(controls, dtype=np.float32)
        if c.shape not in ((self.worlds, 4), (self.worlds * 4,)):
            raise ValueError(f"RlEnv.set_leader_controls: controls must have shape ({self.worlds}, 4), got {c.shape}")
        check(lib.swcl_rl_env_set_leader_controls(self._h, ffi.from_buffer("float[]", c), c.size))

    def layout(self) -> dict:
        """The layout every world shares: ``waypoints`` (K, 4) x, y, z, target
        speed (K = 0 for a joystick leader) and ``obstacles`` (B, 6) box
        centre xyz, half extents xyz."""
        nw, nb = ffi.new("uint32_t*"), ffi.new("uint32_t*")
        check(lib.swcl_rl_env_get_layout(self._h, ffi.NULL, 0, nw, ffi.NULL, 0, nb))
        wp = np.zeros((nw[0], 4), np.float32)
        ob = np.zeros((nb[0], 6), np.float32)
        check(lib.swcl_rl_env_get_layout(self._h, ffi.from_buffer("float[]", wp), len(wp), ffi.NULL,
                                         ffi.from_buffer("float[]", ob), len(ob), ffi.NULL))
        return {"waypoints": wp, "obstacles": ob}

    def read_state(self) -> dict:
        """Positions / velocities (q.xyz, u) of followers (W*N, 4), (W, N, 4)
        with per_world, and leaders (W, 4)."""
        pos = np.empty((self.slots, 4), dtype=np.float32)
        vel = np.empty((self.slots, 4), dtype=np.float32)
        lpos = np.empty((self.worlds, 4), dtype=np.float32)
        lvel = np.empty((self.worlds, 4), dtype=np.float32)
        f = lambda a: ffi.from_buffer("float[]", a)  # noqa: E731
        check(lib.swcl_rl_env_read_state(self._h, f(pos), pos.size, f(vel), vel.size, f(lpos), f(lvel), lpos.size))
        return {"positions": self._shaped(pos), "velocities": self._shaped(vel), "leader_positions": lpos,
                "leader_velocities": lvel}

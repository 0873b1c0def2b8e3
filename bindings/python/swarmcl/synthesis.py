"""Time-aligned trajectory synthesis (FASTSWARM §5.2.3, Fig. 8(d)): virtual
agents simulated among real tracks on the real data's clock.

At every frame f the swarm holds the virtual agents (ids 0..V-1, their own
state) followed by the real insects in view at frame f (positions of frame f,
forward-difference velocities); one step of dt = frame_time moves the virtual
agents, which therefore interact only with the real insects of that same
frame.  The real insects' stepped state is discarded: frame f + 1 writes them
again from the data.  (write_mixed_csv in energy.py only merges independently
simulated agents into a file; it does not align them in time.)
"""

import os
from typing import Optional

import numpy as np

__all__ = ["mix_time_aligned", "real_frames"]


def real_frames(real_tracks, frame_time: float, start_time: float, frames: int):
    """Per frame 0..frames-1: (track indices, positions (n, 3), velocities
    (n, 3)) of the real tracks in view.  A sample at time t is frame
    round((t - start_time) / frame_time); velocities by forward difference
    within a track (its last sample repeats the previous one).  ValueError when
    the tracks cover fewer than ``frames`` frames from start_time."""
    if not frame_time > 0:
        raise ValueError(f"mix_time_aligned: frame_time must be > 0, got {frame_time}")
    if int(frames) != frames or frames < 1:
        raise ValueError(f"mix_time_aligned: frames must be an integer >= 1, got {frames}")
    per = [([], [], []) for _ in range(frames)]
    last = -1
    for k, (t, p) in enumerate(real_tracks):
        t = np.asarray(t, dtype=np.float64).ravel()
        p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
        if len(t) != len(p) or len(t) < 2:
            raise ValueError(f"mix_time_aligned: real track {k} needs >= 2 samples with one time each")
        if not (np.isfinite(t).all() and np.isfinite(p).all()) or (np.diff(t) <= 0).any():
            raise ValueError(f"mix_time_aligned: real track {k} has non-finite values or times not increasing")
        v = np.empty_like(p)
        v[:-1] = np.diff(p, axis=0) / np.diff(t)[:, None]
        v[-1] = v[-2]
        f = np.rint((t - start_time) / frame_time).astype(np.int64)
        if len(np.unique(f)) != len(f):
            raise ValueError(f"mix_time_aligned: real track {k} has two samples in one frame")
        last = max(last, int(f.max()))
        for i in np.nonzero((f >= 0) & (f < frames))[0]:
            per[f[i]][0].append(k)
            per[f[i]][1].append(p[i])
            per[f[i]][2].append(v[i])
    if last < frames - 1:
        raise ValueError(f"mix_time_aligned: the real tracks cover {last + 1} frames from start_time, "
                         f"fewer than the {frames} asked for")
    return [(np.array(ids, dtype=np.int64), np.array(ps, dtype=np.float32).reshape(-1, 3),
             np.array(vs, dtype=np.float32).reshape(-1, 3)) for ids, ps, vs in per]


def mix_time_aligned(swarm, real_tracks, virtual_positions, frames: int, frame_time: float,
                     start_time: float = 0.0, virtual_velocities=None, path: Optional[str] = None):
    """Simulates V virtual agents among ``real_tracks`` (``[(times (s),
    positions (m)), ...]``) for ``frames`` frames of ``frame_time`` (the
    swarm's dt must be frame_time; its model is set by the caller).  Frame 0
    is the virtual agents' start (``virtual_positions`` (V, 3), velocities
    default 0).  Returns (rows, in_view): rows is an (R, 9) array
    ``id, frame, P.x, P.y, P.z, v.x, v.y, v.z, source`` sorted by (frame, id)
    (real track k: id k, source 1; virtual agent a: id len(real_tracks) + a,
    source 0); in_view[f] the real track indices stepped with the virtual
    agents at frame f.  With ``path`` the rows are also written there as CSV,
    complete or not at all (a temporary file replaced at the end).

    Bad input, nothing written: ValueError for tracks covering fewer frames
    than asked for or shapes that do not match; InvalidArgumentError for a
    swarm capacity below V + the most real insects in view at one frame."""
    vp = np.ascontiguousarray(virtual_positions, dtype=np.float32)
    if vp.ndim != 2 or vp.shape[1] != 3 or len(vp) == 0:
        raise ValueError(f"mix_time_aligned: virtual_positions must be (V, 3) with V >= 1, got {vp.shape}")
    vv = np.zeros_like(vp) if virtual_velocities is None else np.ascontiguousarray(virtual_velocities,
                                                                                   dtype=np.float32)
    if vv.shape != vp.shape:
        raise ValueError("mix_time_aligned: virtual_velocities must match virtual_positions")
    per = real_frames(real_tracks, frame_time, start_time, frames)
    V, base = len(vp), len(real_tracks)
    most = max(len(ids) for ids, _, _ in per)
    # The fullest frame first: a swarm too small fails (InvalidArgumentError
    # from the library, naming its capacity) before any step or file.
    swarm.write_positions(np.zeros((V + most, 3), dtype=np.float32))
    out, in_view = [], []
    for f, (ids, rp, rv) in enumerate(per):
        for k in range(len(ids)):
            out.append((ids[k], f, *rp[k], *rv[k], 1))
        for a in range(V):
            out.append((base + a, f, *vp[a], *vv[a], 0))
        in_view.append(ids)
        if f == frames - 1:
            break  # the last frame is recorded, not stepped
        swarm.write_positions(np.concatenate([vp, rp]))
        swarm.write_velocities(np.concatenate([vv, rv]))
        swarm.step(1)
        vp = swarm.read_positions()[:V].copy()
        vv = swarm.read_velocities()[:V].copy()
    rows = np.array(out, dtype=np.float64)
    rows = rows[np.lexsort((rows[:, 0], rows[:, 1]))]
    if path is not None:
        tmp = os.fspath(path) + ".tmp"
        try:
            with open(tmp, "w") as fh:
                fh.write("id,frame,P.x,P.y,P.z,v.x,v.y,v.z,source\n")
                for r in rows:
                    fh.write("%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n" % (int(r[0]), int(r[1]), *r[2:8], int(r[8])))
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.remove(tmp)
            raise
    return rows, in_view

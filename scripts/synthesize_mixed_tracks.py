#!/usr/bin/env python3
"""FASTSWARM's trajectory synthesis (seed 000 §5.2.3, Fig. 8(b, d)) on the
mosquito tracks: 100 virtual agents simulated by the energy model among 37
real tracks over 500 frames, time-aligned (swarmcl.mix_time_aligned: each
frame the virtual agents step with the real insects in view at that frame).

    python3 scripts/synthesize_mixed_tracks.py [--data ../shared/data/anopheles-coluzzii-swarm.csv]
        [--out build/trajectory_synthesis.csv] [--png docs/images/trajectory_synthesis.png]
        [--tracks 37] [--frames 500] [--virtual 100] [--seed 4]

The window: the `frames`-frame stretch (10 ms frames) holding the most track
ids; in it the `tracks` ids with the most samples (the paper's 37; CSV ids
0..36, then the virtual agents).  Like the paper's (Fig. 8(b)), these tracks
are intermittent: each is in view only for part of the window.  Virtual agents start at real samples of the
window's first 50 frames, jittered by the 5th-percentile nearest-neighbour
distance, with those samples' velocities.  Energy model as in
scripts/validate_fastswarm.py (dataset k = 300 from the same file, radii from
the real nearest-neighbour distances, centre the tracks' mean).

Skips (exit 0) when the data file is absent.
"""

import argparse
import csv
import os
import sys
from collections import defaultdict
from datetime import datetime

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEFAULT_DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data", "anopheles-coluzzii-swarm.csv"))
COLUMNS = {"id": "id", "time": "datetime", "x": "x_cm", "y": "y_cm", "z": "z_cm"}
DT = 0.01  # the data's frame time (100 Hz) and the simulation step


def read_samples(path):
    """id -> sorted [(frame, xyz in m)], frames counted from the first row."""
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            t = datetime.fromisoformat(r["datetime"]).timestamp()
            rows.append((r["id"], t, float(r["x_cm"]) / 100, float(r["y_cm"]) / 100, float(r["z_cm"]) / 100))
    t0 = min(r[1] for r in rows)
    by_id = defaultdict(dict)
    for i, t, x, y, z in rows:
        by_id[i].setdefault(int(round((t - t0) / DT)), (x, y, z))  # one sample per frame
    return {i: sorted(s.items()) for i, s in by_id.items()}


def choose_window(samples, frames, want):
    last = max(f for s in samples.values() for f, _ in s)
    best = (-1, 0)
    for start in range(0, max(1, last - frames + 2), 10):
        n = sum(1 for s in samples.values() if any(start <= f < start + frames for f, _ in s))
        best = max(best, (n, -start))
    start = -best[1]
    counts = {i: sum(1 for f, _ in s if start <= f < start + frames) for i, s in samples.items()}
    ids = sorted((i for i in counts if counts[i] >= 2), key=lambda i: (-counts[i], i))[:want]
    return start, ids


def window_tracks(samples, ids, start, frames):
    """The chosen ids' samples inside the window, one track each (times from
    the window start (s), positions (m)); a track's velocity across a dropped
    frame is the mean over the gap (mix_time_aligned divides by the time)."""
    out = []
    for i in ids:
        s = [(f - start, p) for f, p in samples[i] if start <= f < start + frames]
        out.append((np.array([f for f, _ in s]) * DT, np.array([p for _, p in s])))
    return out


def nearest(points):
    d = np.linalg.norm(points[:, None] - points[None], axis=2)
    np.fill_diagonal(d, np.inf)
    return d.min(axis=1)


def picture(rows, png, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(8, 4), dpi=72)
    lo, hi = rows[:, 2:5].min(axis=0), rows[:, 2:5].max(axis=0)  # one scale for both panels
    for k, (src, name) in enumerate(((1, "real tracks (Fig. 8(b))"),
                                     (None, "+ virtual agents, orange (Fig. 8(d))"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.set_xlim(lo[0], hi[0]), ax.set_ylim(lo[1], hi[1]), ax.set_zlim(lo[2], hi[2])
        for s, colour in ((0, "tab:orange"), (1, "tab:blue")):
            if src is not None and s != src:
                continue
            sel = rows[rows[:, 8] == s]
            for i in np.unique(sel[:, 0]):
                tr = sel[sel[:, 0] == i]
                ax.plot(tr[:, 2], tr[:, 3], tr[:, 4], lw=0.6, color=colour)
        ax.set_title(name, fontsize=9)
        ax.tick_params(labelsize=6)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=os.environ.get("SWARMCL_MOSQUITO_CSV", DEFAULT_DATA))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "trajectory_synthesis.csv"))
    ap.add_argument("--png", default=None, help="write the picture here (e.g. docs/images/trajectory_synthesis.png)")
    ap.add_argument("--tracks", type=int, default=37)
    ap.add_argument("--frames", type=int, default=500)
    ap.add_argument("--virtual", type=int, default=100)
    ap.add_argument("--seed", type=int, default=4)
    args = ap.parse_args()
    if not os.path.isfile(args.data):
        print(f"synthesize_mixed_tracks: skipped, no data at {args.data}")
        return 0
    import swarmcl

    samples = read_samples(args.data)
    start, ids = choose_window(samples, args.frames, args.tracks)
    if len(ids) < args.tracks:
        print(f"synthesize_mixed_tracks: only {len(ids)} tracks in the best {args.frames}-frame window", file=sys.stderr)
        return 1
    real = window_tracks(samples, ids, start, args.frames)
    print(f"window: frames {start}..{start + args.frames - 1} of the data ({args.frames * DT:.2f} s); "
          f"{len(ids)} tracks (CSV ids 0..{len(ids) - 1}), {sum(len(t) for t, _ in real)} samples")

    try:
        most = max(len(ids) for ids, _, _ in swarmcl.real_frames(real, DT, 0.0, args.frames))
    except ValueError as e:  # tracks covering fewer frames than asked for
        print(f"synthesize_mixed_tracks: {e}", file=sys.stderr)
        return 1

    # Nearest-neighbour distances and centre of the whole file, as validate_fastswarm.py.
    frames = defaultdict(list)
    for s in samples.values():
        for f, p in s:
            frames[f].append(p)
    nn = np.concatenate([nearest(np.array(v)) for v in frames.values() if len(v) >= 2])
    p5, p50 = np.percentile(nn, [5, 50])
    allp = np.array([p for v in frames.values() for p in v])
    centre = tuple(float(c) for c in allp.mean(axis=0))
    lo, hi = allp.min(axis=0) - 1.0, allp.max(axis=0) + 1.0

    # Virtual starts: real samples of the first 50 frames, jittered.
    rng = np.random.default_rng(args.seed)
    early = [(p[i], (p[i + 1] - p[i]) / (t[i + 1] - t[i])) for t, p in real for i in range(len(t) - 1)
             if t[i] < 50 * DT]
    if not early:  # no real insect in the first 50 frames: start at any of the window's samples
        early = [(p[i], (p[i + 1] - p[i]) / (t[i + 1] - t[i])) for t, p in real for i in range(len(t) - 1)]
    pick = rng.integers(0, len(early), args.virtual)
    vpos = np.array([early[k][0] for k in pick]) + rng.normal(0, p5, (args.virtual, 3))
    vvel = np.array([early[k][1] for k in pick])

    dataset = swarmcl.Dataset.from_csv(args.data, columns=COLUMNS, unit_scale=0.01, k=300, seed=args.seed)
    with swarmcl.Context() as ctx, swarmcl.Swarm(ctx, capacity=args.virtual + most, seed=args.seed,
                                                 domain=(tuple(lo), tuple(hi)), interaction_radius=float(2 * p50),
                                                 dt=DT) as s:
        s.set_energy_model(dataset, swarmcl.EnergyModel(
            d_rep=float(p5), d_att1=float(p50), d_att2=float(2 * p50), centre=centre,
            noise=swarmcl.NoiseDesc(scale=float(p50), time_scale=1.0, seed=args.seed)))
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        try:
            rows, in_view = swarmcl.mix_time_aligned(s, real, vpos, args.frames, DT, virtual_velocities=vvel,
                                                     path=args.out)
        except ValueError as e:  # e.g. tracks shorter than --frames: nothing written
            print(f"synthesize_mixed_tracks: {e}", file=sys.stderr)
            return 1
    n_real = int((rows[:, 8] == 1).sum())
    print(f"wrote {args.out}: {len(rows)} rows ({n_real} real, {len(rows) - n_real} virtual), "
          f"real insects in view per frame: mean {np.mean([len(v) for v in in_view]):.1f}, most {most}")
    virt = rows[rows[:, 8] == 0]
    speed = np.linalg.norm(virt[:, 5:8], axis=1)
    rspeed = np.linalg.norm(rows[rows[:, 8] == 1][:, 5:8], axis=1)
    print(f"speed median: real {np.median(rspeed):.3f} m/s, virtual {np.median(speed):.3f} m/s")
    if args.png:
        picture(rows, args.png, f"{len(ids)} real tracks x {args.frames} frames + {args.virtual} virtual agents "
                                f"(energy model, time-aligned)")
        print(f"wrote {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

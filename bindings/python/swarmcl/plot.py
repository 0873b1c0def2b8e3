"""Pictures of a run: PNG snapshots from chosen viewpoints and an animated GIF
or MP4, drawn with matplotlib from the files ``swarmcl run`` writes (the
``.npy`` trajectories and ``run.json``), with the domain, obstacles and goal
of the scenario drawn in.

    python -m swarmcl.plot out/aggregation                  # out/aggregation/<name>.png
    python -m swarmcl.plot out/aggregation --gif run.gif    # and an animation

matplotlib is an optional dependency: ``pip install swarmcl[plot]``.
"""
from __future__ import annotations

import argparse
import json
import os
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

# Viewpoints as (elevation, azimuth) in degrees.
DEFAULT_VIEWS: tuple = ((20.0, -60.0), (90.0, -90.0))


@dataclass
class Run:
    """What ``swarmcl run`` wrote into one output folder."""

    name: str
    positions: np.ndarray          # (frames, N, 3) float32
    velocities: np.ndarray         # (frames, N, 3) float32
    times: np.ndarray              # (frames,) seconds
    info: dict                     # run.json
    scenario: dict = field(default_factory=dict)  # the scenario as given


def load_run(out_dir: str) -> Run:
    """Loads a run folder; needs the ``npy`` format among the outputs."""
    with open(os.path.join(out_dir, "run.json"), encoding="utf-8") as f:
        info = json.load(f)
    name = info["scenario"]
    pos_path = os.path.join(out_dir, f"{name}_positions.npy")
    if not os.path.exists(pos_path):
        raise FileNotFoundError(f"{pos_path} not found: run with --format including npy")
    positions = np.load(pos_path)
    velocities = np.load(os.path.join(out_dir, f"{name}_velocities.npy"))
    every = int(info.get("every", 1))
    dt = float(info.get("dt", 1.0))
    times = np.arange(positions.shape[0]) * every * dt
    times[-1] = min(times[-1], info.get("steps", times[-1] / dt) * dt)
    return Run(name, positions, velocities, times, info, info.get("parameters") or {})


def _require_matplotlib():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: F401
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("swarmcl.plot needs matplotlib: pip install matplotlib") from e
    return plt


def _sphere_wire(ax, center, radius, color, alpha=0.35):
    u, v = np.mgrid[0 : 2 * np.pi : 24j, 0 : np.pi : 12j]
    ax.plot_wireframe(
        center[0] + radius * np.cos(u) * np.sin(v),
        center[1] + radius * np.sin(u) * np.sin(v),
        center[2] + radius * np.cos(v),
        color=color, alpha=alpha, linewidth=0.5,
    )


def _box_edges(ax, lo, hi, color, alpha=0.5, lw=0.8):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    for a in range(3):
        b, c = [i for i in range(3) if i != a]
        for cb in (lo[b], hi[b]):
            for cc in (lo[c], hi[c]):
                p, q = np.zeros(3), np.zeros(3)
                p[a], q[a] = lo[a], hi[a]
                p[b] = q[b] = cb
                p[c] = q[c] = cc
                ax.plot(*zip(p, q), color=color, alpha=alpha, linewidth=lw)


def _draw_scene(ax, scenario: dict):
    domain = scenario.get("domain")
    if domain:
        _box_edges(ax, domain["min"], domain["max"], "0.5")
    for ob in scenario.get("obstacles", []):
        if ob.get("type") == "sphere":
            _sphere_wire(ax, ob["center"], ob["radius"], "tab:red", 0.6)
        elif ob.get("type") == "box":
            c, h = np.asarray(ob["center"], float), np.asarray(ob["half_extents"], float)
            _box_edges(ax, c - h, c + h, "tab:red", 0.9, 1.2)
    goal = (scenario.get("model") or {}).get("goal")
    if goal:
        _sphere_wire(ax, goal["center"], max(goal.get("radius", 0.0), 0.05), "tab:green", 0.25)
    # The path model: its goals (one group, or per group), and cylinder obstacles.
    model = scenario.get("model") or {}
    goals = list(model.get("goals", []))
    for group in model.get("groups", []):
        goals += group.get("goals", [])
    for g in goals:
        if g.get("type") == "box":
            c, h = np.asarray(g["center"], float), np.asarray(g["half_extents"], float)
            _box_edges(ax, c - h, c + h, "tab:green", 0.6)
        else:
            _sphere_wire(ax, g["center"], max(g.get("radius", 0.0), 0.05), "tab:green", 0.25)
    for ob in scenario.get("obstacles", []):
        if ob.get("type") == "cylinder":
            b = np.asarray(ob["base"], float)
            r, height = float(ob["radius"]), float(ob["height"])
            t = np.linspace(0, 2 * np.pi, 25)
            for z in (b[2], b[2] + height):
                ax.plot(b[0] + r * np.cos(t), b[1] + r * np.sin(t), np.full_like(t, z), color="tab:red", lw=1.0)
            ax.plot([b[0], b[0]], [b[1] + r, b[1] + r], [b[2], b[2] + height], color="tab:red", lw=1.0)


def _limits(ax, run: Run):
    domain = run.scenario.get("domain")
    if domain:
        lo, hi = np.asarray(domain["min"], float), np.asarray(domain["max"], float)
    else:
        pts = run.positions.reshape(-1, 3)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-6)))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")


def _scatter(ax, run: Run, frame: int):
    p = run.positions[frame]
    speed = np.linalg.norm(run.velocities[frame], axis=1)
    size = max(0.5, min(8.0, 4000.0 / max(len(p), 1)))
    return ax.scatter(p[:, 0], p[:, 1], p[:, 2], c=speed, cmap="viridis", s=size, depthshade=False)


def render_snapshots(out_dir: str, png_path: str | None = None, frames: Sequence[int] | None = None,
                     views: Sequence[tuple] = DEFAULT_VIEWS, dpi: int = 110) -> str:
    """One PNG: a row per viewpoint, a column per frame (default: first,
    middle and last).  Returns the PNG's path."""
    plt = _require_matplotlib()
    run = load_run(out_dir)
    n = run.positions.shape[0]
    frames = list(frames) if frames is not None else sorted({0, n // 2, n - 1})
    for f in frames:
        if not 0 <= f < n:
            raise ValueError(f"frame {f} out of range (0..{n - 1})")
    fig = plt.figure(figsize=(4.2 * len(frames), 4.0 * len(views)))
    for r, (elev, azim) in enumerate(views):
        for c, f in enumerate(frames):
            ax = fig.add_subplot(len(views), len(frames), r * len(frames) + c + 1, projection="3d")
            _draw_scene(ax, run.scenario)
            sc = _scatter(ax, run, f)
            _limits(ax, run)
            ax.view_init(elev=elev, azim=azim)
            ax.set_title(f"{run.name}: t = {run.times[f]:.2f} s", fontsize=9)
    fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="speed (m/s)")
    png_path = png_path or os.path.join(out_dir, f"{run.name}.png")
    tmp = png_path + ".partial.png"
    fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, png_path)  # atomic, like the library's outputs
    return png_path


def render_animation(out_dir: str, path: str, view: tuple = DEFAULT_VIEWS[0], fps: int = 15,
                     dpi: int = 80) -> str:
    """An animated GIF (Pillow) or MP4 (needs ffmpeg) of every frame."""
    plt = _require_matplotlib()
    from matplotlib import animation

    run = load_run(out_dir)
    fig = plt.figure(figsize=(5, 5))
    ax = fig.add_subplot(projection="3d")
    _draw_scene(ax, run.scenario)
    sc = _scatter(ax, run, 0)
    _limits(ax, run)
    ax.view_init(elev=view[0], azim=view[1])
    title = ax.set_title("")

    def update(f):
        p = run.positions[f]
        sc._offsets3d = (p[:, 0], p[:, 1], p[:, 2])
        sc.set_array(np.linalg.norm(run.velocities[f], axis=1))
        title.set_text(f"{run.name}: t = {run.times[f]:.2f} s")
        return sc, title

    anim = animation.FuncAnimation(fig, update, frames=run.positions.shape[0], interval=1000 / fps)
    writer = animation.PillowWriter(fps=fps) if path.lower().endswith(".gif") else animation.FFMpegWriter(fps=fps)
    tmp = path + ".partial" + os.path.splitext(path)[1]
    anim.save(tmp, writer=writer, dpi=dpi)
    plt.close(fig)
    os.replace(tmp, path)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m swarmcl.plot", description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir", help="a folder written by `swarmcl run` (with the npy format)")
    ap.add_argument("--png", help="snapshot file (default: OUT_DIR/<name>.png)")
    ap.add_argument("--frames", help="comma-separated frame numbers (default: first, middle, last)")
    ap.add_argument("--gif", help="also write an animation (.gif, or .mp4 with ffmpeg)")
    args = ap.parse_args(argv)
    frames = [int(f) for f in args.frames.split(",")] if args.frames else None
    print(render_snapshots(args.out_dir, args.png, frames))
    if args.gif:
        print(render_animation(args.out_dir, args.gif))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

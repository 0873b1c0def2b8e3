"""Scenario layouts as meshes: the RL scenarios' box obstacles
(``RlEnv.layout()``, ``swcl_rl_env_get_layout``) as a Wavefront OBJ, for
drawing the scenarios or handing them to the models that take meshes (the
path model's ``ObjObstacle``).  The environment itself uses the exact boxes."""

from __future__ import annotations

import os
from typing import Optional

import numpy as np

__all__ = ["box_mesh", "boxes_to_obj"]

# The 12 triangles of a box over its corners (bit k of the corner index is
# the sign of axis k), wound counter-clockwise seen from outside.
_FACES = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6],   # x = -h, x = +h
                   [0, 1, 5], [0, 5, 4], [2, 6, 7], [2, 7, 3],   # y = -h, y = +h
                   [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]])  # z = -h, z = +h


def box_mesh(boxes) -> tuple:
    """(vertices (8B, 3), triangles (12B, 3)) of boxes (B, 6): centre xyz,
    half extents xyz (> 0)."""
    b = np.asarray(boxes, np.float64).reshape(-1, 6)
    if not np.isfinite(b).all() or (b[:, 3:] <= 0).any():
        raise ValueError("boxes: centres must be finite and half extents > 0")
    corner = np.array([[(k >> a) & 1 for a in range(3)] for k in range(8)], np.float64) * 2 - 1
    verts = (b[:, None, :3] + corner[None, :, :] * b[:, None, 3:]).reshape(-1, 3)
    tris = (_FACES[None, :, :] + 8 * np.arange(len(b))[:, None, None]).reshape(-1, 3)
    return verts, tris


def boxes_to_obj(boxes, path: Optional[os.PathLike] = None, comment: str = "") -> str:
    """The boxes as OBJ text (one object per box), written to ``path`` when given."""
    verts, tris = box_mesh(boxes)
    lines = [f"# {c}" for c in comment.splitlines()]
    for i in range(len(tris) // 12):
        lines.append(f"o box{i}")
        lines += [f"v {x:.6g} {y:.6g} {z:.6g}" for x, y, z in verts[8 * i:8 * i + 8]]
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in tris[12 * i:12 * i + 12]]
    text = "\n".join(lines) + "\n"
    if path is not None:
        with open(path, "w", encoding="ascii") as f:
            f.write(text)
    return text

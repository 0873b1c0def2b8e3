#!/usr/bin/env python3
"""Writes examples/meshes/hamlet.obj: a few houses (box bodies with
gabled roofs) for the migratory-locusts scenario of the curl-noise paper (§7,
Fig. 1 left).  The project generates its own obstacle meshes; run this again
to regenerate the file (it is deterministic)."""
import os
import sys

# (x, y, width along x, depth along y, wall height, roof height), metres; z is up.
HOUSES = [
    (35.0, 12.0, 10.0, 8.0, 6.0, 4.0),
    (38.0, 34.0, 12.0, 9.0, 7.0, 4.0),
    (60.0, 22.0, 9.0, 12.0, 8.0, 5.0),
    (82.0, 10.0, 11.0, 8.0, 6.0, 4.0),
    (85.0, 37.0, 10.0, 10.0, 10.0, 5.0),
]


def house(x, y, w, d, h, roof, base):
    """Closed, outward-oriented house: 10 vertices, 16 triangles (indices from base)."""
    x0, x1, y0, y1 = x - w / 2, x + w / 2, y - d / 2, y + d / 2
    v = [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0),
         (x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h),
         (x0, y, h + roof), (x1, y, h + roof)]           # ridge along x
    f = [(0, 2, 1), (0, 3, 2),                          # floor (facing -z)
         (0, 1, 5), (0, 5, 4), (2, 3, 7), (2, 7, 6),    # walls y0, y1
         (1, 2, 6), (1, 6, 5), (3, 0, 4), (3, 4, 7),    # walls x1, x0
         (4, 5, 9), (4, 9, 8), (6, 7, 8), (6, 8, 9),    # roof slopes
         (5, 6, 9), (7, 4, 8)]                          # gables
    return v, [(a + base, b + base, c + base) for a, b, c in f]


def main(path):
    verts, faces = [], []
    for hs in HOUSES:
        v, f = house(*hs, base=len(verts))
        verts += v
        faces += f
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as out:
        out.write("# swarmcl: a hamlet of %d houses (scripts/make_hamlet_obj.py)\n" % len(HOUSES))
        for v in verts:
            out.write("v %g %g %g\n" % v)
        for f in faces:
            out.write("f %d %d %d\n" % (f[0] + 1, f[1] + 1, f[2] + 1))


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "examples", "meshes", "hamlet.obj"))

#!/usr/bin/env python3
"""Writes the FASTSWARM Table 1 scenarios to examples/scenarios/energy_*.json.

The keypoint curves (heart: 11 keypoints, star: 10, paper Fig. 5) and the
initial positions near them are generated here so that the files can be
re-made; everything else is plain JSON to edit by hand.
"""
import json
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "examples", "scenarios")

AGGREGATION = {"rep": 1, "oa": 1, "cos": 0.05, "dir": 1, "acc": 1, "env": 0, "n": 0.2, "user": 0}
MATING = {"rep": 1, "oa": 1, "cos": 0.05, "dir": 1, "acc": 1, "env": 1, "n": 0.5, "user": 0}
ESCAPING = {"rep": 1, "oa": 1, "cos": 0.2, "dir": 1, "acc": 1, "env": 2, "n": 0.3, "user": 0}
ESCAPING_DANGER = dict(ESCAPING, oa=0, cos=0)
SHAPE = {"rep": 1, "oa": 0.5, "cos": 0, "dir": 1, "acc": 1, "env": 0, "n": 1, "user": 1}
DATASET = {"type": "synthetic", "k": 300, "groups": 10, "seed": 1}


def heart(n, size):
    # The classic heart curve in the x-z plane, n keypoints equally spaced
    # along its length (the parameter crawls near the cusps, so equal
    # parameter steps would put two keypoints within a keypoint's reach).
    def at(t):
        x = 16 * math.sin(t) ** 3
        z = 13 * math.cos(t) - 5 * math.cos(2 * t) - 2 * math.cos(3 * t) - math.cos(4 * t)
        return (size * x / 32, size * z / 32)
    m = 20000
    dense = [at(2 * math.pi * i / m) for i in range(m + 1)]
    arc = [0.0]
    for a, b in zip(dense, dense[1:]):
        arc.append(arc[-1] + math.dist(a, b))
    pts, j = [], 0
    for k in range(n):
        target = arc[-1] * k / n
        while arc[j] < target:
            j += 1
        pts.append([round(dense[j][0], 4), 0.0, round(dense[j][1], 4)])
    return pts


def star(n, size):
    # A five-pointed star: outer and inner vertices alternate (n = 10).
    pts = []
    for k in range(n):
        r = size / 2 if k % 2 == 0 else size / 5
        t = math.pi / 2 + 2 * math.pi * k / n
        pts.append([round(r * math.cos(t), 4), 0.0, round(r * math.sin(t), 4)])
    return pts


def near(points, count, spread, seed):
    rng = random.Random(seed)
    out = []
    for i in range(count):
        p = points[i % len(points)]
        out.append([round(c + rng.uniform(-spread, spread), 4) for c in p])
    return out


def scenario(name, agents, model, steps, initial, domain=1.5, every=10):
    return {
        "name": name, "seed": 4, "dt": 0.01, "steps": steps,
        "domain": {"min": [-domain] * 3, "max": [domain] * 3},
        "interaction_radius": 0.4,
        "agents": {"count": agents, "initial": initial},
        "model": dict({"type": "energy", "dataset": DATASET}, **model),
        "output": {"dir": "out/" + name, "formats": ["csv"], "every": every},
    }


def main():
    ball = {"type": "sphere", "center": [0, 0, 0], "radius": 0.3}
    files = {
        "energy_aggregation_37": scenario("energy_aggregation_37", 37,
                                          {"weights": AGGREGATION, "centre": [0, 0, 0]}, 2000, ball),
        "energy_aggregation_300": scenario("energy_aggregation_300", 300,
                                           {"weights": AGGREGATION, "centre": [0, 0, 0]}, 2000,
                                           dict(ball, radius=0.5)),
        "energy_mating": scenario("energy_mating", 100, {
            "weights": MATING,
            "stimuli": [{"type": "attract", "position": [-0.5, 0, 0], "velocity": [0.1, 0, 0]}]},
            1000, dict(ball, radius=0.4)),
        "energy_escaping": scenario("energy_escaping", 100, {
            "weights": ESCAPING, "danger_weights": ESCAPING_DANGER, "centre": [0, 0, 0], "danger_horizon": 1.0,
            "stimuli": [{"type": "startle", "position": [-1.5, 0, 0], "velocity": [0.5, 0, 0],
                         "d_danger": 0.3}]},
            1200, ball),
    }
    for name, pts in (("heart", heart(11, 1.6)), ("star", star(10, 1.6))):
        files["energy_" + name] = scenario(
            "energy_" + name, 500,
            {"weights": SHAPE, "keypoints": pts, "keypoints_closed": True, "bidirectional": True,
             "keypoint_reach": 0.1},
            2000, {"type": "points", "positions": near(pts, 500, 0.08, 7)})
    for name, s in files.items():
        path = os.path.join(OUT, name + ".json")
        with open(path, "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
        print(path)


if __name__ == "__main__":
    main()

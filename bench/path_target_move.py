#!/usr/bin/env python3
# Milliseconds per chasing-target move (curl-noise paper §7, Table 1 "per user manipulation")
# at examples/scenarios/path_chasing.json's grid.  Run from the repository root:
#   PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python bench/path_target_move.py
# ms per target move at path_chasing.json's grid (80 x 40 x 120), as the scenario (procedural mesh noise)
# and with the noise baked (the nodes near the ball's old and new places are rebaked: part of each move).
import numpy as np
import swarmcl
ctx = swarmcl.Context()
for baked in (False, True):
    with swarmcl.Swarm(ctx, agent_count=100, seed=11, domain=((0, 0, 0), (8, 4, 12)), interaction_radius=0.1, dt=1/30) as s:
        noise = swarmcl.NoiseDesc(scale=0.4, gain=0.25, seed=3, boundary_distance=0.3, domain_walls=True)
        if baked:
            noise.baked = True
        s.set_path_model(swarmcl.PathModel(obstacles=[swarmcl.SphereObstacle((4, 2, 6), 0.7), swarmcl.SphereObstacle((2.5, 2, 8.5), 0.5)],
                                           goals=[swarmcl.Goal((6, 2, 10), "sphere", radius=0.8)], resolution=(80, 40, 120),
                                           speed=1.5, goal_falloff=1.0, noise=noise))
        s.add_path_target(swarmcl.PathTarget((6, 2, 10), 0.3))
        s.set_path_goals(0, [])
        ts = []
        for k in range(10):
            c = (6, 2, 10 - 0.5 * k)
            ts.append(s.set_path_target(0, c))
            s.step(1)
        print(f"baked={baked}: set_target ms per move: median {1e3*np.median(ts[1:]):.1f} min {1e3*min(ts[1:]):.1f} max {1e3*max(ts[1:]):.1f}; preprocess {s.path_info().preprocess_seconds*1e3:.0f} ms")

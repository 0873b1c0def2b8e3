"""Worlds through Python (issue 25): Swarm(..., worlds=W), per-world
parameters as arrays of length W, (W, N, 3) views, each world bitwise the
swarm alone; bad input names the parameter and the world."""

import json

import numpy as np
import pytest

import swarmcl

DOMAIN = ((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
SEEDS = [7, 8, 90, 2**40]
SCALES = [0.3, 0.45, 0.6, 0.35]
NOISE_SEEDS = [1, 2, 3, 4]
MIN_DISTANCE = [0.03, 0.0, 0.05, 0.02]


def model(k=0):
    return swarmcl.FieldModel(
        noise=swarmcl.NoiseDesc(type="curl", seed=NOISE_SEEDS[k], scale=SCALES[k], time_scale=1.5),
        goal=(0.2, 0.0, -0.1), goal_radius=0.3, min_distance=MIN_DISTANCE[k])


def test_worlds_are_bitwise_the_swarms_alone(ctx):
    n, steps = 250, 30
    with swarmcl.Swarm(ctx, agent_count=n, domain=DOMAIN, interaction_radius=0.1, dt=0.02,
                       worlds=len(SEEDS), world_seeds=SEEDS) as s:
        assert s.worlds == 4 and s.agent_count == n
        s.set_field_model(model(0))
        s.set_world_param("noise.scale", SCALES)
        s.set_world_param("noise.seed", NOISE_SEEDS)
        s.set_world_param("min_distance", MIN_DISTANCE)
        np.testing.assert_allclose(s.world_param("noise.scale"), SCALES, rtol=1e-6)
        s.step(steps)
        pos, vel = s.positions, s.velocities
        counts = s.neighbor_count(0.12)
        stats = s.take_world_step_stats()
    assert pos.shape == (4, n, 3) and vel.shape == (4, n, 3) and counts.shape == (4, n)
    for k, seed in enumerate(SEEDS):
        with swarmcl.Swarm(ctx, agent_count=n, seed=seed, domain=DOMAIN, interaction_radius=0.1, dt=0.02) as one:
            one.set_field_model(model(k))
            one.step(steps)
            np.testing.assert_array_equal(pos[k], one.positions)
            np.testing.assert_array_equal(vel[k], one.velocities)
            np.testing.assert_array_equal(counts[k], one.neighbor_count(0.12))
            assert stats[k].mde_moved_total == one.take_step_stats().mde_moved_total
    assert stats[1].mde_moved_total == 0 and sum(x.mde_moved_total for x in stats) > 0


def test_world_views_round_trip(ctx):
    with swarmcl.Swarm(ctx, agent_count=10, worlds=3, domain=DOMAIN) as s:
        p = np.random.default_rng(0).uniform(-0.5, 0.5, size=(3, 12, 3)).astype(np.float32)
        s.positions = p
        assert s.agent_count == 12
        np.testing.assert_array_equal(s.positions, p)
        s.set_field_model(model())
        s.set_world_param("goal.center", [[0, 0, 0], [0.1, 0.2, 0.3], [1, 1, 1]])
        np.testing.assert_allclose(s.world_param("goal.center")[1], [0.1, 0.2, 0.3], rtol=1e-6)


def test_bad_world_input_names_parameter_and_world(ctx):
    with pytest.raises(ValueError, match="worlds"):
        swarmcl.Swarm(ctx, agent_count=10, worlds=0)
    with pytest.raises(ValueError, match="world_seeds"):
        swarmcl.Swarm(ctx, agent_count=10, worlds=3, world_seeds=[1, 2])
    with swarmcl.Swarm(ctx, agent_count=10, worlds=3, domain=DOMAIN) as s:
        s.set_field_model(model())
        before = s.world_param("noise.scale").copy()
        with pytest.raises(swarmcl.InvalidArgumentError, match="2 values given for 3 worlds"):
            s.set_world_param("noise.scale", [0.2, 0.3])
        with pytest.raises(swarmcl.InvalidArgumentError, match="in world 1"):
            s.set_world_param("noise.scale", [0.2, float("nan"), 0.3])
        with pytest.raises(swarmcl.InvalidArgumentError, match=r"world 2 is outside \[0, inf\)"):
            s.set_world_param("min_distance", [0.1, 0.2, -1.0])
        with pytest.raises(swarmcl.InvalidArgumentError, match="no parameter 'nope'"):
            s.set_world_param("nope", [1, 2, 3])
        np.testing.assert_array_equal(s.world_param("noise.scale"), before)
        # The path model runs worlds, its goals per world by their own keys;
        # what moves its goals while it runs (set_path_goals, the lamp's
        # setter, chasing targets) is one world's and says so.
        from swarmcl.path import Goal
        s.set_path_model(swarmcl.PathModel(goals=[Goal((0.5, 0.5, 0.5), "sphere", 0.2)], resolution=(8, 8, 8)))
        s.set_world_param("goals.0.radius", [0.1, 0.2, 0.3])
        np.testing.assert_allclose(s.world_param("groups.0.goals.0.radius"), [0.1, 0.2, 0.3], rtol=1e-6)
        with pytest.raises(swarmcl.InvalidArgumentError, match=r"groups.0.goals.0.radius = -1 in world 2"):
            s.set_world_param("goals.0.radius", [0.1, 0.2, -1.0])
        np.testing.assert_allclose(s.world_param("goals.0.radius"), [0.1, 0.2, 0.3], rtol=1e-6)
        with pytest.raises(swarmcl.InvalidArgumentError, match="several worlds"):
            s.set_path_goals(0, [Goal((0.2, 0.2, 0.2))])
        s.step(2)


def test_metrics_of_each_world_are_those_of_the_swarm_alone(ctx):
    # Metrics.attach on a swarm of worlds measures every world on the device
    # from the same launches; world(k) equals the metrics of world k's swarm
    # run alone, bitwise (moments, median, MAD, PDFs).
    n, samples, every = 120, 8, 2
    with swarmcl.Swarm(ctx, agent_count=n, domain=DOMAIN, interaction_radius=0.1, dt=0.02,
                       worlds=len(SEEDS), world_seeds=SEEDS) as s:
        s.set_field_model(model(0))
        s.set_world_param("noise.scale", SCALES)
        s.set_world_param("min_distance", MIN_DISTANCE)
        with swarmcl.Metrics.attach(s, every * 0.02) as m:
            for _ in range(samples):
                m.sample()
                s.step(every)
            with pytest.raises(swarmcl.SwarmclError, match="world"):
                m.info("speed")  # all worlds at once: read one
            with pytest.raises(swarmcl.SwarmclError, match="no world 4"):
                m.world(4)
            with pytest.raises(ValueError, match="integer >= 0"):
                m.world(-1)
            worlds = [m.world(k) for k in range(len(SEEDS))]
    for k, seed in enumerate(SEEDS):
        with swarmcl.Swarm(ctx, agent_count=n, seed=seed, domain=DOMAIN, interaction_radius=0.1, dt=0.02) as one:
            mk = model(0)
            one.set_field_model(swarmcl.FieldModel(
                noise=swarmcl.NoiseDesc(type="curl", seed=NOISE_SEEDS[0], scale=SCALES[k], time_scale=1.5),
                goal=mk.goal, goal_radius=mk.goal_radius, min_distance=MIN_DISTANCE[k]))
            with swarmcl.Metrics.attach(one, every * 0.02) as alone:
                for _ in range(samples):
                    alone.sample()
                    one.step(every)
                for name in swarmcl.METRICS:
                    assert worlds[k].info(name) == alone.info(name), (k, name)
                    np.testing.assert_array_equal(worlds[k].pdf(name), alone.pdf(name))
    assert worlds[0].info("speed")["mean"] != worlds[2].info("speed")["mean"]
    for w in worlds:
        w.close()


def test_force_model_worlds_are_the_swarms_alone(ctx):
    # The force model on worlds (issue 25): each world, with its own seed,
    # r_rep and min_distance, bitwise its swarm alone.
    n, steps = 90, 15
    r_rep, d_min = [0.08, 0.05, 0.12, 0.06], [0.03, 0.0, 0.05, 0.04]

    def force(k):
        return swarmcl.ForceModel(r_rep=r_rep[k], r_ali=0.2, r_att=0.4, min_distance=d_min[k])

    with swarmcl.Swarm(ctx, agent_count=n, domain=DOMAIN, interaction_radius=0.2, dt=0.02,
                       worlds=len(SEEDS), world_seeds=SEEDS) as s:
        s.set_force_model(force(0))
        s.set_world_param("r_rep", r_rep)
        s.set_world_param("min_distance", d_min)
        s.step(steps)
        pos, vel = s.positions, s.velocities
        with pytest.raises(swarmcl.InvalidArgumentError, match="terms cannot differ between worlds"):
            s.set_world_param("terms", [63, 62, 63, 63])
    for k, seed in enumerate(SEEDS):
        with swarmcl.Swarm(ctx, agent_count=n, domain=DOMAIN, interaction_radius=0.2, dt=0.02, seed=seed) as one:
            one.set_force_model(force(k))
            one.step(steps)
            assert pos[k].tobytes() == one.positions.tobytes()
            assert vel[k].tobytes() == one.velocities.tobytes()


def test_path_model_moving_goals_run_as_worlds_bitwise_alone(ctx, tmp_path):
    # Waypoints without targets (§7 chasing, moving goals) on worlds: every
    # world's goals move at each waypoint and its cost field is solved again,
    # each world as alone; worlds 0 and 2 share their goals (one field), the
    # others have their own radius.  A checkpoint taken after the first move
    # resumes bitwise.
    doc = {"name": "moving_goals", "seed": 3, "dt": 0.02, "steps": 40,
           "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
           "agents": {"count": 60, "initial": {"type": "uniform", "min": [0.3, 0.3, 0.3], "max": [1.0, 1.0, 1.0]}},
           "model": {"type": "path", "noise": {"type": "curl", "scale": 0.5, "gain": 0.3, "seed": 1},
                     "grid": {"resolution": [12, 12, 12]}, "speed": 0.8, "goal_falloff": 0.3,
                     "goals": [{"type": "sphere", "center": [1.5, 1.5, 1.5], "radius": 0.2}],
                     "moving_goal": {"waypoints": [[0.5, 1.5, 0.5], [1.5, 0.5, 1.0]], "every": 10},
                     "min_distance": 0.04},
           "output": {"dir": "out", "formats": ["npy"], "every": 10}}
    radii, seeds, steps = [0.2, 0.35, 0.2, 0.1], [3, 4, 5, 6], 35
    with swarmcl.Scenario.parse(json.dumps(doc)) as scn, scn.create_world_swarm(ctx, 4, seeds) as s:
        s.set_world_param("goals.0.radius", radii)
        s.step(12)  # past the first move
        s.save(tmp_path / "moving.swcl")
        s.step(steps - 12)
        pos, vel = s.positions, s.velocities
        centre = s.world_param("goals.0.center")
    with swarmcl.Swarm.load(ctx, tmp_path / "moving.swcl") as resumed:
        resumed.step(steps - 12)
        assert resumed.positions.tobytes() == pos.tobytes()
    # The goals moved twice (steps 10 and 20, then 30): every world's first goal at the waypoint.
    np.testing.assert_array_equal(np.asarray(centre).reshape(4, 3), np.float32([[0.5, 1.5, 0.5]] * 4))
    for k, (radius, seed) in enumerate(zip(radii, seeds)):
        one = json.loads(json.dumps(doc))
        one["seed"], one["model"]["goals"][0]["radius"] = seed, radius
        with swarmcl.Scenario.parse(json.dumps(one)).create_swarm(ctx) as alone:
            alone.step(steps)
            assert pos[k].tobytes() == alone.positions.tobytes(), f"world {k}"
            assert vel[k].tobytes() == alone.velocities.tobytes(), f"world {k}"


@pytest.mark.parametrize("scales", [[0.5, 0.5, 0.35], [0.5, 0.5, 0.5]], ids=["noise per world", "one noise"])
def test_path_model_chasing_targets_run_as_worlds_bitwise_alone(ctx, tmp_path, scales):
    # Chasing (§7) on worlds: the targets are one for every world; the
    # waypoints move target 0, every world's fields (its own goal radius and
    # noise scale) and noise boundaries follow as alone; a target added and
    # moved through the run-time setters too.  A checkpoint after a move
    # resumes bitwise.  A baked noise with targets is refused by name.
    doc = {"name": "chasing", "seed": 3, "dt": 0.02, "steps": 40,
           "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
           "agents": {"count": 50, "initial": {"type": "uniform", "min": [0.3, 0.3, 0.3], "max": [1.0, 1.0, 1.0]}},
           "model": {"type": "path", "noise": {"type": "curl", "scale": 0.5, "gain": 0.4, "seed": 1,
                                               "boundary_distance": 0.3},
                     "grid": {"resolution": [12, 12, 12]}, "speed": 0.8, "goal_falloff": 0.3,
                     "goals": [{"type": "sphere", "center": [1.5, 1.5, 1.5], "radius": 0.2}],
                     "targets": [{"center": [1.2, 0.8, 1.0], "radius": 0.15}],
                     "moving_goal": {"waypoints": [[0.6, 1.4, 0.7], [1.4, 0.6, 1.2]], "every": 8},
                     "min_distance": 0.04},
           "output": {"dir": "out", "formats": ["npy"], "every": 10}}
    radii, seeds, steps = [0.2, 0.3, 0.2], [3, 4, 5], 30
    extra = swarmcl.PathTarget(center=(0.5, 0.5, 1.5), radius=0.1)

    def drive(s, first, last):
        # Steps first..last-1; at step 12 a second target, at 20 it moves.
        for step in range(first, last):
            if step == 12:
                assert s.add_path_target(extra) == 1
            if step == 20:
                s.set_path_target(1, (0.6, 0.6, 1.4))
            s.step(1)

    with swarmcl.Scenario.parse(json.dumps(doc)) as scn, scn.create_world_swarm(ctx, 3, seeds) as s:
        s.set_world_param("goals.0.radius", radii)
        s.set_world_param("noise.scale", scales)
        drive(s, 0, 14)
        s.save(tmp_path / "chasing.swcl")
        drive(s, 14, steps)
        pos = s.positions
    with swarmcl.Swarm.load(ctx, tmp_path / "chasing.swcl") as resumed:
        drive(resumed, 14, steps)
        assert resumed.positions.tobytes() == pos.tobytes()
    for k, (radius, scale, seed) in enumerate(zip(radii, scales, seeds)):
        one = json.loads(json.dumps(doc))
        one["seed"], one["model"]["goals"][0]["radius"], one["model"]["noise"]["scale"] = seed, radius, scale
        with swarmcl.Scenario.parse(json.dumps(one)).create_swarm(ctx) as alone:
            drive(alone, 0, steps)
            assert pos[k].tobytes() == alone.positions.tobytes(), f"world {k}"
    baked = json.loads(json.dumps(doc))
    baked["model"]["noise"]["baked"] = True
    with swarmcl.Scenario.parse(json.dumps(baked)) as scn:
        with pytest.raises(swarmcl.InvalidArgumentError, match="chasing targets with a baked noise"):
            scn.create_world_swarm(ctx, 2)


@pytest.mark.parametrize("own_domains", [False, True])
def test_policy_model_worlds_are_bitwise_the_swarms_alone(ctx, tmp_path, own_domains):
    # The policy model on worlds: a leader a world (alike), each world with
    # its own seed, r_coh, body radius, du_max and dq_max_deg (and, with
    # own_domains, its own domain: its own grid), bitwise its swarm alone;
    # the observations come back world by world; a checkpoint resumes
    # bitwise; the leader's parameters are refused per world by name.
    from conftest import TOUR
    n, steps, seeds = 70, 12, [3, 11, 29]
    per_world = {"r_coh": [18.0, 12.0, 18.0], "body_radius": [0.5, 0.8, 0.3], "du_max": [0.1, 0.05, 0.2],
                 "dq_max_deg": [4.0, 2.0, 8.0]}
    domain = ((-60, -60, -30), (60, 60, 30))
    domains = ([((-60 - 10 * k, -60 + 5 * k, -30), (60 + 7 * k, 60, 30 + 10 * k)) for k in range(3)]
               if own_domains else [domain] * 3)

    def model(k=0):
        return swarmcl.PolicyModel(leader_mode="tour", leader_speed=0.6, waypoints=TOUR,
                                   **{key: v[k] for key, v in per_world.items()})

    def start(s, k):
        rng = np.random.default_rng(seeds[k])
        return rng.normal(0, 4, (n, 3)).astype(np.float32) + np.float32([-8, 0, 0])

    with swarmcl.Swarm(ctx, agent_count=n, domain=domain, interaction_radius=18.5, dt=0.1, worlds=3,
                       world_seeds=seeds, world_domains=domains if own_domains else None) as s:
        np.testing.assert_array_equal(s.world_domains, np.float64(domains))
        s.write_positions(np.stack([start(s, k) for k in range(3)]))
        s.write_velocities(np.tile(np.float32([0.5, 0, 0]), (3, n, 1)))
        s.set_policy_model(model(0))
        for key, v in per_world.items():
            s.set_world_param(key, v)
        with pytest.raises(swarmcl.InvalidArgumentError, match="u_max cannot differ between worlds"):
            s.set_world_param("u_max", [3.0, 2.0, 3.0])
        with pytest.raises(swarmcl.InvalidArgumentError, match="leader.du_max cannot differ between worlds"):
            s.set_world_param("leader.du_max", [0.1, 0.2, 0.1])
        with pytest.raises(swarmcl.InvalidArgumentError, match="world 1"):
            s.set_world_param("r_coh", [18.0, 0.5, 18.0])  # below r_ali: refused, nothing set
        np.testing.assert_allclose(s.world_param("r_coh"), per_world["r_coh"])
        s.step(steps // 2)
        s.save(tmp_path / "policy.swcl")
        s.step(steps - steps // 2)
        pos, vel = s.positions, s.velocities
        obs, act = s.policy_observe()
    assert obs.shape == (3, n, 54) and act.shape == (3, n, 4)
    with swarmcl.Swarm.load(ctx, tmp_path / "policy.swcl") as resumed:
        np.testing.assert_array_equal(resumed.world_domains, np.float64(domains))
        resumed.step(steps - steps // 2)
        assert resumed.positions.tobytes() == pos.tobytes()
    for k in range(3):
        with swarmcl.Swarm(ctx, agent_count=n, domain=domains[k], interaction_radius=18.5, dt=0.1,
                           seed=seeds[k]) as one:
            one.write_positions(start(one, k))
            one.write_velocities(np.tile(np.float32([0.5, 0, 0]), (n, 1)))
            one.set_policy_model(model(k))
            one.step(steps)
            assert pos[k].tobytes() == one.positions.tobytes(), f"world {k}"
            assert vel[k].tobytes() == one.velocities.tobytes(), f"world {k}"
            o, a = one.policy_observe()
            assert obs[k].tobytes() == o.tobytes() and act[k].tobytes() == a.tobytes(), f"world {k}"
    assert pos[0].tobytes() != pos[1].tobytes()


def test_world_domains_place_each_world_in_its_box_and_bad_ones_are_refused(ctx):
    boxes = np.array([[(-1, -1, -1), (1, 1, 1)], [(2, 0, 0), (5, 1, 0.5)]])
    with swarmcl.Swarm(ctx, agent_count=200, worlds=2, world_domains=boxes, interaction_radius=0.2) as s:
        pos = s.positions
        for k in range(2):
            assert (pos[k] >= np.float32(boxes[k, 0])).all() and (pos[k] < np.float32(boxes[k, 1])).all()
    with pytest.raises(ValueError, match=r"world_domains must be shaped \(2, 2, 3\)"):
        swarmcl.Swarm(ctx, agent_count=10, worlds=2, world_domains=boxes[:1])
    bad = boxes.copy()
    bad[1, 1, 2] = -1.0  # world 1: max z below min z
    with pytest.raises(swarmcl.InvalidArgumentError, match=r"world 1 domain min\[2\]"):
        swarmcl.Swarm(ctx, agent_count=10, worlds=2, world_domains=bad)
    bad[1, 1, 2] = np.nan
    with pytest.raises(swarmcl.InvalidArgumentError, match="world 1 domain bounds must be finite"):
        swarmcl.Swarm(ctx, agent_count=10, worlds=2, world_domains=bad)
    # The path model's grid covers one domain for every world.
    with swarmcl.Swarm(ctx, agent_count=10, worlds=2, world_domains=boxes) as s:
        with pytest.raises(swarmcl.InvalidArgumentError, match="the path model needs one domain for every world"):
            s.set_path_model(swarmcl.PathModel())


def test_step_frames_are_the_frames_of_step_then_read(ctx):
    def swarm(worlds):
        s = swarmcl.Swarm(ctx, agent_count=40, worlds=worlds, interaction_radius=0.2, dt=0.02)
        s.set_field_model(swarmcl.FieldModel(min_distance=0.05))
        return s
    for worlds in (3, 1):
        with swarm(worlds) as a, swarm(worlds) as b:
            frames = a.step_frames(5, every=2)
            assert frames.shape == ((5, 3, 40, 3) if worlds == 3 else (5, 40, 3))
            for f in range(5):
                b.step(2)
                assert frames[f].tobytes() == b.positions.tobytes(), f"frame {f}"
            assert a.step_count == 10
            with pytest.raises(ValueError, match="every >= 1"):
                a.step_frames(2, every=0)
            assert a.step_frames(0).shape[0] == 0 and a.step_count == 10
            # out=: written in place; a wrong one refused before any step.
            out = np.empty((2,) + frames.shape[1:], dtype=np.float32)
            assert a.step_frames(2, every=2, out=out) is out
            b.step(4)
            assert out[1].tobytes() == b.positions.tobytes() and a.step_count == 14
            for bad in (np.empty((3,) + frames.shape[1:], np.float32), out.astype(np.float64), out[:, ::-1]):
                with pytest.raises(ValueError, match="step_frames: out"):
                    a.step_frames(2, every=2, out=bad)
            assert a.step_count == 14
    # Metrics of one world's frames read in place from all worlds' frames
    # are those of the world's frames copied out.
    with swarm(3) as a:
        frames = np.concatenate([a.positions[None], a.step_frames(20)])
        for k in range(3):
            with swarmcl.Metrics.from_frames(frames[:, k], 0.02) as strided, \
                    swarmcl.Metrics.from_frames(np.ascontiguousarray(frames[:, k]), 0.02) as packed:
                assert not frames[:, k].flags.c_contiguous
                for m in swarmcl.METRICS:
                    assert strided.info(m) == packed.info(m)
                assert np.array_equal(strided.pdf("speed"), packed.pdf("speed"))

"""The path model from Python: defaults from C, a run around a mesh given as
arrays, moving goals, groups, errors as exceptions."""

import numpy as np
import pytest

import swarmcl

DOMAIN = ((0.0, 0.0, 0.0), (4.0, 2.0, 2.0))
CUBE_V = np.array([[x, y, z] for z in (-.3, .3) for y in (-.3, .3) for x in (-.3, .3)], np.float32) + (2, 1, 1)
CUBE_T = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                   [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]], np.uint32)


def test_defaults_are_the_papers():
    m = swarmcl.PathModel()
    assert (m.cost_a, m.cost_b, m.speed) == (0.6, 0.4, 1.5)
    assert m.noise.scale == 0.4 and m.noise.gain == 0.25
    assert m.resolution == (64, 64, 64)


def make(ctx, **kw):
    s = swarmcl.Swarm(ctx, agent_count=200, seed=2, domain=DOMAIN, interaction_radius=0.1, dt=0.02)
    pos = s.positions
    pos[:, 0] = np.where(pos[:, 0] < 2, 0.3, 3.7)  # out of the cube, at both ends
    s.positions = pos
    model = swarmcl.PathModel(obstacles=[swarmcl.MeshObstacle(CUBE_V, CUBE_T)], resolution=(40, 20, 20),
                              noise=swarmcl.NoiseDesc(gain=0.1, domain_walls=True), **kw)
    s.set_path_model(model)
    return s


def test_run_around_a_mesh_reaches_the_goal(ctx):
    with make(ctx, goals=[swarmcl.Goal((3.6, 1.0, 1.0), "sphere", radius=0.3)], speed=1.0) as s:
        info = s.path_info()
        assert info.grid == (40, 20, 20) and info.preprocess_seconds > 0
        s.step(250)
        p = s.positions
        assert np.isfinite(p).all()
        inside = np.all(np.abs(p - (2, 1, 1)) < 0.28, axis=1)
        assert not inside.any()
        assert np.median(np.linalg.norm(p - (3.6, 1, 1), axis=1)) < 0.5
        assert s.take_step_stats().steps == 250
        t = s.set_path_goals(0, [swarmcl.Goal((0.4, 1.0, 1.0))])
        assert t > 0 and s.path_info().recomputes == 1


def test_two_groups_cross(ctx):
    with swarmcl.Swarm(ctx, agent_count=100, seed=2, domain=DOMAIN, interaction_radius=0.1, dt=0.02) as s:
        pos = s.positions
        pos[:50, 0], pos[50:, 0] = 0.3, 3.7
        s.positions = pos
        s.set_path_model(swarmcl.PathModel(resolution=(40, 20, 20), speed=1.0, groups=[
            swarmcl.PathGroup(50, [swarmcl.Goal((3.7, 1, 1), "sphere", radius=0.3)]),
            swarmcl.PathGroup(50, [swarmcl.Goal((0.3, 1, 1), "sphere", radius=0.3)])]))
        s.step(250)
        p = s.positions
        assert np.all(p[:50, 0] > 3.0) and np.all(p[50:, 0] < 1.0)


def test_errors_are_exceptions_and_keep_the_model(ctx):
    with make(ctx, goals=[swarmcl.Goal((3.6, 1.0, 1.0))]) as s:
        with pytest.raises(swarmcl.InvalidArgumentError, match="inside an obstacle"):
            s.set_path_model(swarmcl.PathModel(obstacles=[swarmcl.MeshObstacle(CUBE_V, CUBE_T)],
                                               goals=[swarmcl.Goal((2, 1, 1))], resolution=(40, 20, 20)))
        with pytest.raises(swarmcl.InvalidArgumentError, match="outside the grid"):
            s.set_path_goals(0, [swarmcl.Goal((9, 9, 9))])
        bad = CUBE_V.copy()
        bad[3, 1] = np.nan
        with pytest.raises(swarmcl.InvalidArgumentError, match="vertex 3"):
            s.set_path_model(swarmcl.PathModel(obstacles=[swarmcl.MeshObstacle(bad, CUBE_T)],
                                               goals=[swarmcl.Goal((3.6, 1, 1))]))
        with pytest.raises(swarmcl.IOError_):
            s.set_path_model(swarmcl.PathModel(obstacles=[swarmcl.ObjObstacle("/nonexistent.obj")],
                                               goals=[swarmcl.Goal((3.6, 1, 1))]))
        assert s.path_info().grid == (40, 20, 20)  # the first model is still there
        s.step(2)


def test_chasing_target_driven_from_python(ctx):
    """§7 chasing: a target dragged each few steps; the swarm follows it; bad centres
    (inside the cube, outside the grid) raise and leave the target where it was."""
    with swarmcl.Swarm(ctx, agent_count=60, seed=4, domain=DOMAIN, interaction_radius=0.1, dt=0.02) as s:
        s.set_path_model(swarmcl.PathModel(obstacles=[swarmcl.MeshObstacle(CUBE_V, CUBE_T)],
                                           goals=[swarmcl.Goal((3.6, 1.0, 1.0))], resolution=(40, 20, 20),
                                           speed=1.0, goal_falloff=0.2))
        assert s.add_path_target(swarmcl.PathTarget((3.5, 0.5, 1.0), 0.15)) == 0
        s.set_path_goals(0, [])  # the target alone is the goal
        for k in range(20):
            c = (3.5, 0.5 + k * 0.05, 1.0)
            t = s.set_path_target(0, c)
            assert t > 0 or k == 0  # k = 0: where it was added
            s.step(10)
        s.step(100)
        d = np.linalg.norm(s.positions - c, axis=1)
        assert np.median(d) < 0.4
        assert s.set_path_target(0, c) == 0.0  # not moved: nothing recomputed
        with pytest.raises(swarmcl.InvalidArgumentError, match="inside an obstacle"):
            s.set_path_target(0, (2.0, 1.0, 1.0))
        with pytest.raises(swarmcl.InvalidArgumentError, match="outside the path grid"):
            s.set_path_target(0, (9.0, 1.0, 1.0))
        assert s.path_target(0).center == pytest.approx(c)
        assert s.path_target_count() == 1
        with pytest.raises(swarmcl.InvalidArgumentError, match="no free space"):
            s.set_path_lamp(swarmcl.Lamp((2.0, 1.0, 1.0), radius=0.01, keep_out=0.01))
        s.set_path_lamp(swarmcl.Lamp((1.0, 1.0, 1.0), radius=0.1, angle=1.2))
        s.step(5)
        assert np.isfinite(s.positions).all()

"""The force model (shape-constrained flying insects) through the Python binding."""

import numpy as np
import pytest

import swarmcl

DOMAIN = ((-4.0, -4.0, -4.0), (4.0, 4.0, 4.0))


def test_defaults_are_table_1():
    m = swarmcl.ForceModel()
    assert (m.r_rep, m.r_ali, m.r_att) == (0.3, 10.0, 30.0)
    assert (m.w_rep, m.w_ali, m.w_att, m.w_dis) == (0.2, 3.0, 13.0, 4.0)
    assert (m.eta, m.rho, m.alpha, m.max_speed) == (0.125, 0.32, 0.7, 0.75)


def run(ctx, steps, seed=4, n=500, **kw):
    model = swarmcl.ForceModel(min_spacing=0.0, keyframes=[swarmcl.Keyframe(0, "sphere")], **kw)
    with swarmcl.Swarm(ctx, agent_count=n, seed=seed, domain=DOMAIN, interaction_radius=1.0,
                       dt=1 / 60) as s:
        s.set_force_model(model)
        s.step(steps)
        return s.positions, s.velocities, s.force_targets()


def test_swarm_gathers_on_the_sphere_and_keeps_flying(ctx):
    p, v, t = run(ctx, 900)   # band 0.15 m ~ the target spacing sqrt(4 pi / 500)
    r = np.linalg.norm(p, axis=1)
    assert np.mean(np.abs(r - 1.0) < 0.15) >= 0.9
    assert np.linalg.norm(v, axis=1).mean() >= 0.3
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, atol=0.02)   # targets on the mesh


def test_deterministic_for_a_seed(ctx):
    a = run(ctx, 30)[0]
    b = run(ctx, 30)[0]
    np.testing.assert_array_equal(a, b)


def test_raw_mesh_keyframes_path_and_errors(ctx):
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    tris = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.uint32)
    with swarmcl.Swarm(ctx, agent_count=100, seed=1, domain=DOMAIN, interaction_radius=1.0) as s:
        s.set_force_model(swarmcl.ForceModel(min_spacing=0.0, keyframes=[
            swarmcl.Keyframe(0, vertices=verts, triangles=tris)]))
        s.step(1)
        t = s.force_targets()
        assert (t >= -1e-6).all() and (t.sum(axis=1) <= 1 + 1e-5).all()
        s.set_force_path([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], speed=0.5)
        with pytest.raises(swarmcl.InvalidArgumentError, match="at least 4"):
            s.set_force_path([[0, 0, 0], [1, 0, 0], [2, 0, 0]], speed=0.5)
        with pytest.raises(swarmcl.InvalidArgumentError, match="increasing frame order"):
            s.set_force_keyframes([swarmcl.Keyframe(5, "torus"), swarmcl.Keyframe(2, "heart")])
        with pytest.raises(swarmcl.InvalidArgumentError, match="alpha"):
            s.set_force_model(swarmcl.ForceModel(alpha=2.0))
        with pytest.raises(ValueError):
            swarmcl.ForceModel(assignment="random").to_c()
        s.step(2)   # the model in place still runs
        assert np.isfinite(s.positions).all()


def test_scenario_with_the_force_model(ctx):
    sc = swarmcl.Scenario.parse("""{"agents": {"count": 64}, "domain": {"min": [-3,-3,-3], "max": [3,3,3]},
        "model": {"type": "force", "min_spacing": 0, "keyframes": [{"frame": 0, "shape": "star"}]}}""")
    assert sc.info["model"] == "force"
    with sc.create_swarm(ctx) as s:
        s.step(3)
        assert s.force_targets().shape == (64, 3)


def test_shape_turns_with_the_path_unless_orient_is_off(ctx):
    # A horse (long along +x) on a path along +y: turned a quarter by default.
    assert swarmcl.ForceModel().path_orient is True
    path = [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]]
    extents = {}
    for orient in (True, False):
        model = swarmcl.ForceModel(min_spacing=0.0, keyframes=[swarmcl.Keyframe(0, "horse")],
                                   path=path, path_speed=0.5, path_orient=orient)
        with swarmcl.Swarm(ctx, agent_count=200, seed=3, domain=DOMAIN, interaction_radius=1.0) as s:
            s.set_force_model(model)
            s.step(1)
            t = s.force_targets()
            extents[orient] = t.max(axis=0) - t.min(axis=0)
    assert extents[True][1] > 2.0 and extents[True][0] < 1.0
    assert extents[False][0] > 2.0 and extents[False][1] < 1.0


def test_mesh_obstacles_keep_insects_out(ctx, tmp_path):
    # Insects fly from x = -2 to a sphere of targets at x = +2 past a box
    # (an OBJ file) off their line; none ends inside it (exact test).
    obj = tmp_path / "box.obj"
    obj.write_text("v -0.3 0.05 -0.6\nv 0.3 0.05 -0.6\nv 0.3 0.85 -0.6\nv -0.3 0.85 -0.6\n"
                   "v -0.3 0.05 0.6\nv 0.3 0.05 0.6\nv 0.3 0.85 0.6\nv -0.3 0.85 0.6\n"
                   "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n")
    m = swarmcl.ForceModel()
    assert m.mesh_obstacles == [] and m.mesh_cell == 0.0
    sphere = swarmcl.Keyframe(0, "sphere", scale=0.4, offset=(2.0, 0.0, 0.0))
    model = swarmcl.ForceModel(min_spacing=0.0, keyframes=[sphere], obstacle_range=0.5,
                               mesh_obstacles=[swarmcl.ObjObstacle(str(obj)),
                                               swarmcl.CylinderObstacle((0, -2, -0.5), 0.2, 1.0)])
    rng = np.random.default_rng(3)
    start = rng.uniform(-0.35, 0.35, (100, 3)).astype(np.float32)
    start[:, 0] -= 2.0
    with swarmcl.Swarm(ctx, agent_count=100, seed=2, domain=DOMAIN, interaction_radius=1.0, dt=0.05) as s:
        s.positions = start
        s.set_force_model(model)
        for _ in range(30):
            s.step(10)
            p = s.positions - np.array([0.0, 0.45, 0.0], np.float32)
            inside = (np.abs(p) < np.array([0.3, 0.4, 0.6], np.float32)).all(axis=1)
            assert not inside.any()
        assert s.positions[:, 0].mean() > 1.0
        # Bad input: a clear error, the model in place stays.
        with pytest.raises(swarmcl.IOError_):
            s.set_force_model(swarmcl.ForceModel(mesh_obstacles=[swarmcl.ObjObstacle(str(tmp_path / "no.obj"))]))
        with pytest.raises(swarmcl.InvalidArgumentError, match="raise mesh_cell"):
            s.set_force_model(swarmcl.ForceModel(mesh_obstacles=[swarmcl.ObjObstacle(str(obj))], mesh_cell=1e-3))
        with pytest.raises(TypeError):
            swarmcl.ForceModel(mesh_obstacles=[swarmcl.Sphere((0, 0, 0), 1.0)]).to_c()
        np.testing.assert_allclose(np.linalg.norm(s.force_targets() - [2, 0, 0], axis=1), 0.4, atol=0.02)

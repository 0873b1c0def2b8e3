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

"""The §IV evaluation metrics (swarmcl.rl.evaluation, issue 15 item 8)."""

import os

import numpy as np
import pytest

if os.environ.get("SWARMCL_REQUIRE_RL") == "1":
    import gymnasium  # noqa: F401 - scripts/test.sh installs swarmcl[rl]
else:
    pytest.importorskip("gymnasium")

from swarmcl.rl import RlEnv  # noqa: E402
from swarmcl.rl.evaluation import (cohesion_repulsion, inter_agent_distance, speed_differential,  # noqa: E402
                                   swarm_rewards)


def test_swarm_rewards_equal_the_environments(ctx):
    """Eq. 14-19 in NumPy give the rewards the device computed for the same state."""
    env = RlEnv(ctx, 2, 60, scenario="roaming")
    try:
        env.reset(7)
        for _ in range(15):
            _, rew, _, _ = env.step(env.rag_actions())
        st = env.read_state()
        for w in range(2):
            sl = slice(w * 60, (w + 1) * 60)
            vel = st["velocities"][sl]
            got = swarm_rewards(st["positions"][sl, :3], vel[:, :3], vel[:, 3], st["leader_positions"][w, :3])
            np.testing.assert_allclose(got, rew[sl], rtol=2e-4, atol=2e-4)
            some = np.array([3, 0, 59])
            np.testing.assert_allclose(
                swarm_rewards(st["positions"][sl, :3], vel[:, :3], vel[:, 3], st["leader_positions"][w, :3], rows=some,
                              block=2), got[some], rtol=1e-12)
    finally:
        env.close()


def test_inter_agent_distance_is_equation_20_and_21():
    p = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [10, 0, 0]], float)
    mu, sigma, pairs = inter_agent_distance(p, radius=2.5)
    d = np.array([1, 2, 1, 1, 2, 1], float)  # ordered pairs within 2.5; the agent at 10 has none
    assert pairs == 6
    assert mu == pytest.approx(d.mean()) and sigma == pytest.approx(d.std())
    mu1, _, pairs1 = inter_agent_distance(p, radius=2.5, rows=[1])
    assert (mu1, pairs1) == (pytest.approx(1.0), 2)
    assert np.isnan(inter_agent_distance(p, radius=0.5)[0])
    with pytest.raises(ValueError, match="radius"):
        inter_agent_distance(p, radius=0)
    with pytest.raises(ValueError, match="shape"):
        inter_agent_distance(p[:, :2], radius=1)


def test_cohesion_repulsion_counts_the_longer_vector():
    # A close pair (0.5 apart: both repelled), a pair 12 apart (both drawn in),
    # and a lone agent far away (neither).
    p = np.array([[0, 0, 0], [0.5, 0, 0], [100, 0, 0], [112, 0, 0], [500, 0, 0]], float)
    assert cohesion_repulsion(p) == (2, 2)
    # An agent with a close neighbour and a far one: repulsion's w_sep = 4 beats w_coh = 2.
    assert cohesion_repulsion(np.array([[0, 0, 0], [0.5, 0, 0], [12, 0, 0]], float))[0] >= 1
    assert cohesion_repulsion(p, rows=[0, 2]) == (1, 1)
    with pytest.raises(ValueError, match="radii"):
        cohesion_repulsion(p, r_sep=10, r_ali=9)


def test_speed_differential():
    assert speed_differential([[0.5, 1.0], [1.0, 1.0]], [1.0, 0.5]) == pytest.approx((0.5 + 0 + 0.5 + 0.5) / 4)
    with pytest.raises(ValueError):
        speed_differential([], 1.0)


def test_scenario_layout_and_its_mesh(ctx, tmp_path):
    from swarmcl.rl.layout import box_mesh, boxes_to_obj

    env = RlEnv(ctx, 1, 4, scenario="maze")
    try:
        lay = env.layout()
    finally:
        env.close()
    assert lay["waypoints"].shape == (8, 4) and lay["obstacles"].shape == (5, 6)
    np.testing.assert_array_equal(lay["obstacles"][0], [20, -6, 0, 1, 14, 10])
    verts, tris = box_mesh(lay["obstacles"])
    assert verts.shape == (40, 3) and tris.shape == (60, 3)
    # Every triangle faces away from its box's centre (outward normals), and
    # the 12 triangles of a box cover its area 2(ab + bc + ca) * 4.
    for i, b in enumerate(lay["obstacles"].astype(float)):
        t = verts[tris[12 * i:12 * i + 12]]
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        assert (np.einsum("tk,tk->t", n, t.mean(1) - b[:3]) > 0).all()
        h = b[3:]
        assert 0.5 * np.linalg.norm(n, axis=1).sum() == pytest.approx(8 * (h[0] * h[1] + h[1] * h[2] + h[2] * h[0]))
    text = boxes_to_obj(lay["obstacles"], tmp_path / "maze.obj", comment="maze")
    assert (tmp_path / "maze.obj").read_text() == text
    assert text.count("\nv ") == 40 and text.count("\nf ") == 60
    with pytest.raises(ValueError, match="half extents"):
        box_mesh([0, 0, 0, 1, 0, 1])
    env = RlEnv(ctx, 1, 4, scenario="roaming")
    try:
        assert env.layout()["waypoints"].shape == (0, 4)
    finally:
        env.close()


def test_the_evaluation_script_runs_every_part_small(tmp_path):
    """scripts/rl_evaluation.py end to end on tiny settings (its full run writes docs/rl-evaluation.md)."""
    import json
    import subprocess
    import sys

    from conftest import REPO

    out = tmp_path / "ev.json"
    cmd = [sys.executable, str(REPO / "scripts" / "rl_evaluation.py"), "--worlds", "2", "--agents", "12",
           "--warmup", "5", "--record", "50", "--nav-worlds", "1", "--nav-max-steps", "150", "--sizes", "30", "60",
           "--scal-steps", "70", "--settle-steps", "40", "--out-json", str(out), "--out-md", str(tmp_path / "ev.md"),
           "--figures-dir", str(tmp_path), "--meshes-dir", str(tmp_path)]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    res = json.loads(out.read_text())
    assert list(res["control"]) == ["rule", "policy_roaming", "policy_roaming_ddpg"]  # the default policies
    for method in res["control"]:
        assert len(res["control"][method]) == 8 and len(res["navigation"][method]) == 3
        for r in res["control"][method].values():
            assert np.isfinite(r["speed_diff"]) and r["speed_diff"] >= 0
        assert res["control"][method]["180 left"]["leader_turned_deg"] == pytest.approx(180, abs=1)
    assert [r["agents"] for r in res["scalability"]["no_efs"]] == [30, 60]
    for r in res["scalability"]["efs"] + res["scalability"]["no_efs"]:
        # the placement's reward, and the mean of the samples after step 40 (steps 50, 60, 70)
        assert np.isfinite(r["start_reward"]) and r["settle_steps"] == 40
        settled = [e["reward"] for e in r["rewards"] if e["step"] > 40]
        assert [e["step"] for e in r["rewards"] if e["step"] > 40] == [50, 60, 70]
        assert r["mean_reward"] == pytest.approx(np.mean(settled))
    assert set(res["crowding"]) == {"rule", "policy_roaming", "policy_roaming_ddpg"}
    for r in res["crowding"].values():
        assert 0 <= r["crowded"] <= 1 and len(r["eq19"]) == len(r["eq19_scales"])
    assert res["rag"] == {"rag_leader_pd": True, "rag_leader_kp": 0.25, "rag_leader_kd": 1.0}
    assert set(res["commands"]) == {"control", "navigation", "scalability", "crowding"}
    assert res["commands"]["control"].startswith("PYTHONPATH=bindings/python SWARMCL_BUILD_DIR=$PWD/build python "
                                                 "scripts/rl_evaluation.py --worlds 2")
    md = (tmp_path / "ev.md").read_text()
    assert "| 90° | top |" in md and "| 60 |" in md and "`policy_roaming_ddpg`" in md
    assert "with the PD leader coupling (k_p 0.25, k_d 1" in md and "## Why the learned swarms crowd" in md
    assert "Settled reward minus the placement's" in md
    assert "* control, navigation, scalability, crowding: `PYTHONPATH=" in md
    for name in ("rl_eval_interagent.png", "rl_eval_scenarios.png", "rl_eval_scalability.png", "rl_maze.obj",
                 "rl_stairway.obj"):
        assert (tmp_path / name).stat().st_size > 0, name


def _rl_evaluation_script():
    """scripts/rl_evaluation.py as a module (it imports scripts/machine_info.py beside it)."""
    import importlib.util
    import sys

    from conftest import REPO

    sys.path.insert(0, str(REPO / "scripts"))
    try:
        spec = importlib.util.spec_from_file_location("rl_evaluation", REPO / "scripts" / "rl_evaluation.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
    finally:
        sys.path.remove(str(REPO / "scripts"))
    return mod


def _rows(sizes, rewards):
    return [{"agents": n, "mean_reward": r} for n, r in zip(sizes, rewards)]


def test_scalability_sentence_comes_from_the_numbers():
    """The Fig. 11 summary says narrows / widens / neither as the numbers do,
    not a fixed sentence (issue 28)."""
    summary = _rl_evaluation_script().scalability_summary
    sizes = [200, 600, 1000, 100_000]
    # The results of 2026-11-25 (100,000 measured from step 50): the gap
    # falls 14.3 -> 0.43 and both rewards fall.
    narrow = summary(_rows(sizes, [-6.5, -26.4, -40.7, -88.0]), _rows(sizes, [-20.8, -36.7, -42.6, -88.5]))
    assert "4 of 4 sizes" in narrow and "the gap narrows at every larger size" in narrow
    assert "widens" not in narrow and "both policies' rewards fall" in narrow
    assert "+14.300 at 200" in narrow and "+0.500 at 100,000" in narrow
    # A gap that widens with size: the same function must say so.
    wide = summary(_rows(sizes, [-6.0, -5.0, -4.0, -3.0]), _rows(sizes, [-7.0, -8.0, -10.0, -20.0]))
    assert "the gap widens at every larger size" in wide and "narrows" not in wide
    assert "4 of 4 sizes" in wide and "both policies" not in wide   # EFS rises, no EFS falls
    # Neither, with a sign change and a loss for EFS at one size.
    mixed = summary(_rows(sizes[:3], [-6.0, -9.0, -4.0]), _rows(sizes[:3], [-7.0, -8.0, -10.0]))
    assert "2 of 3 sizes" in mixed and "neither narrows nor widens steadily" in mixed and "changes sign" in mixed
    assert "no trend" in summary(_rows([200], [-1.0]), _rows([200], [-2.0]))
    with pytest.raises(ValueError, match="same sizes"):
        summary(_rows(sizes, [0, 0, 0, 0]), _rows(sizes[:3], [0, 0, 0]))

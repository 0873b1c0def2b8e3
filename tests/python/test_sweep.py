"""Parameter sweeps (issue 25): every row of a grid or list run as one world
of one swarm gives the statistics and score of the same scenario run alone;
a model without worlds runs one swarm a row; MPI ranks give the same rows;
bad grids are refused before anything runs or is written."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import swarmcl

SCENARIO = {
    "name": "sweep_tiny", "seed": 4, "dt": 0.02, "steps": 30,
    "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
    "agents": {"count": 24, "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
    "model": {"type": "field", "noise": {"type": "curl", "scale": 0.5, "gain": 0.3, "seed": 1, "domain_walls": True},
              "goal": {"center": [1, 1, 1.5], "speed": 0.5}, "min_distance": 0.05},
    "output": {"dir": "results", "formats": ["npy"], "every": 5},
}
GRID = {"model.noise.gain": [0.1, 0.6], "model.goal.speed": [0.2, 0.7, 1.2]}


def alone(ctx, values, steps=30, frames=False):
    doc = json.loads(json.dumps(SCENARIO))
    for path, v in values.items():
        node = doc
        *parts, last = path.split(".")
        for p in parts:
            node = node[int(p)] if isinstance(node, list) else node[p]
        if isinstance(node, list):
            node[int(last)] = v
        else:
            node[last] = v
    with swarmcl.Scenario.parse(json.dumps(doc)).create_swarm(ctx) as s:
        out = [s.read_positions()]
        for _ in range(steps):
            s.step(1)
            out.append(s.read_positions())
        return s.read_velocities(), s.nearest_neighbor()[0], s.take_step_stats(), np.stack(out)


def test_grid_rows_are_the_runs_alone(ctx):
    keys, rows = swarmcl.load_grid(GRID, SCENARIO)
    assert keys == list(GRID) and len(rows) == 6 and rows[1] == [0.1, 0.7]  # first key slowest
    r = swarmcl.sweep(SCENARIO, GRID, context=ctx)
    assert r["worlds"] and len(r["rows"]) == 6
    for row in r["rows"]:
        vel, nn, stats, frames = alone(ctx, {k: row[k] for k in keys})
        assert row["finite"]
        assert row["mean_speed"] == float(np.linalg.norm(vel, axis=1).mean())
        assert row["median_nearest_distance"] == float(np.median(nn))
        assert row["mde_moved_total"] == stats.mde_moved_total
    assert len({row["mean_speed"] for row in r["rows"]}) == 6


def test_domain_rows_run_as_worlds_each_in_its_own_domain(ctx):
    """A grid over the domain's corners: the rows still run as the worlds
    of one swarm, each world in its row's domain (its noise walls and grid
    its own), and each row is the scenario alone with that domain."""
    grid = {"domain.max.0": [1.6, 1.8], "domain.min.2": [0.0, 0.35], "model.goal.speed": [0.4]}
    r = swarmcl.sweep(SCENARIO, grid, context=ctx)
    assert r["worlds"] and r["swarms"] == 1 and len(r["rows"]) == 4
    for row in r["rows"]:
        vel, nn, stats, _ = alone(ctx, {k: row[k] for k in grid})
        assert row["mean_speed"] == float(np.linalg.norm(vel, axis=1).mean())
        assert row["median_nearest_distance"] == float(np.median(nn))
        assert row["mde_moved_total"] == stats.mde_moved_total
    assert len({row["radius_of_gyration"] for row in r["rows"]}) == 4  # the walls moved
    # A domain whose max is below its min: the scenario refuses it, naming it.
    with pytest.raises(swarmcl.SwarmclError, match="domain"):
        swarmcl.sweep(SCENARIO, {"domain.max.0": [2.0, -1.0]}, context=ctx)


def test_scores_against_tracks_are_those_of_the_runs_alone(ctx):
    _, _, _, frames = alone(ctx, {"model.noise.gain": 0.4, "model.goal.speed": 0.9})
    with swarmcl.Metrics.from_frames(frames, 0.02) as real:
        runs = {"runs": [{"model.noise.gain": 0.4, "model.goal.speed": 0.9},
                         {"model.noise.gain": 0.1, "model.goal.speed": 0.2}]}
        r = swarmcl.sweep(SCENARIO, runs, tracks=real, context=ctx)
        assert r["rows"][0]["score"] == pytest.approx(1.0, abs=1e-12)  # the run the tracks came from
        _, _, _, other = alone(ctx, {"model.noise.gain": 0.1, "model.goal.speed": 0.2})
        with swarmcl.Metrics.from_frames(other, 0.02) as sim:
            e = swarmcl.distances(real, sim)
        assert r["rows"][1]["score"] == pytest.approx(swarmcl.score(e), abs=1e-12) and r["rows"][1]["score"] < 0.99


def test_a_model_without_worlds_runs_one_swarm_a_row(ctx):
    force = {"name": "f", "seed": 2, "dt": 0.01, "steps": 10, "domain": {"min": [-1, -1, -1], "max": [1, 1, 1]},
             "interaction_radius": 0.2, "agents": {"count": 20, "initial": {"type": "sphere", "center": [0, 0, 0],
                                                                             "radius": 0.5}},
             "model": {"type": "force", "w_att": 2.0, "eta": 0.2}}
    r = swarmcl.sweep(force, {"model.eta": [0.1, 0.8]}, context=ctx)
    assert not r["worlds"] and len(r["rows"]) == 2 and all(row["finite"] for row in r["rows"])
    assert r["rows"][0]["mean_speed"] != r["rows"][1]["mean_speed"]


def test_a_path_grid_over_goal_radii_runs_as_worlds_and_rows_are_the_runs_alone(ctx):
    # A path goal's radius is set per world by its own key (each world then
    # has its own cost field): the grid still runs as one swarm of worlds.
    path = json.loads(json.dumps(SCENARIO))
    path["model"] = {"type": "path", "noise": {"type": "curl", "scale": 0.5, "gain": 0.3, "seed": 1},
                     "grid": {"resolution": [10, 10, 10]}, "speed": 0.5, "goal_falloff": 0.5,
                     "goals": [{"type": "sphere", "center": [1, 1, 1.5], "radius": 0.3}], "min_distance": 0.05}
    grid = {"model.goals.0.radius": [0.1, 0.4], "model.speed": [0.3, 0.9]}
    r = swarmcl.sweep(path, grid, context=ctx)
    assert r["worlds"] and len(r["rows"]) == 4
    for row in r["rows"]:
        doc = json.loads(json.dumps(path))
        doc["model"]["goals"][0]["radius"], doc["model"]["speed"] = row["model.goals.0.radius"], row["model.speed"]
        with swarmcl.Scenario.parse(json.dumps(doc)).create_swarm(ctx) as s:
            s.step(30)
            assert row["mean_speed"] == float(np.linalg.norm(s.read_velocities(), axis=1).mean())
    assert len({row["mean_speed"] for row in r["rows"]}) == 4


def test_rows_the_model_refuses_together_run_in_swarms_of_their_own(ctx):
    # A noise time scale of 0 selects the static kernel: such a row cannot be
    # a world beside moving ones, so the rows are split into swarms the
    # model takes (0 | 1 | 2, 3), each row still the scenario alone.
    r = swarmcl.sweep(SCENARIO, {"model.noise.time_scale": [0.0, 1.0, 2.0, 3.0]}, context=ctx)
    assert r["worlds"] and r["swarms"] == 3 and len(r["rows"]) == 4
    for row in r["rows"]:
        vel, nn, stats, _ = alone(ctx, {"model.noise.time_scale": row["model.noise.time_scale"]})
        assert row["mean_speed"] == float(np.linalg.norm(vel, axis=1).mean())
        assert row["median_nearest_distance"] == float(np.median(nn))
        assert row["mde_moved_total"] == stats.mde_moved_total
    assert len({row["mean_speed"] for row in r["rows"]}) == 4


def test_seeds_are_replicates_run_as_worlds(ctx):
    # "seed" is each world's seed: replicates of a scenario (here beside a
    # model parameter) run as one swarm, each row the scenario alone with
    # that seed.
    r = swarmcl.sweep(SCENARIO, {"seed": [3, 8, 21], "model.goal.speed": [0.4, 0.9]}, context=ctx)
    assert r["worlds"] and r["swarms"] == 1 and len(r["rows"]) == 6
    for row in r["rows"]:
        assert isinstance(row["seed"], int)
        vel, nn, stats, _ = alone(ctx, {"seed": row["seed"], "model.goal.speed": row["model.goal.speed"]})
        assert row["mean_speed"] == float(np.linalg.norm(vel, axis=1).mean())
        assert row["median_nearest_distance"] == float(np.median(nn))
        assert row["mde_moved_total"] == stats.mde_moved_total
    assert len({row["mean_speed"] for row in r["rows"]}) == 6


def policy_scenario():
    from conftest import REPO, TOUR
    return {"name": "policy_tiny", "seed": 5, "dt": 0.1, "steps": 8,
            "domain": {"min": [-40, -40, -20], "max": [40, 40, 20]}, "interaction_radius": 18.5,
            "agents": {"count": 40, "velocity": [0.5, 0, 0],
                       "initial": {"type": "sphere", "center": [-8, 0, 0], "radius": 5}},
            "model": {"type": "policy", "weights": str(REPO / "models" / "policy_roaming.safetensors"),
                      "leader": {"mode": "tour", "speed": 0.6, "waypoints": [list(w) for w in TOUR]}},
            "output": {"dir": "results", "formats": ["npy"], "every": 5}}


def test_a_policy_grid_runs_as_worlds_and_its_leaders_keys_one_swarm_a_row(ctx):
    # The followers' parameters vary per world (one swarm for the grid, each
    # row the scenario alone); the leader's are one for every world in the
    # model's table, so a grid over them runs one swarm a row.
    policy = policy_scenario()
    grid = {"model.du_max": [0.05, 0.2], "model.body_radius": [0.3, 0.8]}
    r = swarmcl.sweep(policy, grid, context=ctx)
    assert r["worlds"] and r["swarms"] == 1 and len(r["rows"]) == 4
    for row in r["rows"]:
        doc = json.loads(json.dumps(policy))
        doc["model"]["du_max"], doc["model"]["body_radius"] = row["model.du_max"], row["model.body_radius"]
        with swarmcl.Scenario.parse(json.dumps(doc)).create_swarm(ctx) as s:
            s.step(8)
            assert row["mean_speed"] == float(np.linalg.norm(s.read_velocities(), axis=1).mean())
            assert row["median_nearest_distance"] == float(np.median(s.nearest_neighbor()[0]))
    assert len({row["mean_speed"] for row in r["rows"]}) == 4
    leader = swarmcl.sweep(policy, {"model.leader.speed": [0.3, 0.9]}, context=ctx)
    assert not leader["worlds"] and leader["swarms"] == 2
    assert leader["rows"][0]["mean_speed"] != leader["rows"][1]["mean_speed"]


@pytest.mark.parametrize("grid, says", [
    ({"model.noise.nope": [1, 2]}, "neither in the scenario nor a parameter of the field model"),
    ({"model.goal.speed": [0.5, -1.0]}, "leaves the parameter's valid range"),
    ({"model.goal.speed": []}, "non-empty list"),
    ({"model.goal.speed": [0.5, float("nan")]}, "not a finite number"),
    ({"runs": [{"model.goal.speed": 0.5}, {"model.noise.gain": 0.5}]}, "every run sets the same keys"),
    ({"model.noise.type": [0, 1]}, "not a number"),
    ({"seed": [1, -2]}, "integers in"),
    ({"seed": [1.5]}, "not an integer"),
    ({}, "expected"),
])
def test_bad_grids_are_refused(ctx, grid, says):
    with pytest.raises(ValueError, match=says):
        swarmcl.sweep(SCENARIO, grid, context=ctx)


def test_cli_writes_csv_and_nothing_on_error(tmp_path):
    (tmp_path / "s.json").write_text(json.dumps(SCENARIO))
    (tmp_path / "g.json").write_text(json.dumps(GRID))
    (tmp_path / "bad.json").write_text(json.dumps({"model.goal.speed": [-1.0]}))
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(swarmcl.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH", "")) if p))
    cmd = [sys.executable, "-m", "swarmcl", "sweep", "s.json", "--quiet"]
    p = subprocess.run(cmd + ["--grid", "g.json", "--out", "out.csv"], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert lines[0].startswith("model.noise.gain,model.goal.speed,finite,mean_speed") and len(lines) == 7
    p = subprocess.run(cmd + ["--grid", "bad.json", "--out", "bad.csv"], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 1 and "valid range" in p.stderr and not (tmp_path / "bad.csv").exists()


def test_two_mpi_ranks_give_the_same_rows(tmp_path, ctx):
    mpirun = shutil.which("mpirun")
    if mpirun is None or subprocess.run([sys.executable, "-c", "import mpi4py"]).returncode != 0:
        if os.environ.get("SWARMCL_REQUIRE_MPI") == "1":
            pytest.fail("mpirun or mpi4py missing but SWARMCL_REQUIRE_MPI=1 (scripts/test.sh installs them)")
        pytest.skip("no mpirun / mpi4py")
    (tmp_path / "s.json").write_text(json.dumps(SCENARIO))
    (tmp_path / "g.json").write_text(json.dumps(GRID))
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(swarmcl.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH", "")) if p),
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = [mpirun, "-np", "2", sys.executable, "-m", "swarmcl", "sweep", "s.json", "--grid", "g.json",
           "--out", "two.json", "--quiet"]
    p = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    two = json.loads((tmp_path / "two.json").read_text())
    one = swarmcl.sweep(SCENARIO, GRID, context=ctx)
    assert two["ranks"] == 2 and two["rows"] == one["rows"]

"""Parameter estimation (issue 14, Par-Est): ranges files, CMA-ES and the GA
through a batched population evaluator, determinism for a seed, recovery of
known parameters, and the same answer over 1 and 2 MPI ranks."""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import swarmcl

pytest.importorskip("cma")
pytest.importorskip("deap")

SCENARIO = {
    "name": "fit_tiny", "seed": 9, "dt": 0.02, "steps": 40,
    "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
    "agents": {"count": 16, "velocity": [0.1, 0, 0],
               "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
    "model": {"type": "field", "noise": {"type": "curl", "scale": 0.5, "gain": 0.2, "seed": 1, "domain_walls": True},
              "goal": {"center": [1, 1, 1.5], "speed": 0.5}, "min_distance": 0.02},
    "output": {"dir": "results", "formats": ["npy"], "every": 5},
}
RANGES = {"model.noise.gain": [0.05, 1.0], "model.goal.speed": [0.1, 1.5]}


def frames_of(ctx, scenario, steps):
    with swarmcl.Scenario.parse(json.dumps(scenario)).create_swarm(ctx) as s:
        frames = [s.read_positions()]
        for _ in range(steps):
            s.step(1)
            frames.append(s.read_positions())
    return np.stack(frames)


@pytest.fixture(scope="module")
def truth():
    t = json.loads(json.dumps(SCENARIO))
    t["model"]["noise"]["gain"], t["model"]["goal"]["speed"] = 0.6, 0.9
    return t


@pytest.fixture(scope="module")
def real(truth):
    with swarmcl.Context() as c:
        frames = frames_of(c, truth, 40)
    m = swarmcl.Metrics.from_frames(frames, 0.02)
    yield m
    m.close()


def test_ranges_are_checked_against_the_scenario():
    params = swarmcl.load_ranges({"model.noise.gain": [0, 1], "agents.count": [4, 20]}, SCENARIO)
    assert [p.integer for p in params] == [False, True]
    assert params[1].value(0.45) == 11  # 4 + 0.45 * 16 = 11.2, rounded
    for bad, msg in (({"model.noise.nope": [0, 1]}, "neither in the scenario nor a parameter of the field model"),
                     ({"agents.nope": [0, 1]}, "no field 'nope'"), ({"model.noise.type": [0, 1]}, "not a number"),
                     ({"model.noise.gain": [1, 0]}, "low < high"), ({"model.noise.gain": [0]}, r"\[low, high\]"),
                     ({"model.noise.domain_walls": [0, 1]}, "not a number"), ({}, "at least one")):
        with pytest.raises(ValueError, match=msg):
            swarmcl.load_ranges(bad, SCENARIO)


def test_the_true_parameters_score_one_and_the_population_is_scored_together(ctx, real, truth):
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    ev = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False)
    u_true = [(0.6 - 0.05) / 0.95, (0.9 - 0.1) / 1.4]
    scores = ev([u_true, [0.0, 0.0], [1.0, 1.0]])
    assert scores[0] == pytest.approx(1.0, abs=1e-12)  # the same run as the "real" data (host path: exact)
    assert scores[1] < 0.9 and scores[2] < 0.9
    assert ev([[0.0, 0.0]]) == [scores[1]]  # alone or in a population: the same score
    assert ev.evaluations == 4
    # Streamed on the device (the default): the same ranking, the true
    # parameters within the fine histograms' error of 1 (their PDFs spread
    # each fine bin over its z-range: with 600 samples per metric a few
    # hundredths of E_phi, docs/evaluation.md).
    streamed = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=True)
    s2 = streamed([u_true, [0.0, 0.0], [1.0, 1.0]])
    assert s2[0] == pytest.approx(1.0, abs=0.05)
    assert s2[0] > max(s2[1:]) and s2 == streamed([u_true, [0.0, 0.0], [1.0, 1.0]])


def test_a_generation_as_worlds_scores_as_its_runs_alone(ctx, real):
    # The default evaluator runs a field-model generation as the worlds of
    # one swarm (issue 25) with each world's metrics on the device: every
    # score equals the one of the same run as a swarm of its own, over
    # several seeds too; and so with the metrics measured on the host.
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    worlds = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, seeds=2, streamed=True)
    alone = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, seeds=2, worlds=False)
    assert worlds.world_keys == ["noise.gain", "goal.speed"] and alone.world_keys is None
    assert worlds.streamed and alone.streamed
    # The default measures worlds on the host on a CPU device (faster there),
    # on the device elsewhere.
    default = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40)
    assert default.streamed == (ctx.device.type != swarmcl.DeviceType.CPU)
    pop = [list(u) for u in np.random.default_rng(3).uniform(size=(5, 2))]
    a, b = worlds(pop), alone(pop)
    assert a == b and len(set(a)) == 5
    host_worlds = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, seeds=2,
                                                      streamed=False)
    host_alone = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, seeds=2,
                                                     streamed=False, worlds=False)
    assert host_worlds.world_keys is not None
    c, d = host_worlds(pop), host_alone(pop)
    assert c == d and len(set(c)) == 5
    # The device's fine histograms are close to the exact PDFs, not equal.
    assert c != a and np.allclose(a, c, atol=0.05)
    # A domain corner fitted: still worlds, each in its own domain, every
    # score its run's alone.
    ranges = dict(RANGES, **{"domain.max.0": [1.55, 1.9]})
    params = swarmcl.load_ranges(ranges, SCENARIO)
    boxed = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False)
    boxed_alone = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False,
                                                      worlds=False)
    assert boxed.world_keys == ["noise.gain", "goal.speed"]
    pop3 = [list(u) for u in np.random.default_rng(4).uniform(size=(4, 3))]
    e, f = boxed(pop3), boxed_alone(pop3)
    assert e == f and boxed.last_swarms == 1
    assert e != boxed([u[:2] + [0.5] for u in pop3])  # the domain matters
    # A parameter outside the table (agents.count) keeps one swarm a run.
    other = swarmcl.fitting.PopulationEvaluator(
        SCENARIO, swarmcl.load_ranges({"agents.count": [8, 20]}, SCENARIO), real, ctx, steps=40)
    assert other.world_keys is None


def test_a_force_model_generation_as_worlds_scores_as_its_runs_alone(ctx, real):
    # The force model runs worlds too (its internal forces, curl noise and
    # MDE): a generation varying r_rep and w_ali scores as its runs alone,
    # with target meshes too (each world assigns its own insects).
    force = json.loads(json.dumps(SCENARIO))
    force["model"] = {"type": "force", "r_rep": 0.1, "r_ali": 0.3, "r_att": 0.6, "max_speed": 0.5,
                      "cruise_speed": 0.2, "min_distance": 0.02}
    params = swarmcl.load_ranges({"model.r_rep": [0.05, 0.2], "model.w_ali": [0.5, 3.0]}, force)
    worlds = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, seeds=2, streamed=True)
    alone = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, seeds=2, worlds=False)
    assert worlds.world_keys == ["r_rep", "w_ali"] and alone.world_keys is None
    pop = [list(u) for u in np.random.default_rng(5).uniform(size=(4, 2))]
    a, b = worlds(pop), alone(pop)
    assert a == b and len(set(a)) == 4
    shaped = json.loads(json.dumps(force))
    shaped["model"]["keyframes"] = [{"frame": 0, "shape": "sphere", "scale": 0.5, "offset": [1, 1, 1]}]
    worlds = swarmcl.fitting.PopulationEvaluator(shaped, params, real, ctx, steps=40, streamed=False)
    alone = swarmcl.fitting.PopulationEvaluator(shaped, params, real, ctx, steps=40, streamed=False, worlds=False)
    c, d = worlds(pop), alone(pop)
    assert worlds.world_keys == ["r_rep", "w_ali"] and worlds.last_swarms == 1
    assert c == d and len(set(c)) == 4 and c != a[:4]
    # The scenario's eta and rho (Eq. 4: noise.scale = rho, noise.gain =
    # eta / rho) run as worlds too, each fitted or not, bitwise as alone.
    force["model"].update(eta=0.3, rho=0.25, noise_time_scale=1.0)
    for ranges, keys in (({"model.eta": [0.0, 1.0], "model.rho": [0.1, 0.6]}, ["noise.scale", "noise.gain"]),
                         ({"model.rho": [0.1, 0.6], "model.noise_time_scale": [0.5, 2.0]},
                          ["noise.time_scale", "noise.scale", "noise.gain"])):
        params = swarmcl.load_ranges(ranges, force)
        worlds = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, streamed=False)
        alone = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, streamed=False, worlds=False)
        assert worlds.world_keys == keys
        a, b = worlds(pop), alone(pop)
        assert a == b and len(set(a)) == 4
    # eta fitted while the scenario leaves rho to its default: one swarm a run.
    del force["model"]["rho"]
    params = swarmcl.load_ranges({"model.eta": [0.0, 1.0]}, force)
    assert swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40).world_keys is None


def test_a_force_generation_with_kernel_selecting_or_refused_values_still_runs_as_worlds(ctx, real):
    # The studies' force scenarios start from noise_time_scale 0 (the static
    # curl kernel) and fit it in [0, 5]: a generation is then made from its
    # first individual's values, so it still runs as worlds; individuals the
    # model refuses (cruise_speed above max_speed) are refused, and the
    # rest still run as one swarm.
    force = json.loads(json.dumps(SCENARIO))
    force["model"] = {"type": "force", "r_rep": 0.1, "r_ali": 0.3, "r_att": 0.6, "max_speed": 0.5,
                      "cruise_speed": 0.2, "eta": 0.3, "rho": 0.25, "noise_type": "curl",
                      "noise_time_scale": 0.0}
    params = swarmcl.load_ranges({"model.noise_time_scale": [0.0, 5.0], "model.max_speed": [0.3, 2.0],
                                  "model.cruise_speed": [0.0, 0.8]}, force)
    worlds = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, streamed=False)
    alone = swarmcl.fitting.PopulationEvaluator(force, params, real, ctx, steps=40, streamed=False, worlds=False)
    pop = [[0.2, 0.5, 0.3], [0.6, 0.9, 0.1], [0.9, 0.2, 0.5], [0.4, 0.6, 0.6], [0.7, 0.4, 0.2], [0.3, 0.8, 0.4]]
    a = worlds(pop)
    assert worlds.last_swarms == 1 and worlds.refused == 0
    assert a == alone(pop) and len(set(a)) == 6
    # Individual 2 asks cruise_speed 0.8 above max_speed 0.3: refused alone and
    # as a world; the other five keep their scores from the worlds.
    bad = [list(u) for u in pop]
    bad[2] = [0.9, 0.0, 1.0]
    b, c = worlds(bad), alone(bad)
    assert b == c and b[2] == swarmcl.fitting.REFUSED_SCORE and worlds.refused == 1
    assert [x for i, x in enumerate(b) if i != 2] == [x for i, x in enumerate(a) if i != 2]
    assert worlds.last_swarms == 1 and alone.last_swarms == 5
    # One individual at time scale 0 (the static kernel) among moving ones:
    # the generation is split into groups of one kernel each, same scores.
    mixed = [list(u) for u in pop]
    mixed[3][0] = 0.0
    d = worlds(mixed)
    assert d == alone(mixed) and 1 < worlds.last_swarms < 6
    assert [x for i, x in enumerate(d) if i != 3] == [x for i, x in enumerate(a) if i != 3]


def test_an_energy_model_generation_as_worlds_scores_as_its_runs_alone(ctx, real):
    # The energy model runs worlds too (issue 25): a generation varying the
    # weights of examples/evaluation/energy_mosquito.ranges.json scores as
    # its runs alone, streamed or measured on the host, with the fixed centre
    # of that scenario, with the swarm's own centre (each world's) and with
    # keypoints (each world's agents keep their goals).
    energy = json.loads(json.dumps(SCENARIO))
    energy["dt"] = 0.01
    energy["model"] = {"type": "energy", "dataset": {"type": "synthetic", "k": 120, "groups": 6},
                       "weights": {"rep": 1, "oa": 1, "cos": 0.05, "dir": 1, "acc": 1, "env": 0, "n": 0.2,
                                   "user": 0},
                       "centre": [1, 1, 1]}
    ranges = {"model.weights.rep": [0.0, 3.0], "model.weights.cos": [0.0, 1.0], "model.weights.dir": [0.0, 3.0],
              "model.weights.acc": [0.0, 3.0], "model.weights.n": [0.0, 2.0]}
    pop = [list(u) for u in np.random.default_rng(7).uniform(size=(4, len(ranges)))]
    swarm_centre = json.loads(json.dumps(energy))
    del swarm_centre["model"]["centre"]
    shaped = json.loads(json.dumps(energy))
    shaped["model"]["keypoints"] = [[0.5, 0.5, 1], [1.5, 1.5, 1]]
    shaped["model"]["weights"]["user"] = 1.0
    for scenario in (energy, swarm_centre, shaped):
        params = swarmcl.load_ranges(ranges, scenario)
        for streamed in (False, True):
            worlds = swarmcl.fitting.PopulationEvaluator(scenario, params, real, ctx, steps=40, seeds=2,
                                                         streamed=streamed)
            alone = swarmcl.fitting.PopulationEvaluator(scenario, params, real, ctx, steps=40, seeds=2,
                                                        streamed=streamed, worlds=False)
            assert worlds.world_keys == ["weights.rep", "weights.cos", "weights.dir", "weights.acc", "weights.n"]
            assert alone.world_keys is None
            a, b = worlds(pop), alone(pop)
            assert a == b and len(set(a)) == 4
            assert worlds.refused == 0 and worlds.last_swarms == 1


def test_a_path_model_generation_as_worlds_scores_as_its_runs_alone(ctx, real):
    # The path model runs worlds too (issue 25): a generation varying the
    # keys of examples/evaluation/path_mosquito.ranges.json (the noise, s0,
    # the goal ramp and the goal's radius, which gives each world its own
    # cost field) scores as its runs alone, streamed or measured on the
    # host; so does one that chases a target (one swarm a run only with a
    # baked noise).
    path = json.loads(json.dumps(SCENARIO))
    path["model"] = {"type": "path", "noise": {"type": "curl", "scale": 0.4, "gain": 0.5, "seed": 2,
                                               "boundary_distance": 0.3, "domain_walls": True},
                     "grid": {"resolution": [12, 12, 12]}, "speed": 0.5, "goal_falloff": 1.0,
                     "goals": [{"type": "sphere", "center": [1, 1, 1], "radius": 0.3}], "min_distance": 0.02}
    ranges = {"model.noise.scale": [0.05, 1.0], "model.noise.gain": [0.05, 2.0], "model.speed": [0.05, 2.0],
              "model.goals.0.radius": [0.05, 1.0], "model.goal_falloff": [0.1, 3.0]}
    params = swarmcl.load_ranges(ranges, path)
    pop = [list(u) for u in np.random.default_rng(11).uniform(size=(5, len(ranges)))]
    for streamed in (False, True):
        worlds = swarmcl.fitting.PopulationEvaluator(path, params, real, ctx, steps=40, seeds=2, streamed=streamed)
        alone = swarmcl.fitting.PopulationEvaluator(path, params, real, ctx, steps=40, seeds=2, streamed=streamed,
                                                    worlds=False)
        assert worlds.world_keys == ["noise.scale", "noise.gain", "speed", "goals.0.radius", "goal_falloff"]
        a, b = worlds(pop), alone(pop)
        assert worlds.last_swarms == 1 and alone.last_swarms == 10
        assert a == b and len(set(a)) == 5 and worlds.refused == 0
    # A chasing target runs as worlds too; with a baked noise, one swarm a run.
    chasing = json.loads(json.dumps(path))
    chasing["model"]["targets"] = [{"center": [1.2, 1, 1], "radius": 0.1}]
    worlds = swarmcl.fitting.PopulationEvaluator(chasing, params, real, ctx, steps=40, streamed=False)
    alone = swarmcl.fitting.PopulationEvaluator(chasing, params, real, ctx, steps=40, worlds=False, streamed=False)
    assert worlds.world_keys is not None and worlds(pop) == alone(pop) and worlds.last_swarms == 1
    chasing["model"]["noise"]["baked"] = True
    assert swarmcl.fitting.PopulationEvaluator(chasing, swarmcl.load_ranges(ranges, chasing), real, ctx,
                                               steps=40).world_keys is None


def test_a_policy_model_generation_as_worlds_scores_as_its_runs_alone(ctx, real):
    # The policy model runs worlds too: a generation varying the followers'
    # parameters is one swarm and scores as its runs alone; a range over the
    # leader's parameters (one for every world in the table) runs one swarm
    # a run.
    from conftest import REPO, TOUR
    policy = {"name": "policy_fit", "seed": 3, "dt": 0.1, "steps": 40,
              "domain": {"min": [-40, -40, -20], "max": [40, 40, 20]}, "interaction_radius": 18.5,
              "agents": {"count": 16, "velocity": [0.5, 0, 0],
                         "initial": {"type": "sphere", "center": [-4, 0, 0], "radius": 3}},
              "model": {"type": "policy", "weights": str(REPO / "models" / "policy_roaming.safetensors"),
                        "leader": {"mode": "tour", "speed": 0.6, "waypoints": [list(w) for w in TOUR]}}}
    ranges = {"model.du_max": [0.02, 0.3], "model.dq_max_deg": [1.0, 10.0], "model.body_radius": [0.2, 1.0]}
    params = swarmcl.load_ranges(ranges, policy)
    pop = [list(u) for u in np.random.default_rng(5).uniform(size=(4, len(ranges)))]
    for streamed in (False, True):
        worlds = swarmcl.fitting.PopulationEvaluator(policy, params, real, ctx, steps=20, seeds=2, streamed=streamed)
        alone = swarmcl.fitting.PopulationEvaluator(policy, params, real, ctx, steps=20, seeds=2, streamed=streamed,
                                                    worlds=False)
        assert worlds.world_keys == ["du_max", "dq_max_deg", "body_radius"]
        a, b = worlds(pop), alone(pop)
        assert worlds.last_swarms == 1 and alone.last_swarms == 8
        assert a == b and len(set(a)) == 4 and worlds.refused == 0
    leader = swarmcl.load_ranges({"model.leader.speed": [0.2, 1.0]}, policy)
    assert swarmcl.fitting.PopulationEvaluator(policy, leader, real, ctx, steps=20).world_keys is None


def test_the_scale_penalty_is_the_mean_wasserstein_distance_in_real_spreads(ctx, real, truth):
    # Host path (exact): the penalised score is E - λ P, P recomputed here
    # from the same run's frames; the true parameters are 0 away, a slower
    # goal speed is not, and the robust option keeps E 1 for the true run.
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    plain = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False)
    pen = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False,
                                              scale_penalty=2.0, robust=True)
    u_true, u_slow = [(0.6 - 0.05) / 0.95, (0.9 - 0.1) / 1.4], [(0.6 - 0.05) / 0.95, 0.0]
    e_plain, e_pen = plain([u_true, u_slow]), pen([u_true, u_slow])
    # u maps back to 0.6 and 0.9 within a double's rounding, so the run may
    # differ from the "real" one in the last float bits: W1 sees ~1e-8 where
    # the binned PDFs see nothing.
    assert e_pen[0] == pytest.approx(1.0, abs=1e-6)
    slow = json.loads(json.dumps(SCENARIO))
    slow["model"]["noise"]["gain"], slow["model"]["goal"]["speed"] = 0.6, 0.1
    with swarmcl.Metrics.from_frames(frames_of(ctx, slow, 40), 0.02) as sim:
        w = swarmcl.wasserstein(real, sim)
        spread = [1.4826 * real.info(k)["mad"] for k in range(7)]
        p = np.mean([w[n] / spread[k] for k, n in enumerate(swarmcl.METRICS) if w[n] is not None and spread[k] > 0])
        e_robust = swarmcl.score(swarmcl.distances(real, sim, robust=True))
    assert p > 0.1
    assert e_pen[1] == pytest.approx(e_robust - 2.0 * p, abs=1e-6)  # the same last-bits caveat
    assert e_plain[1] != pytest.approx(e_pen[1])
    with pytest.raises(ValueError, match="scale_penalty"):
        swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, scale_penalty=-1.0)
    # P over chosen metrics only (scale_metrics): speed and spacing.
    two = ("speed", "nearest_distance")
    sel = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False,
                                              scale_penalty=2.0, robust=True, scale_metrics=two)
    p_two = np.mean([w[n] / spread[swarmcl.METRICS.index(n)] for n in two])
    assert p_two != pytest.approx(p)
    assert sel([u_slow])[0] == pytest.approx(e_robust - 2.0 * p_two, abs=1e-6)
    for bad in (["speed", "nope"], [], ["speed", "speed"]):
        with pytest.raises(ValueError, match="scale_metrics"):
            swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, scale_penalty=1.0, scale_metrics=bad)


def test_a_fit_recovers_known_parameters(ctx, real):
    # The "real" tracks are the scenario run with gain 0.6, goal speed 0.9
    # (truth): CMA-ES from the scenario's 0.2 and 0.5 finds both within 10 %
    # (3 % measured: 0.619, 0.927, 161 runs, 14 s on the 2-core machine).
    r = swarmcl.fit(SCENARIO, real, RANGES, method="cmaes", generations=20, population=8, seed=1, steps=40,
                    context=ctx, tolerance=1e-4)
    assert r["best"]["model.noise.gain"] == pytest.approx(0.6, rel=0.10)
    assert r["best"]["model.goal.speed"] == pytest.approx(0.9, rel=0.10)


def test_the_history_is_plotted_with_whether_it_converged(tmp_path, ctx, real):
    pytest.importorskip("matplotlib")
    r = swarmcl.fit(SCENARIO, real, RANGES, method="ga", generations=2, population=4, seed=1, steps=40, context=ctx)
    swarmcl.fitting.plot_history(r, tmp_path / "fit.png")
    assert (tmp_path / "fit.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_nested_model_fitted_from_the_smaller_ones_best_scores_no_lower(ctx, real):
    # The smaller model fits the gain alone (the goal speed stays 0.5); the
    # nested one fits both, started from the smaller one's best: it can only
    # gain (its start is scored first).
    small = swarmcl.fit(SCENARIO, real, {"model.noise.gain": [0.05, 1.0]}, method="ga", generations=3,
                        population=6, seed=4, steps=40, context=ctx)
    nested = swarmcl.fit(SCENARIO, real, RANGES, method="cmaes", generations=3, population=6, seed=4, steps=40,
                         context=ctx, start={"model.noise.gain": small["best"]["model.noise.gain"],
                                             "model.goal.speed": 0.5})
    assert nested["history"][0]["generation"] == 0
    assert nested["history"][0]["best"] == small["best_score"]  # the same run, scored the same
    assert nested["best_score"] >= small["best_score"]
    for bad, msg in (({"model.noise.gain": 5.0}, "outside its range"), ({"model.nope": 1.0}, "not among")):
        with pytest.raises(ValueError, match=msg):
            swarmcl.fit(SCENARIO, real, RANGES, context=ctx, start=bad, generations=1, population=4)


def test_several_seeds_score_the_mean_of_their_runs(ctx, real):
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    u = [0.3, 0.7]
    two = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, streamed=False, seeds=2)
    one = [swarmcl.fitting.PopulationEvaluator(dict(SCENARIO, seed=s), params, real, ctx, steps=40,
                                               streamed=False)([u])[0] for s in (9, 10)]
    assert one[0] != one[1]  # the placement seed matters
    assert two([u]) == [pytest.approx(np.mean(one), abs=1e-12)]
    assert two.evaluations == 1
    with pytest.raises(ValueError, match="seeds"):
        swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, seeds=0)


def test_pooled_seeds_score_their_runs_samples_together(ctx, real):
    # pool=True: an individual's runs are one sample set (Metrics.merge of
    # each run's frames), scored once; the same as worlds, alone, on the
    # host and (close) on the device; a refused individual still scores low.
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    pop = [[0.3, 0.7], [0.8, 0.1], [0.5, 0.5]]
    expected = []
    for u in pop:
        scn = swarmcl.fitting._with_values(SCENARIO, params, u)
        parts = [swarmcl.Metrics.from_frames(frames_of(ctx, dict(scn, seed=s), 40), 0.02) for s in (9, 10, 11)]
        with swarmcl.Metrics.merge(parts) as sim:
            expected.append(swarmcl.score(swarmcl.distances(real, sim)))
            expected_terms = swarmcl.distances(real, sim)
            assert sim.info("speed")["count"] == sum(p.info("speed")["count"] for p in parts)
        for p in parts:
            p.close()
    kw = dict(steps=40, seeds=3, pool=True)
    hosted = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, streamed=False, **kw)
    alone = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, streamed=False, worlds=False, **kw)
    device = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, streamed=True, **kw)
    a, b, c = hosted(pop), alone(pop), device(pop)
    assert a == pytest.approx(expected, abs=1e-12) and b == a
    # terms() of a scenario pools its runs the same way (the last individual's).
    assert np.array_equal(hosted.terms(scn), expected_terms)
    assert np.allclose(c, a, atol=0.05)
    mean = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, streamed=False, steps=40, seeds=3)
    assert mean(pop) != a  # the mean of three scores is another estimate
    params = [swarmcl.Parameter("model.noise.gain", 0.05, 1.0), swarmcl.Parameter("model.min_distance", -1.0, 0.5)]
    bad = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, streamed=False, **kw)
    refused, fine = bad([[0.5, 0.1], [0.5, 0.9]])  # min_distance -0.85 (refused) and 0.35
    assert refused == swarmcl.fitting.REFUSED_SCORE and fine > swarmcl.fitting.REFUSED_SCORE
    assert bad.refused == 3  # its three runs, as without pooling
    with pytest.raises(TypeError, match="merge"):
        swarmcl.Metrics.merge([])


def test_a_reseeded_fit_runs_each_generation_on_seeds_of_its_own(ctx, real, monkeypatch):
    # reseed=True: generation g's runs start from the scenario's seed + g * S
    # (common random numbers within a generation, none shared across them),
    # the result is CMA-ES's final mean scored on the scenario's own seeds.
    seen = []
    call = swarmcl.fitting.PopulationEvaluator.__call__

    def spy(self, population, base_seed=None):
        seen.append((len(population), base_seed))
        return call(self, population, base_seed)
    monkeypatch.setattr(swarmcl.fitting.PopulationEvaluator, "__call__", spy)
    kw = dict(method="cmaes", generations=4, population=6, seed=3, steps=40, context=ctx, seeds=2, pool=True,
              tolerance=0.0, step_tolerance=1e-9)
    r = swarmcl.fit(SCENARIO, real, RANGES, reseed=True, **kw)
    generations = [b for n, b in seen[:-1]]
    assert generations == [9 + 2 * g for g in range(1, len(generations) + 1)]
    assert seen[-1] == (1, 9)  # the final mean, on the scenario's seeds
    assert r["reseed"] and r["scenario"]["seed"] == 9
    monkeypatch.setattr(swarmcl.fitting.PopulationEvaluator, "__call__", call)
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    again = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40, seeds=2, pool=True)
    u = [(r["best"][p.path] - p.low) / (p.high - p.low) for p in params]
    assert again([u]) == [pytest.approx(r["best_score"], abs=1e-12)]
    # Deterministic for a seed; without reseed every generation is on seeds 9, 10.
    a = swarmcl.fit(SCENARIO, real, RANGES, reseed=True, **kw)
    assert a["best"] == r["best"] and a["best_score"] == r["best_score"]
    fixed = swarmcl.fit(SCENARIO, real, RANGES, **kw)
    assert not fixed["reseed"] and fixed["best"] != r["best"]
    for bad in (dict(method="ga"), dict(restarts=1)):
        with pytest.raises(ValueError, match="reseed"):
            swarmcl.fit(SCENARIO, real, RANGES, reseed=True, context=ctx, **bad)


def test_searches_stop_on_tolerance_and_say_so(ctx, real):
    # A tolerance no gain can pass: the GA stops after `patience` stalled
    # generations, CMA-ES on its own tolerance, both before the budget.
    kw = dict(generations=30, population=6, seed=2, steps=40, context=ctx, tolerance=10.0)
    ga = swarmcl.fit(SCENARIO, real, RANGES, method="ga", patience=2, **kw)
    assert ga["converged"] and len(ga["history"]) == 2 and "no gain" in ga["stop"][0]
    # Copies keep their score: fewer evaluations than scored slots.
    assert ga["evaluations"] == 6 + sum(h["individuals"] for h in ga["history"])
    es = swarmcl.fit(SCENARIO, real, RANGES, method="cmaes", restarts=1, **kw)
    assert es["converged"] and any(k.startswith("tol") for k in es["stop"])
    assert len(es["history"]) < 30
    budget = swarmcl.fit(SCENARIO, real, RANGES, method="ga", generations=2, population=6, seed=2, steps=40,
                         context=ctx, tolerance=0.0, patience=5)
    assert not budget["converged"] and budget["stop"] == ["generations"]
    with pytest.raises(ValueError, match="restarts"):
        swarmcl.fit(SCENARIO, real, RANGES, restarts=-1, context=ctx)
    # The step tolerance alone (scores may still differ): CMA-ES stops once
    # its steps are below that fraction of every range, and says "tolx".
    steps = swarmcl.fit(SCENARIO, real, RANGES, method="cmaes", generations=60, population=6, seed=2, steps=40,
                        context=ctx, tolerance=0.0, step_tolerance=0.2)
    assert steps["converged"] and "tolx" in steps["stop"] and len(steps["history"]) < 60
    assert steps["step_tolerance"] == 0.2
    for bad in (0.0, 1.0, float("nan")):
        with pytest.raises(ValueError, match="step_tolerance"):
            swarmcl.fit(SCENARIO, real, RANGES, step_tolerance=bad, context=ctx)
    # With patience, CMA-ES also stops when its best gains no more than the
    # tolerance in that many generations (a rough score may never let cma's
    # own tolerances trigger): here its best is -0.212 from its fourth generation on.
    stall = swarmcl.fit(SCENARIO, real, RANGES, method="cmaes", generations=60, population=6, seed=2, steps=40,
                        context=ctx, tolerance=0.05, step_tolerance=1e-9, patience=3)
    assert stall["converged"] and stall["patience"] == 3
    assert stall["stop"] == ["no gain above 0.05 in 3 generations"] and len(stall["history"]) == 8
    with pytest.raises(ValueError, match="patience and restarts"):
        swarmcl.fit(SCENARIO, real, RANGES, patience=3, restarts=1, context=ctx)
    with pytest.raises(ValueError, match="patience"):
        swarmcl.fit(SCENARIO, real, RANGES, patience=0, context=ctx)


@pytest.mark.parametrize("method", ["cmaes", "ga"])
def test_fit_is_deterministic_for_a_seed_and_improves(ctx, real, method):
    kw = dict(method=method, generations=4, population=6, seed=3, steps=40, context=ctx)
    a = swarmcl.fit(SCENARIO, real, RANGES, **kw)
    b = swarmcl.fit(SCENARIO, real, RANGES, **kw)
    for r in (a, b):
        r.pop("seconds")
    assert a == b
    assert set(a["best"]) == set(RANGES)
    # "Improves": the fit scores above the scenario's own starting values
    # (gain 0.2, speed 0.5; the truth is 0.6, 0.9) scored the same way, and
    # above the first generation's mean.  (best_so_far >= the first best
    # could not fail: it is a running maximum from that value.)
    params = swarmcl.load_ranges(RANGES, SCENARIO)
    ev = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40)
    start = [(0.2 - 0.05) / 0.95, (0.5 - 0.1) / 1.4]
    start_score = ev([start])[0]
    assert a["best_score"] > start_score
    assert a["best_score"] > a["history"][0]["mean"]
    assert a["scenario"]["model"]["noise"]["gain"] == a["best"]["model.noise.gain"]
    with pytest.raises(ValueError, match="method"):
        swarmcl.fit(SCENARIO, real, RANGES, method="annealing", context=ctx)
    with pytest.raises(ValueError, match="two parameters"):
        swarmcl.fit(SCENARIO, real, {"model.noise.gain": [0, 1]}, method="cmaes", context=ctx)


def test_the_same_answer_over_one_and_two_mpi_ranks(tmp_path, truth):
    mpirun = shutil.which("mpirun")
    if mpirun is None or subprocess.run([sys.executable, "-c", "import mpi4py"]).returncode != 0:
        if os.environ.get("SWARMCL_REQUIRE_MPI") == "1":
            pytest.fail("mpirun or mpi4py missing but SWARMCL_REQUIRE_MPI=1 (scripts/test.sh installs them)")
        pytest.skip("no mpirun / mpi4py")
    # Tracks as CSV, from the "true" run.
    with swarmcl.Context() as c:
        frames = frames_of(c, truth, 40)
    rows = ["id,time,x,y,z"] + [f"{i},{f * 0.02:.4f},{p[0]!r},{p[1]!r},{p[2]!r}"
                                for f in range(frames.shape[0]) for i, p in enumerate(frames[f].tolist())]
    (tmp_path / "tracks.csv").write_text("\n".join(rows) + "\n")
    (tmp_path / "scenario.json").write_text(json.dumps(SCENARIO))
    (tmp_path / "ranges.json").write_text(json.dumps(RANGES))
    # The ranks import the same swarmcl as this test (installed or from the source tree).
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(swarmcl.__file__)))
    path = os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH", "")) if p)
    env = dict(os.environ, PYTHONPATH=path, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    # `swarmcl fit` (the C++ program, which hands over to Python) when
    # scripts/test.sh names it; python -m swarmcl fit in any case.
    cli = os.environ.get("SWARMCL_CLI")
    runs = [(1, [sys.executable, "-m", "swarmcl"]), (2, [sys.executable, "-m", "swarmcl"])]
    if cli:
        env["SWARMCL_PYTHON"] = sys.executable
        runs.append((2, [cli]))
    results = []
    for n, (ranks, program) in enumerate(runs):
        out = tmp_path / f"fit{n}.json"
        cmd = [mpirun, "-np", str(ranks), *program, "fit", "scenario.json",
               "--tracks", "tracks.csv", "--ranges", "ranges.json", "--generations", "3", "--population", "5",
               "--seed", "7", "--steps", "40", "--seeds", "2", "--pool", "--out", str(out), "--quiet"]
        p = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stdout + p.stderr
        r = json.loads(out.read_text())
        assert r["ranks"] == ranks and r["seeds"] == 2 and r["pool"] is True
        for k in ("seconds", "ranks", "refused_on_rank0", "evaluations"):
            r.pop(k)
        results.append(r)
    assert all(r == results[0] for r in results[1:])


class _TwoRanks:
    """A stand-in for a 2-rank communicator: this process is rank `rank`;
    the other rank's gathered part and broadcast commands are given."""

    def __init__(self, rank, other_part=None, commands=()):
        self.rank, self.other_part, self.commands, self.gathered = rank, other_part, list(commands), []

    def Get_rank(self):
        return self.rank

    def Get_size(self):
        return 2

    def bcast(self, obj, root=0):
        return obj if self.rank == 0 else self.commands.pop(0)

    def gather(self, obj, root=0):
        self.gathered.append(obj)
        return [obj, self.other_part] if self.rank == 0 else None


def test_a_rank_that_fails_in_a_generation_fails_the_generation_with_its_message():
    # Rank 0 raises the serving rank's error, naming it, instead of returning
    # a generation with scores missing; a serving rank sends its error and
    # keeps serving until stopped.
    from swarmcl.fitting import _RankError, _Ranks
    ranks = _Ranks(lambda pop: [1.0] * len(pop), _TwoRanks(0, _RankError(1, "SwarmclError: out of memory")))
    with pytest.raises(RuntimeError, match="rank 1 failed in a generation: SwarmclError: out of memory"):
        ranks.map([[0.1], [0.2], [0.3]])
    assert _Ranks(lambda pop: [1.0] * len(pop), _TwoRanks(0, [2.0])).map([[0.1], [0.2]]) == [1.0, 2.0]

    def boom(pop):
        raise MemoryError("no room")
    comm = _TwoRanks(1, commands=[("evaluate", [[0.1], [0.2]], None), ("stop", None, None)])
    _Ranks(boom, comm).serve()
    assert len(comm.gathered) == 1 and isinstance(comm.gathered[0], _RankError)
    assert comm.gathered[0].rank == 1 and comm.gathered[0].message == "MemoryError: no room"


def test_compare_iterates_entropy_weights_over_models(ctx, real):
    # Three "models": the field model with its noise gain fitted, with its
    # goal pull fitted, with its noise scale fitted; Steps 1-5 of §3.3.  (With
    # two models Eq. 4 always gives equal weights: each non-constant column
    # normalises to {0, 1}, whose entropy is 0.)
    models = {"gain": (SCENARIO, {"model.noise.gain": [0.05, 1.0]}),
              "pull": (SCENARIO, {"model.goal.speed": [0.1, 1.5]}),
              "scale": (SCENARIO, {"model.noise.scale": [0.2, 1.0]})}
    r = swarmcl.fitting.compare(models, real, max_iterations=2, tolerance=1e-9, context=ctx, method="ga",
                                generations=2, population=4, seed=2, steps=40)
    assert len(r["iterations"]) == 2  # the tolerance is never met: stops at the maximum
    w = np.array(r["weights"])
    assert w.shape == (7,) and abs(w.sum() - 1) < 1e-12 and np.all(w >= 0)
    assert set(r["ranking"]) == {"gain", "pull", "scale"}
    assert np.ptp(w) > 0  # three models: the terms are weighted unequally
    for name, m in r["models"].items():
        terms = np.array([m["terms"][k] for k in swarmcl.METRICS])
        assert m["score"] == pytest.approx(swarmcl.score(terms, r["weights"], r["p1"], r["p2"]))
    with pytest.raises(ValueError, match="two models"):
        swarmcl.fitting.compare({"one": models["gain"]}, real, context=ctx)


def test_refused_and_blown_up_individuals_score_low_never_nan(ctx, real):
    # A negative MDE distance is refused by the scenario reader; frames that
    # blew up (NaN) make non-finite metrics: both score -1e6.
    # load_ranges refuses such a range up front (the field model's table:
    # min_distance >= 0); built by hand, the evaluator still scores it low.
    with pytest.raises(ValueError, match=r"leaves the parameter's valid range \[0, inf\)"):
        swarmcl.load_ranges({"model.noise.gain": [0.05, 1.0], "model.min_distance": [-1.0, -0.5]}, SCENARIO)
    params = [swarmcl.Parameter("model.noise.gain", 0.05, 1.0), swarmcl.Parameter("model.min_distance", -1.0, -0.5)]
    ev = swarmcl.fitting.PopulationEvaluator(SCENARIO, params, real, ctx, steps=40)
    scores = ev([[0.5, 0.5], [0.2, 0.9]])
    assert scores == [swarmcl.fitting.REFUSED_SCORE] * 2 and ev.refused == 2
    assert ev._score(swarmcl.InvalidArgumentError(-1, "a sample is not finite")) == swarmcl.fitting.REFUSED_SCORE


def test_the_evaluation_templates_and_their_ranges_agree():
    import pathlib
    folder = pathlib.Path(__file__).resolve().parents[2] / "examples" / "evaluation"
    if not folder.is_dir():
        pytest.skip("examples/ not beside the tests")
    names = sorted(p.name[: -len(".ranges.json")] for p in folder.glob("*.ranges.json"))
    assert names == ["energy_mosquito", "field_mosquito", "force_mosquito", "path_mosquito"]
    for name in names:
        scenario = json.loads((folder / f"{name}.json").read_text())
        params = swarmcl.load_ranges(str(folder / f"{name}.ranges.json"), scenario)
        assert len(params) >= 2  # cma needs two
        if scenario["model"]["type"] != "energy":  # the energy one needs its track file
            swarmcl.Scenario.parse(json.dumps(scenario)).close()

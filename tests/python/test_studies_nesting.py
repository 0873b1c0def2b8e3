"""The studies' nested models (issue 26, item 2) on the mosquito tracks'
training half: force + curl contains dynamics only (eta = 0) and noise only
(every zone weight 0); fitted from the better of their fits, as
scripts/evaluation_studies.py does, it never scores lower than either on
the data it was fitted to.  Short fits (the property holds for any length:
the start is scored first and the best is kept), a shorter run than the
studies' so the test takes seconds.  Skipped without ../shared/data."""
import os
import sys
from types import SimpleNamespace

import pytest

import swarmcl

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
studies = pytest.importorskip("evaluation_studies")
pytest.importorskip("cma")

ARGS = SimpleNamespace(method="cmaes", generations=3, population=6, warmup=50, sim_seeds=1, restarts=0,
                       tolerance=0.0, step_tolerance=1e-6, patience=None)


def shortened(scenario):
    s = dict(scenario)
    s["steps"] = 250
    return s


@pytest.mark.skipif(not os.path.exists(studies.DATA), reason="needs ../shared/data/anopheles-coluzzii-swarm.csv")
def test_the_studies_nested_models_never_score_below_the_models_they_contain(tmp_path, ctx):
    files, _, _ = studies.split_tracks(studies.DATA, str(tmp_path))
    chosen = studies.variants(files["train"])
    assert studies.NESTED["force+curl"] == ("force dynamics only", "force noise only")
    with swarmcl.Metrics.from_csv(files["train"], columns=studies.COLUMNS) as train:
        smaller = {}
        for name in studies.NESTED["force+curl"]:
            scenario, ranges = chosen[name]
            r, _ = studies.fit_from_best_start(shortened(scenario), train, ranges, [], ARGS, 3, ctx, {})
            smaller[name] = r
        scenario, ranges = chosen["force+curl"]
        starts = [studies.start_from(smaller[n]["scenario"], ranges) for n in smaller]
        # Each smaller model's point is a point of the larger one: the same run.
        for n, st in zip(smaller, starts):
            assert set(st) == set(ranges)
            if n == "force dynamics only":
                assert st["model.eta"] == 0.0
            else:
                assert st["model.w_att"] == st["model.w_ali"] == st["model.w_rep"] == 0.0
        nested, start_score = studies.fit_from_best_start(shortened(scenario), train, ranges, starts, ARGS, 3, ctx,
                                                          {})
    best_smaller = max(r["best_score"] for r in smaller.values())
    # The start is the better smaller fit, scored by the larger model as it
    # scored itself (a float or two of rounding in the value's round trip
    # through [0, 1] may move the run, not by more than this).
    assert start_score == pytest.approx(best_smaller, abs=1e-6)
    assert nested["best_score"] >= start_score
    assert nested["best_score"] >= best_smaller - 1e-6


@pytest.mark.skipif(not os.path.exists(studies.DATA), reason="needs ../shared/data/anopheles-coluzzii-swarm.csv")
def test_fresh_runs_score_a_fit_on_seeds_it_was_not_fitted_on(tmp_path, ctx):
    # The studies score every fit again on simulation seeds from FRESH_SEED:
    # what a fit's own seed is does not matter there, while E over the fit's
    # own seeds does depend on them.
    files, _, _ = studies.split_tracks(studies.DATA, str(tmp_path))
    scenario = shortened(studies.variants(files["train"])["force+gaussian"][0])
    args = SimpleNamespace(warmup=50, fresh_runs=3)
    with swarmcl.Metrics.from_csv(files["test"], columns=studies.COLUMNS) as test:
        real = {"test": test}
        fresh = [studies.fresh_scores(dict(scenario, seed=s), real, ctx, args) for s in (5, 77)]
        assert fresh[0] == fresh[1]
        own = [swarmcl.fitting.PopulationEvaluator(dict(scenario, seed=s), [], test, ctx, warmup=50, seeds=3,
                                                   pool=True)([[]])[0] for s in (5, studies.FRESH_SEED)]
        assert own[0] != own[1] and own[1] == fresh[0]["test"]
        second = studies.fresh_scores(scenario, real, ctx, args, seed=studies.SECOND_BLOCK)["test"]
        assert second != fresh[0]["test"]  # another block of runs, another estimate

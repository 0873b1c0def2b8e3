"""The short soak (10^4 steps per model) of scripts/soak.py: no NaN/Inf, speeds
within each model's bound, no agent out of its domain, resident memory flat."""

import importlib.util
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("soak", REPO / "scripts" / "soak.py")
soak = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(soak)


@pytest.mark.parametrize("model", sorted(soak.MODELS))
def test_soak_10k_steps(model):
    rep = soak.run_soak(model, steps=10_000, every=500, rss_slack_mib=16.0)
    assert rep["failures"] == []
    assert rep["steps_done"] == 10_000
    assert rep["finite"]
    assert 0.0 < rep["max_speed"] <= rep["speed_bound"]
    assert rep["outside_domain"] == 0
    assert rep["ok"]

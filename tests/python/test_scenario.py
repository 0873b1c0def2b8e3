"""Scenario files through the Python API: loading, validation errors, swarms,
and recording."""

import numpy as np
import pytest

import swarmcl
from conftest import REPO

AGGREGATION = REPO / "examples" / "scenarios" / "aggregation.json"


@pytest.mark.skipif(not AGGREGATION.is_file(), reason="examples/scenarios not in this tree")
def test_load_example_and_create_swarm(ctx):
    with swarmcl.Scenario.load(AGGREGATION) as sc:
        info = sc.info
        assert info["name"] == "aggregation" and info["model"] == "field"
        assert info["agents"] == 1000 and info["steps"] > 0 and info["dt"] > 0
        assert set(info["output_formats"]) <= {"csv", "npy", "vtp"}
        with sc.create_swarm(ctx) as s:
            assert s.agent_count == info["agents"]
            s.step(2)
            assert s.take_step_stats().steps == 2


MINIMAL = '{"agents": {"count": 50}, "steps": 3}'


def test_parse_minimal():
    with swarmcl.Scenario.parse(MINIMAL) as sc:
        assert sc.info["agents"] == 50 and sc.info["steps"] == 3


@pytest.mark.parametrize("text, needle", [
    ('{"agents": {"count": 50}, ', "line 1"),                        # malformed JSON: line and column
    ('[]', "expected an object"),
    ('{"agents": {"count": "many"}}', "agents.count"),                # key path of a bad value
    ('{"agents": {"count": 5}, "model": {"type": "field", "noise": {"scale": -1}}}', "model.noise.scale"),
])
def test_validation_errors(text, needle):
    with pytest.raises(swarmcl.ParseError) as e:
        swarmcl.Scenario.parse(text)
    assert isinstance(e.value, ValueError)
    assert e.value.status == swarmcl.lib.SWCL_ERROR_PARSE
    assert needle in str(e.value)


def test_missing_file(tmp_path):
    with pytest.raises(swarmcl.IOError_) as e:
        swarmcl.Scenario.load(tmp_path / "nope.json")
    assert "nope.json" in str(e.value)


def test_recorder_npy(ctx, tmp_path):
    with swarmcl.Swarm(ctx, agent_count=20, seed=4) as s, \
            swarmcl.Recorder(tmp_path, "run", formats=["npy", "csv"]) as rec:
        frames = []
        for f in range(3):
            rec.add_frame(s, f, f * s.step_count)
            frames.append(s.positions)
            s.velocities = np.ones((20, 3))
            s.step(1)
        rec.finish()
    got = np.load(tmp_path / "run_positions.npy")
    assert got.shape == (3, 20, 3)
    np.testing.assert_array_equal(got, np.stack(frames))
    assert (tmp_path / "run.csv").is_file()

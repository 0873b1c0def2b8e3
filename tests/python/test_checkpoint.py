"""Checkpoints through the Python API: Swarm.save / Swarm.load resume a run
bit for bit in another context; bad files raise ParseError / IOError_ and
leave no swarm behind."""

import numpy as np
import pytest

import swarmcl
from conftest import REPO

EXAMPLES = REPO / "examples" / "scenarios"


@pytest.mark.parametrize("name", ["chasing.json", "path_two_blocks.json", "energy_heart.json"])
def test_save_load_resumes_bit_for_bit(ctx, tmp_path, name):
    path = EXAMPLES / name
    if not path.is_file():
        pytest.skip("examples/scenarios not in this tree")
    with swarmcl.Scenario.load(path) as sc:
        with sc.create_swarm(ctx) as straight, sc.create_swarm(ctx) as first:
            straight.step(20)
            first.step(8)
            first.save(tmp_path / "swarm.swcl")
            with swarmcl.Context() as other:
                with swarmcl.Swarm.load(other, tmp_path / "swarm.swcl") as resumed:
                    assert resumed.step_count == 8
                    resumed.step(12)
                    assert resumed.step_count == 20
                    np.testing.assert_array_equal(resumed.read_positions(), straight.read_positions())
                    np.testing.assert_array_equal(resumed.read_velocities(), straight.read_velocities())
                    assert resumed.take_step_stats() == straight.take_step_stats()


def test_ballistic_swarm(ctx, tmp_path, rng):
    s = swarmcl.Swarm(ctx, capacity=40)
    s.write_positions(rng.uniform(-1, 1, (30, 3)))
    s.write_velocities(rng.uniform(-0.2, 0.2, (30, 3)))
    s.step(3)
    s.save(str(tmp_path / "b.swcl"))
    t = swarmcl.Swarm.load(ctx, str(tmp_path / "b.swcl"))
    s.step(5)
    t.step(5)
    np.testing.assert_array_equal(s.positions, t.positions)
    np.testing.assert_array_equal(s.velocities, t.velocities)


def test_bad_files_are_refused(ctx, tmp_path):
    s = swarmcl.Swarm(ctx, agent_count=10)
    good = tmp_path / "good.swcl"
    s.save(good)
    data = good.read_bytes()
    with pytest.raises(swarmcl.IOError_):
        swarmcl.Swarm.load(ctx, tmp_path / "missing.swcl")
    cases = {
        "truncated.swcl": data[: len(data) // 2],
        "flipped.swcl": data[:40] + bytes([data[40] ^ 4]) + data[41:],
        "magic.swcl": b"NOTACKPT" + data[8:],
        "empty.swcl": b"",
    }
    for name, content in cases.items():
        (tmp_path / name).write_bytes(content)
        with pytest.raises(swarmcl.ParseError) as info:
            swarmcl.Swarm.load(ctx, tmp_path / name)
        assert "checkpoint" in str(info.value), name
    with pytest.raises(TypeError):
        swarmcl.Swarm.load("not a context", good)

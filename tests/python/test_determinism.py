"""The same scenario run by the swarmcl CLI and by Python gives bitwise the
same frames (issue 16 item 4), for every model type.  Needs the CLI binary:
$SWARMCL_CLI, else swarmcl in $SWARMCL_BUILD_DIR or build/; skipped without."""

import json
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import swarmcl

REPO = pathlib.Path(__file__).resolve().parents[2]
CASES = {"field": ("aggregation.json", 48), "path": ("path_aggregation.json", 48),
         "force": ("force_moon_5k.json", 48), "energy": ("energy_aggregation_37.json", 37),
         "policy": ("policy_roaming.json", 48)}
STEPS, EVERY = 20, 5


def _cli():
    if os.environ.get("SWARMCL_CLI"):
        return os.environ["SWARMCL_CLI"]
    for d in (os.environ.get("SWARMCL_BUILD_DIR"), str(REPO / "build")):
        if d and (pathlib.Path(d) / "swarmcl").is_file():
            return str(pathlib.Path(d) / "swarmcl")
    return shutil.which("swarmcl")


@pytest.mark.parametrize("model", sorted(CASES))
def test_python_frames_equal_the_cli_files(model, ctx, tmp_path):
    cli = _cli()
    if cli is None:
        pytest.skip("no swarmcl CLI binary found")
    fname, agents = CASES[model]
    sc = json.loads((REPO / "examples" / "scenarios" / fname).read_text())
    sc["agents"]["count"] = agents
    sc["steps"] = STEPS
    sc["output"]["formats"], sc["output"]["every"] = ["npy"], EVERY
    if sc["model"].get("type") == "policy":  # weights relative to the example's folder
        sc["model"]["weights"] = str(REPO / "examples" / "scenarios" / sc["model"]["weights"])
    text = json.dumps(sc)
    (tmp_path / "s.json").write_text(text)
    subprocess.run([cli, "run", "s.json", "--out", "o", "--format", "npy", "--quiet"], cwd=tmp_path,
                   check=True, capture_output=True)
    pos = np.load(tmp_path / "o" / f"{sc['name']}_positions.npy")
    vel = np.load(tmp_path / "o" / f"{sc['name']}_velocities.npy")
    assert pos.shape == (STEPS // EVERY + 1, agents, 3)

    with swarmcl.Scenario.parse(text) as scen, scen.create_swarm(ctx) as s:
        for f in range(STEPS // EVERY + 1):
            if f:
                s.step(EVERY)
            p, v = s.read_positions(), s.read_velocities()
            assert p.tobytes() == pos[f].astype(np.float32).tobytes(), f"{model}: positions differ at frame {f}"
            assert v.tobytes() == vel[f].astype(np.float32).tobytes(), f"{model}: velocities differ at frame {f}"
    assert not np.array_equal(pos[0], pos[-1])

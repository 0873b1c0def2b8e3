"""The parameter tables (issue 24): every C descriptor field of a model is a
row of its table with the same default (the descriptor structs stay the
stable ABI; the table is what the library reads scenarios, ranges and device
blocks from), the Python model classes are built from the rows, and fit
ranges are checked against them."""

import dataclasses

import numpy as np
import pytest

import swarmcl
from swarmcl.fitting import load_ranges

ffi, lib = swarmcl.ffi, swarmcl.lib

# The noise rows a model's C descriptor has no field for (the force model's
# descriptor gives its noise as eta, rho and noise_seed: rho is the row
# noise.scale, noise_seed noise.seed, eta = gain * scale is derived).
_FORCE_NOISE_NOT_IN_C = {"noise." + k for k in ("type", "gain", "time_scale", "boundary_distance", "domain_walls",
                                                "region_min", "region_max", "baked", "bake_resolution",
                                                "finite_difference", "fd_step")}

# model -> (its C descriptor, its defaults function, the fields that are
# structured data rather than parameters: pointers and their counts, derived
# fields; the table rows the descriptor has no field for).
DESCRIPTORS = {
    "field": ("swcl_field_model_desc", lib.swcl_field_model_desc_default,
              {"noise.boundaries", "noise.boundary_count"}, set()),
    "noise": ("swcl_noise_desc", lib.swcl_noise_desc_default, {"boundaries", "boundary_count"}, set()),
    "force": ("swcl_force_model_desc", lib.swcl_force_model_desc_default,
              {"keyframes", "keyframe_count", "path", "path_point_count", "obstacles", "obstacle_count",
               "mesh_obstacles", "mesh_obstacle_count", "eta"},
              _FORCE_NOISE_NOT_IN_C | {"terms"}),
    "path": ("swcl_path_model_desc", lib.swcl_path_model_desc_default,
             {"noise.boundaries", "noise.boundary_count", "obstacles", "obstacle_count", "goals", "goal_count",
              "groups", "group_count"},
             {"has_grid_box", "waypoint_every"} | {"lamp." + k for k in ("enabled", "center", "radius", "probability",
                                                                       "speed", "angle", "keep_out")}),
    "energy": ("swcl_energy_model_desc", lib.swcl_energy_model_desc_default,
               {"noise.boundaries", "noise.boundary_count", "stimuli", "stimulus_count", "keypoints",
                "keypoint_count"}, set()),
    "policy": ("swcl_policy_model_desc", lib.swcl_policy_model_desc_default,
               {"weights_path", "weights_data", "weights_size", "waypoints", "waypoint_count", "obstacles",
                "obstacle_count"}, set()),
}


def c_fields(ctype, prefix=""):
    """(dotted name, cffi type) of every field of a C struct, nested structs
    walked into; struct_size left out."""
    out = []
    # A nested struct's type is a CType already (ffi.typeof refuses one).
    for name, f in (ctype if isinstance(ctype, ffi.CType) else ffi.typeof(ctype)).fields:
        if name == "struct_size":
            continue
        if f.type.kind == "struct":
            out += c_fields(f.type, prefix + name + ".")
        else:
            out.append((prefix + name, f.type))
    return out


def c_value(desc, dotted):
    v = desc
    for part in dotted.split("."):
        v = getattr(v, part)
    return v


def as_table_value(row, v, ctype):
    if ctype.kind == "array":
        return [as_table_value(row, v[i], ctype.item) for i in range(ctype.length)]
    if row["type"] == "enum":
        return row["values"][int(v)]
    if row["type"] == "bool":
        return bool(v)
    if row["type"] == "float" or row["type"] == "vec3":
        return float(np.float32(v))
    return int(v)


@pytest.mark.parametrize("model", sorted(DESCRIPTORS))
def test_every_descriptor_field_is_a_row_with_the_same_default(model):
    ctype, default_fn, structured, not_in_c = DESCRIPTORS[model]
    rows = {r["c_field"]: r for r in swarmcl.model_parameters(model)}
    desc = default_fn()
    fields = dict(c_fields(ctype))
    missing = [n for n in fields if n not in rows and n not in structured]
    assert not missing, f"{ctype} fields without a row in the {model} table: {missing}"
    extra = [n for n in rows if n not in fields and n not in not_in_c]
    assert not extra, f"{model} table rows without a {ctype} field: {extra}"
    for name, row in rows.items():
        if name in not_in_c:
            continue
        have = as_table_value(row, c_value(desc, name), fields[name])
        want = row["default"]
        if row["type"] in ("float", "vec3"):
            want = [float(np.float32(x)) for x in want] if isinstance(want, list) else float(np.float32(want))
        assert have == want, f"{ctype}.{name}: C default {have!r}, table default {want!r}"


def test_every_model_table_is_exported_with_its_rows():
    tables = swarmcl.model_parameters()
    assert "field" in tables
    for model, rows in tables.items():
        for r in rows:
            assert {"key", "c_field", "type", "default", "range", "unit", "doc", "ref"} <= set(r), (model, r)
    with pytest.raises(ValueError, match="known: "):
        swarmcl.model_parameters("boids")


def test_field_model_class_is_built_from_the_table():
    rows = {r["c_field"]: r for r in swarmcl.model_parameters("field")}
    m = swarmcl.FieldModel()
    for name in ("goal_radius", "goal_speed", "goal_falloff", "min_distance"):
        assert getattr(m, name) == float(np.float32(rows[name]["default"])), name
        assert rows[name]["doc"] in swarmcl.FieldModel.__doc__
    assert m.goal is None and isinstance(m.noise, swarmcl.NoiseDesc)
    p, _ = swarmcl.FieldModel(goal=(1, 2, 3), goal_speed=2.0, min_distance=0.02).to_c()
    assert p.has_goal == 1 and list(p.goal) == [1, 2, 3]
    assert p.goal_speed == 2.0 and p.min_distance == pytest.approx(0.02)
    with pytest.raises(TypeError, match="FieldModel.goal_speed must be a float"):
        swarmcl.FieldModel(goal_speed="fast").to_c()


def test_a_bad_value_from_python_names_the_parameter_and_range(ctx):
    s = swarmcl.Swarm(ctx, agent_count=10, seed=1)
    with pytest.raises(swarmcl.InvalidArgumentError, match=r"goal_radius = -1 is outside \[0, inf\)"):
        s.set_field_model(swarmcl.FieldModel(goal=(0, 0, 0), goal_radius=-1.0))


def test_force_model_class_is_built_from_the_table():
    rows = {r["c_field"]: r for r in swarmcl.model_parameters("force")}
    m = swarmcl.ForceModel()
    for name in ("r_rep", "w_att", "alpha", "max_speed", "rho", "obstacle_range", "path_speed"):
        assert np.float32(getattr(m, name)) == np.float32(rows[name]["default"]), name
        assert rows[name]["doc"] in swarmcl.ForceModel.__doc__
    assert m.path_orient is True and m.keyframe_period == 0 and m.assignment == "nearest"
    assert m.eta == pytest.approx(0.125) and not hasattr(m, "terms")
    p, _ = swarmcl.ForceModel(r_rep=0.5, noise_seed=7, path_orient=False, keyframe_period=9).to_c()
    assert p.r_rep == 0.5 and p.noise_seed == 7 and p.path_orient == 0 and p.keyframe_period == 9
    with pytest.raises(TypeError, match="ForceModel.alpha must be a float"):
        swarmcl.ForceModel(alpha="half").to_c()


def test_a_bad_force_value_from_python_names_the_parameter_and_range(ctx):
    s = swarmcl.Swarm(ctx, agent_count=10, seed=1)
    with pytest.raises(swarmcl.InvalidArgumentError, match=r"alpha = 1.5 is outside \[0, 1\]"):
        s.set_force_model(swarmcl.ForceModel(alpha=1.5))


def test_path_model_class_is_built_from_the_table():
    rows = {r["c_field"]: r for r in swarmcl.model_parameters("path")}
    m = swarmcl.PathModel()
    for name in ("cost_a", "cost_b", "speed", "goal_falloff", "min_distance"):
        assert np.float32(getattr(m, name)) == np.float32(rows[name]["default"]), name
        assert rows[name]["doc"] in swarmcl.PathModel.__doc__
    assert m.second_order is False and m.grid is None and tuple(m.resolution) == (64, 64, 64)
    assert not hasattr(m, "waypoint_every") and not hasattr(m, "has_grid_box")
    p, _ = swarmcl.PathModel(speed=2.5, second_order=True, cost_a=0.5).to_c()
    assert p.speed == 2.5 and p.second_order == 1 and p.cost_a == 0.5
    with pytest.raises(TypeError, match="PathModel.speed must be a float"):
        swarmcl.PathModel(speed="fast").to_c()


FIELD_SCENARIO = {"agents": {"count": 10}, "model": {"type": "field", "goal": {"center": [0, 0, 0]}}}


def test_fit_ranges_are_checked_against_the_table():
    # A table parameter the scenario leaves at its default can be fitted.
    params = load_ranges({"model.goal.speed": [0.5, 2.0], "model.noise.seed": [0, 10]}, FIELD_SCENARIO)
    assert [p.path for p in params] == ["model.goal.speed", "model.noise.seed"]
    assert params[0].integer is False and params[1].integer is True
    with pytest.raises(ValueError, match=r"neither in the scenario nor a parameter of the field model; "
                                         r"its parameters: .*model\.goal\.speed"):
        load_ranges({"model.goal.sped": [0.5, 2.0]}, FIELD_SCENARIO)
    with pytest.raises(ValueError, match=r"leaves the parameter's valid range \[0, inf\)"):
        load_ranges({"model.goal.speed": [-1.0, 2.0]}, FIELD_SCENARIO)
    with pytest.raises(ValueError, match=r"leaves the parameter's valid range \(0, inf\)"):
        load_ranges({"model.noise.scale": [0.0, 2.0]}, FIELD_SCENARIO)
    with pytest.raises(ValueError, match="is a bool parameter of the field model, not a number"):
        load_ranges({"model.noise.baked": [0, 1]}, FIELD_SCENARIO)
    with pytest.raises(ValueError, match="is a uint3 parameter of the field model, not a number"):
        load_ranges({"model.noise.bake_resolution": [8, 16]}, FIELD_SCENARIO)


def test_energy_model_classes_are_built_from_the_table():
    rows = {r["c_field"]: r for r in swarmcl.model_parameters("energy")}
    # The public fields keep their order (positional arguments) and defaults.
    assert [f.name for f in dataclasses.fields(swarmcl.EnergyModel)] == [
        "weights", "danger_weights", "rho", "d_rep", "d_att1", "d_att2", "centre", "span", "accel_time",
        "danger_horizon", "noise", "stimuli", "keypoints", "keypoints_closed", "bidirectional", "keypoint_reach",
        "keep_out"]
    assert [f.name for f in dataclasses.fields(swarmcl.EnergyWeights)] == [
        "rep", "oa", "cos", "dir", "acc", "env", "noise", "user"]
    m = swarmcl.EnergyModel()
    for name in ("rho", "d_rep", "d_att1", "d_att2", "accel_time", "danger_horizon", "keypoint_reach"):
        assert np.float32(getattr(m, name)) == np.float32(rows[name]["default"]), name
        assert rows[name]["doc"] in swarmcl.EnergyModel.__doc__
    assert m.span == 1 and m.keep_out is True and m.keypoints_closed is True and m.bidirectional is True
    assert m.centre is None and m.keypoints is None and m.stimuli == []
    assert (m.noise.scale, m.noise.time_scale) == (pytest.approx(0.2), 1.0)  # the energy model's own noise
    assert m.weights == swarmcl.EnergyWeights(1.0, 1.0, 0.05, 1.0, 1.0, 0.0, 0.2, 0.0)  # Table 1 aggregation
    assert m.danger_weights == swarmcl.EnergyWeights(1.0, 0.0, 0.0, 1.0, 1.0, 2.0, 0.3, 0.0)  # in danger
    assert rows["weights.noise"]["doc"] in swarmcl.EnergyWeights.__doc__
    p, _ = swarmcl.EnergyModel(weights=swarmcl.EnergyWeights(rep=2.0, noise=0.5), rho=3.0, span=2, centre=(1, 2, 3),
                               keep_out=False).to_c()
    assert p.weights.rep == 2.0 and p.weights.noise == 0.5 and p.danger_weights.env == 2.0
    assert p.rho == 3.0 and p.span == 2 and p.keep_out == 0 and p.keypoints_closed == 1
    assert p.has_fixed_centre == 1 and list(p.fixed_centre) == [1, 2, 3]
    assert p.noise.scale == pytest.approx(0.2) and p.noise.time_scale == 1.0
    with pytest.raises(TypeError, match="EnergyModel.span must be a uint32"):
        swarmcl.EnergyModel(span="wide").to_c()
    with pytest.raises(TypeError, match="EnergyWeights.rep must be a float"):
        swarmcl.EnergyModel(weights=swarmcl.EnergyWeights(rep="heavy")).to_c()


def test_a_bad_energy_value_from_python_names_the_parameter_and_range(ctx):
    s = swarmcl.Swarm(ctx, agent_count=10, dt=0.01, seed=1)
    data = swarmcl.Dataset.synthetic(k=60, groups=3)
    with pytest.raises(swarmcl.InvalidArgumentError, match=r"energy model rho = -1 is outside \(0, inf\)"):
        s.set_energy_model(data, swarmcl.EnergyModel(rho=-1.0))
    with pytest.raises(swarmcl.InvalidArgumentError, match=r"energy model danger_weights\.noise = -0\.5 is outside"):
        s.set_energy_model(data, swarmcl.EnergyModel(danger_weights=swarmcl.EnergyWeights(noise=-0.5)))
    with pytest.raises(swarmcl.InvalidArgumentError, match="d_att1 must be a finite number >= d_rep"):
        s.set_energy_model(data, swarmcl.EnergyModel(d_rep=0.5, d_att1=0.1))


ENERGY_SCENARIO = {"agents": {"count": 10}, "model": {"type": "energy", "weights": {"rep": 1.0}}}


def test_energy_fit_ranges_are_checked_against_the_table():
    params = load_ranges({"model.weights.rep": [0.0, 3.0], "model.danger_weights.env": [0.0, 4.0],
                          "model.span": [0, 3]}, ENERGY_SCENARIO)
    assert [p.integer for p in params] == [False, False, True]
    with pytest.raises(ValueError, match=r"neither in the scenario nor a parameter of the energy model"):
        load_ranges({"model.weights.repulsion": [0.0, 1.0]}, ENERGY_SCENARIO)
    with pytest.raises(ValueError, match=r"leaves the parameter's valid range \(0, inf\)"):
        load_ranges({"model.rho": [0.0, 3.0]}, ENERGY_SCENARIO)


def test_policy_model_class_is_built_from_the_table():
    import dataclasses
    rows = {r["c_field"]: r for r in swarmcl.model_parameters("policy")}
    # The public fields keep their order (positional arguments).
    assert [f.name for f in dataclasses.fields(swarmcl.PolicyModel)] == [
        "weights", "leader_mode", "waypoints", "leader_position", "leader_heading", "leader_speed", "leader_du_max",
        "leader_dq_max_deg", "reach_radius", "r_sep", "r_ali", "r_coh", "neighbor_radius", "body_radius", "du_max",
        "dq_max_deg", "u_max", "obstacles"]
    m = swarmcl.PolicyModel()
    for name in ("r_sep", "r_ali", "r_coh", "du_max", "u_max", "reach_radius", "leader_speed"):
        assert np.float32(getattr(m, name)) == np.float32(rows[name]["default"]), name
        assert rows[name]["doc"] in swarmcl.PolicyModel.__doc__
    assert m.leader_mode == "joystick" and m.leader_heading == (1.0, 0.0, 0.0)
    d, _ = swarmcl.PolicyModel(r_coh=20.0, u_max=2.5, leader_mode="tour").to_c()
    assert d.r_coh == 20.0 and d.u_max == 2.5 and d.r_sep == 1.0
    with pytest.raises(TypeError, match="PolicyModel.u_max must be a float"):
        swarmcl.PolicyModel(u_max="fast").to_c()

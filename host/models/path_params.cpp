// The path model's parameters (PathModelConfig), declared once
// (params/param_table.hpp).  The speed s0 and the lamp are read by the
// kernel from the model's parameter block (kernels/path_model.cl,
// PATH_<KEY>).  Structured parts (obstacle meshes, goals and groups, chasing
// targets, the moving goal's waypoints) and the lamp's angle in degrees are
// read by the section (scenario/path_section.cpp).
#include "models/path_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

const ParamTable& path_param_table() {
    static const ParamTable table = [] {
        using C = PathModelConfig;
        using T = ParamType;
        ParamTable t("path", "PathModelConfig");
        t.include("noise.", noise_param_table(), &C::noise, ParamTable::Block::Own);
        t.add("has_grid_box", T::Bool, &C::has_grid_box).implied()
            .says("the grid covers grid.min..grid.max (scenario files: set when they are given); false: the domain")
            .cites("ours")
            .same_in_every_world("the path grid is built once, for every world");
        t.add("grid.min", T::Vec3, &C::grid_min).c("grid_min").in("m")
            .says("the path grid's low corner (with grid.max)").cites("curl-noise paper §5.1")
            .same_in_every_world("the path grid is built once, for every world");
        t.add("grid.max", T::Vec3, &C::grid_max).c("grid_max").in("m")
            .says("the path grid's high corner (with grid.min)").cites("curl-noise paper §5.1")
            .same_in_every_world("the path grid is built once, for every world");
        // No bound per axis: the grid's cell count is (at most 2^26, make_grid).
        t.add("grid.resolution", T::UInt3, &C::resolution).c("resolution").range(2, 4294967295.0)
            .says("cells per axis at most (cubic cells; at most 2^26 cells in all)").cites("curl-noise paper §5.1")
            .same_in_every_world("the path grid is built once, for every world");
        t.add("cost.A", T::Double, &C::weights, &CostWeights::A).c("cost_a").positive()
            .says("A: weight of the path length in the cost").cites("curl-noise paper §5, Eq. 4 (0.6)");
        t.add("cost.B", T::Double, &C::weights, &CostWeights::B).c("cost_b").non_negative()
            .says("B: weight of the obstacles' repulsion in the cost").cites("curl-noise paper §5, Eq. 4 (0.4)");
        t.add("cost.second_order", T::Bool, &C::second_order).c("second_order")
            .says("second-order fast marching").cites("curl-noise paper §5.2");
        t.add("speed", T::Float, &C::speed).non_negative().in("m/s")
            .says("s0, the speed of the global field").cites("curl-noise paper §5.2, Eq. 8, Table 1").on_device();
        t.add("goal_falloff", T::Float, &C::goal_falloff).non_negative().in("m")
            .says("path over which V_g grows from 0 at a goal to s0; 0: at once (the paper's)").cites("ours");
        t.add("min_distance", T::Float, &C::min_distance).non_negative().in("m")
            .says("minimum distance enforcement threshold; 0: off").cites("curl-noise paper §6");
        t.add("moving_goal.every", T::UInt32, &C::waypoint_every).c("waypoint_every").range(1, 4294967295.0)
            .in("steps").says("group 0's goals (or target 0) move to the next waypoint every this many steps")
            .cites("curl-noise paper §7 (chasing)");
        t.add("lamp.enabled", T::Bool, &C::lamp, &PathLamp::enabled).c("lamp.enabled").implied()
            .says("phototaxis is on (scenario files: set when \"lamp\" is given)").cites("curl-noise paper §7")
            .on_device();
        t.add("lamp.center", T::Vec3, &C::lamp, &PathLamp::center).c("lamp.center").needed().in("m")
            .says("the lamp's centre").cites("curl-noise paper §7").on_device();
        t.add("lamp.radius", T::Float, &C::lamp, &PathLamp::radius).c("lamp.radius").positive().in("m")
            .says("the bulb's radius").cites("ours").on_device();
        t.add("lamp.probability", T::Float, &C::lamp, &PathLamp::probability).c("lamp.probability").range(0, 1)
            .says("chance per insect and step of the pull towards the lamp").cites("curl-noise paper §7").on_device();
        t.add("lamp.speed", T::Float, &C::lamp, &PathLamp::speed).c("lamp.speed").non_negative().in("m/s")
            .says("speed of that pull").cites("curl-noise paper §7 (\"a small magnitude of speed\")").on_device();
        t.add("lamp.angle", T::Float, &C::lamp, &PathLamp::angle).c("lamp.angle").range(0, double(1.5707964f)).implied().in("rad")
            .says("the pull turned about +z (scenario files: lamp.angle_deg, in degrees)").cites("ours");
        t.add("lamp.keep_out", T::Float, &C::lamp, &PathLamp::keep_out).c("lamp.keep_out").positive().in("m")
            .says("the pull's radial part fades over this distance above the bulb").cites("ours").on_device();
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl

// The field model's parameters (FieldModelConfig), declared once
// (params/param_table.hpp).  The goal's centre, radius, speed and falloff
// are read by the kernel from the model's parameter block.
#include "models/field_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

const ParamTable& field_param_table() {
    static const ParamTable table = [] {
        using C = FieldModelConfig;
        using T = ParamType;
        ParamTable t("field", "FieldModelConfig");
        t.include("noise.", noise_param_table(), &C::noise, ParamTable::Block::Own);
        t.add("has_goal", T::Bool, &C::has_goal).implied()
            .says("pull towards the goal (scenario files: set when \"goal\" is given)").cites("curl-noise paper §6")
            .on_device();
        t.add("goal.center", T::Vec3, &C::goal).c("goal").needed().in("m")
            .says("the goal's centre").cites("curl-noise paper §6").on_device();
        t.add("goal.radius", T::Float, &C::goal_radius).non_negative().in("m")
            .says("no pull inside this sphere around the goal").cites("ours").on_device();
        t.add("goal.speed", T::Float, &C::goal_speed).non_negative().in("m/s")
            .says("s0, the speed of the pull").cites("curl-noise paper §6, Table 1").on_device();
        t.add("goal.falloff", T::Float, &C::goal_falloff).non_negative().in("m")
            .says("distance over which the pull ramps up to s0; 0: at once (the paper's)").cites("ours").on_device();
        t.add("min_distance", T::Float, &C::min_distance).non_negative().in("m")
            .says("minimum distance enforcement threshold; 0: off").cites("curl-noise paper §6");
        t.add("max_speed", T::Float, &C::max_speed).non_negative().in("m/s")
            .says("a faster agent's velocity is scaled down to this speed; 0: no limit")
            .cites("ours (as the force model's max speed, shape paper §6)").on_device();
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl

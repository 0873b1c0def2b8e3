// The force model's parameters (ForceModelConfig), declared once
// (params/param_table.hpp).  The zone radii and weights, the blend, the
// speeds and the obstacle range are read by the kernels from the model's
// parameter block (kernels/force_model.cl, FORCE_<KEY>).  Structured parts
// (keyframes, the path's control points, obstacles, mesh obstacles) and the
// legacy noise keys (eta, rho, noise_seed, noise_type, noise_time_scale) are
// read by the section (scenario/force_section.cpp).
#include "models/force_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

namespace {
constexpr const char* kTargetsRefused = "the target meshes, their placement and the path are one for every world";
}  // namespace

const ParamTable& force_param_table() {
    static const ParamTable table = [] {
        using C = ForceModelConfig;
        using T = ParamType;
        ParamTable t("force", "ForceModelConfig");
        t.add("r_rep", T::Float, &C::r_rep).positive().in("m")
            .says("R_rep: repulsion zone radius").cites("shape paper §4.1, Eq. 3, Table 1").on_device();
        t.add("r_ali", T::Float, &C::r_ali).positive().in("m")
            .says("R_ali: alignment zone radius (r_rep <= r_ali)").cites("shape paper §4.1, Eq. 3, Table 1").on_device();
        t.add("r_att", T::Float, &C::r_att).positive().in("m")
            .says("R_att: attraction zone radius (r_ali <= r_att)").cites("shape paper §4.1, Eq. 3, Table 1").on_device();
        t.add("w_rep", T::Float, &C::w_rep).non_negative()
            .says("omega_rep: weight of the repulsion").cites("shape paper §4.1, Eq. 2, Table 1").on_device();
        t.add("w_ali", T::Float, &C::w_ali).non_negative()
            .says("omega_ali: weight of the alignment").cites("shape paper §4.1, Eq. 2, Table 1").on_device();
        t.add("w_att", T::Float, &C::w_att).non_negative()
            .says("omega_att: weight of the attraction").cites("shape paper §4.1, Eq. 2, Table 1").on_device();
        t.add("w_dis", T::Float, &C::w_dis).non_negative()
            .says("weight of the distance force").cites("shape paper §5.3, Eq. 6, Table 1").on_device();
        t.add("neighbor_sample", T::UInt32, &C::neighbor_sample)
            .says("> 0: alignment and attraction sample this many agents per agent and step; 0: exact")
            .cites("ours (docs/force-model.md)").on_device();
        t.add("w_con", T::Float, &C::w_con).non_negative()
            .says("weight of the shape-constrained force (the paper's is 1)").cites("shape paper §5.2, Eq. 5")
            .on_device();
        t.add("omega", T::Float, &C::omega).positive()
            .says("sigma = omega sqrt(A/N), the Gaussian's width").cites("shape paper §5.2, Eq. 5").on_device();
        t.add("neighbor_k", T::Float, &C::neighbor_k).positive()
            .says("target neighbours within k sqrt(A/N), Manhattan").cites("shape paper §5.2")
            .same_in_every_world(kTargetsRefused);
        t.add("distance_scale", T::Float, &C::distance_scale).non_negative().in("m")
            .says("normalises d of the distance force; 0: 2 sqrt(A/N)").cites("ours (shape paper §5.3, Eq. 6)")
            .on_device();
        t.add("alpha", T::Float, &C::alpha).range(0, 1)
            .says("blend of the internal (1) and external (0) forces").cites("shape paper §3, Eq. 1").on_device();
        t.add("max_speed", T::Float, &C::max_speed).positive().in("m/s")
            .says("speed limit of the Newton step").cites("shape paper §6, Table 1").on_device();
        t.add("cruise_speed", T::Float, &C::cruise_speed).non_negative().in("m/s")
            .says("slower insects are sped up to it (<= max_speed); 0: off (the paper's)")
            .cites("ours (docs/force-model.md)").on_device();
        t.add("speed_relaxation", T::Float, &C::speed_relaxation).range(0, 1000).in("1/s")
            .says("rate at which the speed relaxes to preferred_speed before each Newton step; 0: off (the paper's)")
            .cites("ours (docs/force-model.md)").on_device();
        t.add("preferred_speed", T::Float, &C::preferred_speed).non_negative().in("m/s")
            .says("speed the relaxation tends to; 0: a linear drag").cites("ours (docs/force-model.md)").on_device();
        t.add("speed_spread", T::Float, &C::speed_spread).range(0, 3)
            .says("log-sd of each insect's pace, which scales its forces and speeds (mean 1); 0: insects alike (the paper's)")
            .cites("ours (docs/force-model.md)").on_device();
        // The internal noise (Eq. 4: scale = rho, gain = eta / rho by
        // default); a scenario's "noise" object starts from the noise
        // module's defaults, the legacy keys from these (force_section.cpp).
        t.include("noise.", noise_param_table(), &C::noise, ParamTable::Block::Own);
        t.row("noise.scale").c("rho");         // swcl_force_model_desc's names
        t.row("noise.seed").c("noise_seed");
        t.add("min_distance", T::Float, &C::min_distance).non_negative().in("m")
            .says("minimum distance enforcement threshold; 0: off").cites("shape paper §6");
        t.add("min_spacing", T::Float, &C::min_spacing).non_negative().in("m")
            .says("meshes scaled so sqrt(A/N) >= this (R_rep); 0: as given").cites("shape paper §5.1")
            .same_in_every_world(kTargetsRefused);
        t.add("assignment", T::Enum, &C::assignment).names({"nearest", "curve"})
            .says("agents to targets: nearest free target in id order, or by rank along a Hilbert curve")
            .cites("ours (shape paper §5.1)")
            .same_in_every_world(kTargetsRefused);
        t.add("sample_seed", T::UInt64, &C::sample_seed)
            .says("seeds the stratified sampling of the target meshes").cites("shape paper §5.1")
            .same_in_every_world("the neighbour sample's seed is one for every world");
        t.add("keyframe_period", T::UInt64, &C::keyframe_period).range(0, 4294967295.0).in("steps")
            .says("> 0: the keyframes repeat every this many steps").cites("ours")
            .same_in_every_world(kTargetsRefused);
        t.add("path.speed", T::Float, &C::path_speed).non_negative().in("m/s")
            .says("speed of the shape along the B-spline path").cites("shape paper §6")
            .same_in_every_world(kTargetsRefused);
        t.add("path.orient", T::Bool, &C::path_orient)
            .says("the shape's frame turns with the path (+x along its tangent); false: translated only")
            .cites("shape paper §6")
            .same_in_every_world(kTargetsRefused);
        t.add("obstacle_range", T::Float, &C::obstacle_range).positive().in("m")
            .says("L: distance over which obstacles ramp the velocity").cites("shape paper §6, Eq. 8-9").on_device();
        t.add("mesh_cell", T::Float, &C::mesh_cell).non_negative().in("m")
            .says("cell edge of the mesh obstacles' distance grid; 0: obstacle_range / 4")
            .cites("ours (docs/force-model.md)")
            .same_in_every_world(kTargetsRefused);
        t.add("terms", T::UInt32, &C::terms).range(0, kForceAll).implied()
            .says("which forces are on (bits: repulsion 1, alignment 2, attraction 4, curl 8, shape 16, distance 32)")
            .cites("ours (tests)").on_device()
            .same_in_every_world("it selects the kernels that run (the fine grid with repulsion)");
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl

// The energy model's parameters (EnergyModelConfig, FASTSWARM), declared once
// (params/param_table.hpp).  The weights (both sets), rho, the radii, span,
// danger_horizon, keypoint_reach and keypoints_closed are read by
// energy_select from the model's parameter block (kernels/energy_model.cl,
// ENERGY_*).  Structured parts stay with the section reader and the
// checkpoint: the dataset (EnergySpec), the stimuli, the keypoints and the
// noise's boundaries; exact_attraction is host-only and not a scenario key.
// References: "§" and "Eq." are the FASTSWARM paper's (Xiang et al.).
#include "models/energy_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {
namespace {

// The eight weights of one set (Table 1's columns), included under
// "weights." and "danger_weights."; `when` ends each doc line.
ParamTable weights_table(const std::string& when, const std::string& table_ref) {
    using W = EnergyWeights;
    using T = ParamType;
    ParamTable t("energy weights", "EnergyWeights");
    struct Row {
        const char* key;
        const char* c_field;  // swcl_energy_weights' name
        float W::*member;
        const char* what;
        const char* ref;
    };
    // Order W_REP .. W_USER: energy_select reads the set as one float8.
    const Row rows[] = {
        {"rep", "rep", &W::rep, "w_rep: weight of the repulsion energy E_rep", "§4.1.1, Eq. 4"},
        {"oa", "oa", &W::oa, "w_oa: weight of the attraction to neighbours E_oa", "§4.1.2, Eq. 6"},
        {"cos", "cos", &W::cos, "w_cos: weight of the attraction to the swarm centre E_cos", "§4.1.2, Eq. 7"},
        {"dir", "dir", &W::dir, "w_dir: weight of the directional continuity E_dir", "§4.2.1, Eq. 9"},
        {"acc", "acc", &W::acc, "w_acc: weight of the acceleration continuity E_acc", "§4.2.1, Eq. 10"},
        {"env", "env", &W::env, "w_env: weight of the response to stimuli E_env", "§4.2.2, Eq. 11-12"},
        {"n", "noise", &W::n, "w_n: weight of the noise-induced direction E_n", "§4.3, Eq. 13"},
        {"user", "user", &W::user, "w_user: weight of the user control (keypoints) E_user", "§4.4, Eq. 14"},
    };
    for (const Row& r : rows) {
        Param& p = t.add(r.key, T::Float, r.member).c(r.c_field).non_negative().on_device();
        p.doc = std::string(r.what) + when;
        p.ref = std::string("FASTSWARM ") + r.ref + "; " + table_ref;
    }
    t.finish<W>();
    return t;
}

}  // namespace

const ParamTable& energy_param_table() {
    static const ParamTable table = [] {
        using C = EnergyModelConfig;
        using T = ParamType;
        ParamTable t("energy", "EnergyModelConfig");
        t.include("weights.", weights_table("", "Table 1 (default: aggregation)"), &C::weights);
        t.include("danger_weights.",
                  weights_table(", for an agent in danger (a startling stimulus within d_danger)",
                                "Table 1, escaping \"in danger\" (docs/energy-model.md)"),
                  &C::danger_weights);
        t.add("rho", T::Float, &C::rho).positive()
            .says("the paper's rho: scale of every term's exponent").cites("FASTSWARM §4.1.1, Eq. 4-14; §5 (2.5)").on_device();
        t.add("d_rep", T::Float, &C::d_rep).positive().in("m")
            .says("repulsion radius: neighbours closer than this repel").cites("FASTSWARM §4.1.1, Eq. 4 (value ours)")
            .on_device();
        t.add("d_att1", T::Float, &C::d_att1).positive().in("m")
            .says("inner attraction radius (at least d_rep)").cites("FASTSWARM §4.1.2, Eq. 6 (value ours)").on_device();
        t.add("d_att2", T::Float, &C::d_att2).positive().in("m")
            .says("outer attraction radius (at least d_att1)").cites("FASTSWARM §4.1.2, Eq. 6 (value ours)")
            .on_device();
        t.add("has_fixed_centre", T::Bool, &C::has_fixed_centre).implied()
            .says("E_cos pulls to a fixed point, not the swarm's mean (scenario files: set when \"centre\" is given)")
            .cites("FASTSWARM §5.1.1 (\"unchanged swarm centre\"; ours)")
            .same_in_every_world("the host uses it once for every world");
        t.add("centre", T::Vec3, &C::fixed_centre).c("fixed_centre").in("m")
            .says("the fixed point E_cos pulls towards; not given: the swarm's mean position")
            .cites("FASTSWARM §4.1.2, Eq. 7; §5.1.1");
        t.add("span", T::UInt32, &C::span).range(0, 1024)
            .says("neighbouring speed groups searched on each side").cites("FASTSWARM §5.2.1 (reduced search; value ours)")
            .on_device()
            .same_in_every_world("it selects the kernel (the candidates per agent, the keep-out test)");
        t.add("accel_time", T::Float, &C::accel_time).non_negative().in("s")
            .says("scale of E_amag, the acceleration magnitudes' difference, per data frame; 0: the dataset's frame time")
            .cites("FASTSWARM §4.2.1, Eq. 10 (units ours, docs/energy-model.md)")
            .same_in_every_world("the host uses it once for every world");
        t.add("danger_horizon", T::Float, &C::danger_horizon).non_negative().in("s")
            .says("look-ahead of the startled prediction").cites("FASTSWARM §4.2.2, Eq. 12 (ours)").on_device();
        t.include("noise.", noise_param_table(), &C::noise, ParamTable::Block::Own);
        t.add("keypoints_closed", T::Bool, &C::keypoints_closed)
            .says("the keypoint curve is a loop").cites("FASTSWARM §5.1.2").on_device();
        t.add("bidirectional", T::Bool, &C::bidirectional)
            .says("odd agent ids traverse the keypoint curve backwards").cites("FASTSWARM §5.1.2 (a bidirectional curve)")
            .same_in_every_world("the host uses it once for every world");
        t.add("keypoint_reach", T::Float, &C::keypoint_reach).positive().in("m")
            .says("a keypoint counts as reached within this distance").cites("FASTSWARM §4.4, Eq. 15 (value ours)")
            .on_device();
        t.add("keep_out", T::Bool, &C::keep_out)
            .says("a velocity that would bring an agent within a startling stimulus' d_danger is chosen only when every one would")
            .cites("ours (docs/energy-model.md)")
            .same_in_every_world("it selects the kernel (the candidates per agent, the keep-out test)");
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl

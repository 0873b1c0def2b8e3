// The noise parameters (NoiseConfig) as one table (params/param_table.hpp);
// every model with a noise includes it under "noise.".  The rows marked
// on_device() are the first slots of the noise's own parameter block
// (NoiseField::write_block appends what it derives from them).
#include "fields/noise_field.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

const ParamTable& noise_param_table() {
    static const ParamTable table = [] {
        using C = NoiseConfig;
        using T = ParamType;
        ParamTable t("noise", "NoiseConfig");
        t.add("type", T::Enum, &C::type).on_device().names({"curl", "perlin", "white", "gaussian"})
            .says("the noise function").cites("noise paper §4.2.1; curl: curl-noise paper §4, Eq. 1-3")
            .same_in_every_world("it selects the noise kernel");
        t.add("scale", T::Float, &C::scale).on_device().positive().in("m")
            .says("feature size of the noise").cites("curl-noise paper Table 1");
        t.add("gain", T::Float, &C::gain).on_device().non_negative().in("m/s")
            .says("speed the noise gives (its amplitude)").cites("curl-noise paper Table 1");
        t.add("seed", T::UInt64, &C::seed).says("seeds the three potentials and the random draws").cites("ours");
        t.add("time_scale", T::Float, &C::time_scale).non_negative().in("s")
            .says("> 0: the field varies in time (4D noise), seconds per noise unit; 0: static").cites("ours");
        t.add("boundary_distance", T::Float, &C::boundary_distance).on_device().positive().in("m")
            .says("d0: distance over which the noise ramps down at boundaries").cites("curl-noise paper §4, Eq. 3");
        t.add("domain_walls", T::Bool, &C::domain_walls)
            .says("the region box is an extended boundary that keeps insects in").cites("curl-noise paper §4");
        t.add("region_min", T::Vec3, &C::region_min).in("m")
            .says("walls and bake region, low corner; all zero: the swarm's domain").cites("ours");
        t.add("region_max", T::Vec3, &C::region_max).in("m")
            .says("walls and bake region, high corner").cites("ours");
        t.add("baked", T::Bool, &C::baked)
            .says("bake onto a grid over the region, then sample trilinearly (curl, perlin; static)").cites("ours")
            .same_in_every_world("it selects the noise kernel");
        t.add("bake_resolution", T::UInt3, &C::bake_resolution).range(2, 4096)
            .says("grid nodes per axis of the bake").cites("ours")
            .same_in_every_world("it selects the noise kernel");
        t.add("finite_difference", T::Bool, &C::finite_difference)
            .says("curl by central differences (for checking)").cites("ours")
            .same_in_every_world("it selects the noise kernel");
        t.add("fd_step", T::Float, &C::fd_step).on_device().non_negative().in("m")
            .says("finite-difference step; 0: scale / 100").cites("ours");
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl

// Scenario files: parsed and validated by host/scenario, made into a swarm
// by make_swarm.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "capi_common.hpp"
#include "models/model_spec.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/scenario.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

HandleRegistry<Scenario>& scenarios() {
    static auto* registry = new HandleRegistry<Scenario>(0x5C, "scenario");
    return *registry;
}

template <size_t N>
void copy_text(char (&dst)[N], const std::string& src) {
    const size_t n = std::min(src.size(), N - 1);
    std::memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

// Both world-swarm creators: world_domains NULL is the scenario's domain in
// every world, else 6 floats a world (min xyz, max xyz).
void create_world_swarm(const char* fn, swcl_scenario scenario, swcl_context context, uint32_t worlds,
                        const uint64_t* world_seeds, const float* world_domains, swcl_swarm* out) {
    check_out(out, "out");
    require(worlds > 0, std::string(fn) + ": worlds must be >= 1");
    auto s = scenarios().get(scenario.id);
    auto ctx = contexts().get(context.id);
    std::vector<uint64_t> seeds;
    if (world_seeds) seeds.assign(world_seeds, world_seeds + worlds);
    std::vector<Domain> domains;
    if (world_domains) {
        domains.resize(worlds);
        for (uint32_t k = 0; k < worlds; ++k)
            for (int a = 0; a < 3; ++a) {
                domains[k].min[a] = world_domains[6 * size_t(k) + a];
                domains[k].max[a] = world_domains[6 * size_t(k) + 3 + a];
            }
    }
    out->id = swarms().add(make_swarm(ctx, *s, worlds, seeds, domains));
}

}  // namespace

extern "C" {

swcl_status swcl_scenario_load(const char* path, swcl_scenario* out) {
    return guarded(__func__, [&] {
        require(path != nullptr, "path is NULL");
        check_out(out, "out");
        out->id = scenarios().add(std::make_shared<Scenario>(load_scenario(path)));
    });
}

swcl_status swcl_scenario_parse(const char* text, size_t length, swcl_scenario* out) {
    return guarded(__func__, [&] {
        require(text != nullptr || length == 0, "text is NULL");
        check_out(out, "out");
        out->id = scenarios().add(std::make_shared<Scenario>(parse_scenario(std::string(text ? text : "", length))));
    });
}

swcl_status swcl_scenario_destroy(swcl_scenario scenario) {
    return guarded(__func__, [&] { scenarios().remove(scenario.id); });
}

swcl_status swcl_scenario_get_info(swcl_scenario scenario, swcl_scenario_info* out) {
    return guarded(__func__, [&] {
        check_struct_size(out, sizeof(swcl_scenario_info), "out");
        auto s = scenarios().get(scenario.id);
        swcl_scenario_info info;
        std::memset(&info, 0, sizeof(info));
        info.struct_size = sizeof(info);
        info.agents = s->swarm.agent_count;
        info.steps = s->steps;
        info.output_every = s->output_every;
        info.output_formats = s->output_formats;
        info.dt = s->swarm.dt;
        info.seed = s->swarm.seed;
        copy_text(info.name, s->name);
        copy_text(info.output_dir, s->output_dir);
        copy_text(info.model, model_name(s->model));
        info.min_distance = model_min_distance(s->model);
        *out = info;
    });
}

swcl_status swcl_scenario_create_swarm(swcl_scenario scenario, swcl_context context, swcl_swarm* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        auto s = scenarios().get(scenario.id);
        auto ctx = contexts().get(context.id);
        auto swarm = make_swarm(ctx, *s);
        out->id = swarms().add(std::move(swarm));
    });
}

swcl_status swcl_scenario_create_world_swarm(swcl_scenario scenario, swcl_context context, uint32_t worlds,
                                             const uint64_t* world_seeds, swcl_swarm* out) {
    return guarded(__func__, [&] { create_world_swarm(__func__, scenario, context, worlds, world_seeds, nullptr, out); });
}

swcl_status swcl_scenario_create_world_swarm_in_domains(swcl_scenario scenario, swcl_context context, uint32_t worlds,
                                                        const uint64_t* world_seeds, const float* world_domains,
                                                        swcl_swarm* out) {
    return guarded(__func__,
                   [&] { create_world_swarm(__func__, scenario, context, worlds, world_seeds, world_domains, out); });
}

}  // extern "C"

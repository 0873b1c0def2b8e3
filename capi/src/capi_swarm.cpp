// Swarms: creation, state transfer, stepping, the model slot, step
// statistics and neighbour queries.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>
#include <mutex>
#include <optional>

#include "capi_common.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

// By reference: a by-value copy would load the enum before the range check.
Attribute attribute_of(const swcl_attribute& a) {
    const uint32_t bits = enum_bits(a);  // a C caller's value may be any int
    switch (bits) {
        case SWCL_ATTRIBUTE_POSITION: return Attribute::Position;
        case SWCL_ATTRIBUTE_VELOCITY: return Attribute::Velocity;
        default: fail(Status::InvalidArgument, "unknown attribute " + std::to_string(bits));
    }
}

}  // namespace

extern "C" {

swcl_swarm_desc swcl_swarm_desc_default(void) {
    swcl_swarm_desc d;
    std::memset(&d, 0, sizeof(d));
    d.struct_size = sizeof(d);
    d.capacity = 1024;
    d.agent_count = 0;
    d.seed = 0;
    for (int a = 0; a < 3; ++a) {
        d.domain_min[a] = -1.0f;
        d.domain_max[a] = 1.0f;
    }
    d.interaction_radius = 0.1f;
    d.dt = 1.0f / 60.0f;
    d.worlds = 1;
    d.world_seeds = nullptr;
    d.world_domains = nullptr;
    return d;
}

swcl_status swcl_swarm_create(swcl_context context, const swcl_swarm_desc* desc, swcl_swarm* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, offsetof(swcl_swarm_desc, worlds), "desc");  // the first version's size
        check_out(out, "out");
        auto ctx = contexts().get(context.id);
        SwarmConfig c;
        c.capacity = desc->capacity;
        c.agent_count = desc->agent_count;
        c.seed = desc->seed;
        for (int a = 0; a < 3; ++a) {
            c.domain_min[a] = desc->domain_min[a];
            c.domain_max[a] = desc->domain_max[a];
        }
        c.interaction_radius = desc->interaction_radius;
        c.dt = desc->dt;
        if (desc->struct_size >= offsetof(swcl_swarm_desc, world_seeds) + sizeof(desc->world_seeds)) {
            c.worlds = desc->worlds;
            require(c.worlds > 0, "swcl_swarm_desc.worlds must be >= 1 (1: one swarm)");
            if (desc->world_seeds) c.world_seeds.assign(desc->world_seeds, desc->world_seeds + c.worlds);
        }
        if (desc->struct_size >= offsetof(swcl_swarm_desc, world_domains) + sizeof(desc->world_domains) &&
            desc->world_domains) {
            c.world_domains.resize(c.worlds);
            for (uint32_t k = 0; k < c.worlds; ++k)
                for (int a = 0; a < 3; ++a) {
                    c.world_domains[k].min[a] = desc->world_domains[6 * size_t(k) + a];
                    c.world_domains[k].max[a] = desc->world_domains[6 * size_t(k) + 3 + a];
                }
        }
        out->id = swarms().add(std::make_shared<Swarm>(std::move(ctx), c));
    });
}

swcl_status swcl_swarm_destroy(swcl_swarm swarm) {
    return guarded(__func__, [&] { swarms().remove(swarm.id); });
}

swcl_status swcl_swarm_agent_count(swcl_swarm swarm, uint32_t* out_count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out_count, "out_count");
        *out_count = s.agent_count();
    });
}

swcl_status swcl_swarm_worlds(swcl_swarm swarm, uint32_t* out_worlds) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out_worlds, "out_worlds");
        *out_worlds = s.worlds();
    });
}

swcl_status swcl_swarm_world_domains(swcl_swarm swarm, float* out, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out, "out");
        require(count == s.worlds(), "swcl_swarm_world_domains: count is " + std::to_string(count) +
                                         " but the swarm has " + std::to_string(s.worlds()) + " worlds");
        for (uint32_t k = 0; k < s.worlds(); ++k)
            for (int a = 0; a < 3; ++a) {
                out[6 * size_t(k) + a] = s.world_domain(k).min[a];
                out[6 * size_t(k) + 3 + a] = s.world_domain(k).max[a];
            }
    });
}

swcl_status swcl_swarm_step_count(swcl_swarm swarm, uint64_t* out_steps) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out_steps, "out_steps");
        *out_steps = s.step_count();
    });
}

swcl_status swcl_swarm_write(swcl_swarm swarm, swcl_attribute attribute, const float* src, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.write(attribute_of(attribute), src, count); });
}

swcl_status swcl_swarm_read(swcl_swarm swarm, swcl_attribute attribute, float* dst, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.read(attribute_of(attribute), dst, count); });
}

swcl_status swcl_swarm_step(swcl_swarm swarm, uint32_t steps) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.step(steps); });
}

swcl_status swcl_swarm_step_frames(swcl_swarm swarm, uint32_t frames, uint32_t every, float* dst, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.step_frames(frames, every, dst, count); });
}

swcl_status swcl_swarm_neighbor_count(swcl_swarm swarm, float radius, uint32_t* out_counts, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.neighbor_count(radius, out_counts, count); });
}

swcl_status swcl_swarm_nearest_neighbor(swcl_swarm swarm, float* out_distances, uint32_t* out_ids,
                                        size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.nearest_neighbor(out_distances, out_ids, count); });
}

swcl_status swcl_swarm_neighbor_lists(swcl_swarm swarm, float radius, uint32_t max_neighbors, uint32_t* out_ids,
                                      uint32_t* out_counts, size_t count, uint32_t* out_truncated) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        const uint32_t truncated = s.neighbor_lists(radius, max_neighbors, out_ids, out_counts, count);
        if (out_truncated) *out_truncated = truncated;
    });
}

swcl_status swcl_swarm_clear_model(swcl_swarm swarm) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.set_behavior(nullptr); });
}

swcl_status swcl_swarm_take_step_stats(swcl_swarm swarm, swcl_step_stats* out) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(out, sizeof(swcl_step_stats), "out");
        swcl_step_stats r;
        std::memset(&r, 0, sizeof(r));
        r.struct_size = sizeof(r);
        r.agents = s.agent_count();
        const std::optional<StepStats> st = s.take_step_stats();
        if (st) {
            r.mde_moved_last = st->mde_moved_last;
            r.mde_moved_total = st->mde_moved_total;
            r.steps = st->steps;
        }
        *out = r;
    });
}

swcl_status swcl_swarm_take_world_step_stats(swcl_swarm swarm, swcl_step_stats* out, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(out != nullptr, "swcl_swarm_take_world_step_stats: out is NULL");
        require(count == s.worlds(), "swcl_swarm_take_world_step_stats: count is " + std::to_string(count) +
                                         " but the swarm has " + std::to_string(s.worlds()) + " worlds");
        for (size_t k = 0; k < count; ++k) check_struct_size(&out[k], sizeof(swcl_step_stats), "out[k]");
        const std::optional<std::vector<StepStats>> st = s.take_world_step_stats();
        for (size_t k = 0; k < count; ++k) {
            swcl_step_stats r;
            std::memset(&r, 0, sizeof(r));
            r.struct_size = sizeof(r);
            r.agents = s.agent_count();
            if (st) {
                r.mde_moved_last = (*st)[k].mde_moved_last;
                r.mde_moved_total = (*st)[k].mde_moved_total;
                r.steps = (*st)[k].steps;
            }
            out[k] = r;
        }
    });
}

swcl_status swcl_swarm_set_world_param(swcl_swarm swarm, const char* name, const double* values, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(name != nullptr, "swcl_swarm_set_world_param: name is NULL");
        require(s.behavior() != nullptr, "swcl_swarm_set_world_param: the swarm has no model");
        s.behavior()->set_world_param(s, name, values, count);
    });
}

swcl_status swcl_swarm_get_world_param(swcl_swarm swarm, const char* name, double* out_values, size_t count,
                                       size_t* out_count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(name != nullptr, "swcl_swarm_get_world_param: name is NULL");
        require(s.behavior() != nullptr, "swcl_swarm_get_world_param: the swarm has no model");
        const std::vector<double> v = s.behavior()->world_param(name);
        if (out_count) *out_count = v.size();
        if (out_values == nullptr && count == 0) return;
        require(out_values != nullptr, "swcl_swarm_get_world_param: out_values is NULL");
        require(count == v.size(), "swcl_swarm_get_world_param: count is " + std::to_string(count) + " but '" +
                                       std::string(name) + "' has " + std::to_string(v.size()) + " values (" +
                                       std::to_string(s.worlds()) + " worlds)");
        std::copy(v.begin(), v.end(), out_values);
    });
}

}  // extern "C"

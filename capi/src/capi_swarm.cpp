// Swarms: creation, state transfer, stepping, the model slot, step
// statistics and neighbour queries.
#include <cstring>
#include <mutex>
#include <optional>

#include "capi_common.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

Attribute attribute_of(swcl_attribute a) {
    switch (a) {
        case SWCL_ATTRIBUTE_POSITION: return Attribute::Position;
        case SWCL_ATTRIBUTE_VELOCITY: return Attribute::Velocity;
        case SWCL_ATTRIBUTE_MAX_ENUM: break;  // not an attribute
    }
    fail(Status::InvalidArgument, "unknown attribute " + std::to_string(int(a)));
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
    return d;
}

swcl_status swcl_swarm_create(swcl_context context, const swcl_swarm_desc* desc, swcl_swarm* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, sizeof(swcl_swarm_desc), "desc");
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

}  // extern "C"

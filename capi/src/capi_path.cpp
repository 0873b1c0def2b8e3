// C entry points of the path model (host/models/path_model.*).
#include <cstring>
#include <string>

#include <cmath>

#include "capi_common.hpp"
#include "capi_noise.hpp"
#include "capi_obstacle.hpp"
#include "models/path_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

std::vector<Goal> goals_from(const swcl_goal* goals, uint32_t count, const std::string& what) {
    require(goals != nullptr || count == 0, what + " is NULL");
    std::vector<Goal> out;
    for (uint32_t i = 0; i < count; ++i) {
        const swcl_goal& g = goals[i];
        Goal o;
        const uint32_t type = enum_bits(g.type);  // a C caller's value may be any int
        switch (type) {
            case SWCL_GOAL_POINT: o.kind = Goal::Kind::Point; break;
            case SWCL_GOAL_SPHERE: o.kind = Goal::Kind::Sphere; break;
            case SWCL_GOAL_BOX: o.kind = Goal::Kind::Box; break;
            default:
                fail(Status::InvalidArgument,
                     what + "[" + std::to_string(i) + "]: unknown goal type " + c_enum_text(type));
        }
        for (int a = 0; a < 3; ++a) {
            o.center[a] = g.center[a];
            o.half_extents[a] = g.half_extents[a];
        }
        o.radius = g.radius;
        out.push_back(o);
    }
    return out;
}

}  // namespace

extern "C" {

swcl_path_model_desc swcl_path_model_desc_default(void) {
    swcl_path_model_desc d;
    std::memset(&d, 0, sizeof(d));
    const PathModelConfig c;
    d.struct_size = sizeof(d);
    d.noise = swcl_noise_desc_default();
    for (int a = 0; a < 3; ++a) d.resolution[a] = c.resolution[a];
    d.cost_a = float(c.weights.A);
    d.cost_b = float(c.weights.B);
    d.second_order = c.second_order ? 1 : 0;
    d.speed = c.speed;
    d.goal_falloff = c.goal_falloff;
    d.min_distance = c.min_distance;
    return d;
}

swcl_status swcl_swarm_path_set_model(swcl_swarm swarm, const swcl_path_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(desc, sizeof(swcl_path_model_desc), "desc");
        check_struct_size(&desc->noise, sizeof(swcl_noise_desc), "desc->noise");
        PathModelConfig c;
        c.noise = noise_config_from(desc->noise);
        require(desc->obstacles != nullptr || desc->obstacle_count == 0, "desc->obstacles is NULL");
        for (uint32_t i = 0; i < desc->obstacle_count; ++i)
            c.obstacles.push_back(obstacle_mesh(desc->obstacles[i], "obstacles[" + std::to_string(i) + "]"));
        for (int a = 0; a < 3; ++a) {
            c.grid_min[a] = desc->grid_min[a];
            c.grid_max[a] = desc->grid_max[a];
            c.resolution[a] = desc->resolution[a];
            c.has_grid_box = c.has_grid_box || desc->grid_min[a] != 0.0f || desc->grid_max[a] != 0.0f;
        }
        c.weights.A = desc->cost_a;
        c.weights.B = desc->cost_b;
        c.second_order = desc->second_order != 0;
        c.speed = desc->speed;
        c.goal_falloff = desc->goal_falloff;
        c.min_distance = desc->min_distance;
        if (desc->group_count > 0) {
            require(desc->groups != nullptr, "desc->groups is NULL");
            for (uint32_t g = 0; g < desc->group_count; ++g)
                c.groups.push_back({desc->groups[g].agents,
                                    goals_from(desc->groups[g].goals, desc->groups[g].goal_count,
                                               "groups[" + std::to_string(g) + "].goals")});
        } else {
            c.groups.push_back({0, goals_from(desc->goals, desc->goal_count, "desc->goals")});
        }
        s.set_behavior(std::make_shared<PathModel>(s, std::move(c)));
    });
}

swcl_status swcl_swarm_path_set_goals(swcl_swarm swarm, uint32_t group, const swcl_goal* goals, uint32_t goal_count,
                                      double* out_seconds) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        auto* model = dynamic_cast<PathModel*>(s.behavior());
        require(model != nullptr, "the swarm has no path model (swcl_swarm_path_set_model)");
        const double t = model->set_goals(group, goals_from(goals, goal_count, "goals"));
        if (out_seconds) *out_seconds = t;
    });
}

swcl_status swcl_swarm_path_get_info(swcl_swarm swarm, swcl_path_info* out) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(out, sizeof(swcl_path_info), "out");
        auto* model = dynamic_cast<PathModel*>(s.behavior());
        require(model != nullptr, "the swarm has no path model (swcl_swarm_path_set_model)");
        swcl_path_info r;
        std::memset(&r, 0, sizeof(r));
        r.struct_size = sizeof(r);
        const Grid3& g = model->grid();
        for (int a = 0; a < 3; ++a) {
            r.grid[a] = g.dims[a];
            r.grid_min[a] = float(g.origin[a]);
        }
        r.cell = float(g.h);
        r.preprocess_seconds = model->preprocess_seconds();
        r.groups = uint32_t(model->config().groups.size());
        r.recomputes = model->recomputes();
        r.recompute_seconds = model->recompute_seconds();
        *out = r;
    });
}

}  // extern "C"

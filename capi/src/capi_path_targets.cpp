// C entry points of the path model's chasing targets and lamp (curl-noise
// paper §7; host/models/path_model.*).
#include <cmath>
#include <cstring>
#include <string>

#include "capi_common.hpp"
#include "models/path_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

PathModel& path_model_of(Swarm& s) {
    auto* model = dynamic_cast<PathModel*>(s.behavior());
    require(model != nullptr, "the swarm has no path model (swcl_swarm_path_set_model)");
    return *model;
}

}  // namespace

extern "C" {

swcl_status swcl_swarm_path_add_target(swcl_swarm swarm, const swcl_path_target* target, uint32_t* out_index) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(target != nullptr, "target is NULL");
        PathModel& model = path_model_of(s);
        PathTarget t;
        t.group = target->group;
        t.radius = target->radius;
        for (int a = 0; a < 3; ++a) t.center[a] = target->center[a];
        const uint32_t index = model.add_target(t);
        if (out_index) *out_index = index;
    });
}

swcl_status swcl_swarm_path_set_target(swcl_swarm swarm, uint32_t index, const float center[3], double* out_seconds) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(center != nullptr, "center is NULL");
        const double t = path_model_of(s).set_target(index, {center[0], center[1], center[2]});
        if (out_seconds) *out_seconds = t;
    });
}

swcl_status swcl_swarm_path_get_target(swcl_swarm swarm, uint32_t index, swcl_path_target* out) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out, "out");
        const auto& targets = path_model_of(s).config().targets;
        require(index < targets.size(), "path model: target " + std::to_string(index) + " does not exist (" +
                                            std::to_string(targets.size()) + " targets)");
        swcl_path_target r;
        std::memset(&r, 0, sizeof(r));
        r.group = targets[index].group;
        r.radius = targets[index].radius;
        for (int a = 0; a < 3; ++a) r.center[a] = targets[index].center[a];
        *out = r;
    });
}

swcl_status swcl_swarm_path_target_count(swcl_swarm swarm, uint32_t* out_count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out_count, "out_count");
        *out_count = uint32_t(path_model_of(s).config().targets.size());
    });
}

swcl_path_lamp swcl_path_lamp_default(void) {
    swcl_path_lamp d;
    std::memset(&d, 0, sizeof(d));
    const PathLamp l;
    d.struct_size = sizeof(d);
    d.enabled = l.enabled ? 1 : 0;
    d.radius = l.radius;
    d.probability = l.probability;
    d.speed = l.speed;
    d.angle = l.angle;
    d.keep_out = l.keep_out;
    return d;
}

swcl_status swcl_swarm_path_set_lamp(swcl_swarm swarm, const swcl_path_lamp* lamp) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(lamp, sizeof(swcl_path_lamp), "lamp");
        PathModel& model = path_model_of(s);
        PathLamp l;
        l.enabled = lamp->enabled != 0;
        for (int a = 0; a < 3; ++a) l.center[a] = lamp->center[a];
        l.radius = lamp->radius;
        l.probability = lamp->probability;
        l.speed = lamp->speed;
        l.angle = lamp->angle;
        l.keep_out = lamp->keep_out;
        model.set_lamp(l);
    });
}

}  // extern "C"

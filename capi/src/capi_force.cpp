// The force model (shape-constrained flying insects): descriptor, keyframes,
// path, targets.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "capi_common.hpp"
#include "capi_obstacle.hpp"
#include "models/force_model.hpp"
#include "shapes/keyframe_spec.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

std::vector<Keyframe> keyframes_from(const swcl_keyframe* kf, uint32_t count) {
    require(kf != nullptr || count == 0, "keyframes is NULL but keyframe_count is " + std::to_string(count));
    std::vector<Keyframe> out;
    for (uint32_t k = 0; k < count; ++k) {
        const swcl_keyframe& f = kf[k];
        const std::string name = "keyframes[" + std::to_string(k) + "]";
        TriangleMesh mesh;
        try {
            // Built by shapes/keyframe_spec as the scenario files' keyframes are.
            KeyframeSpec spec;
            if (f.shape) {
                spec.source = KeyframeSpec::Source::Shape;
                spec.name = f.shape;
            } else {
                require(f.vertices && f.triangles,
                        "needs a shape name or vertices and triangles (NULL given)");
                spec.source = KeyframeSpec::Source::Mesh;
                spec.vertices = f.vertices;
                spec.vertex_count = f.vertex_count;
                spec.triangles = f.triangles;
                spec.triangle_count = f.triangle_count;
            }
            const TriangleMesh source = keyframe_source_mesh(spec);
            const float s = f.scale == 0.0f ? 1.0f : f.scale;
            require(std::isfinite(s) && s > 0.0f, "scale must be > 0 (0: 1)");
            for (float o : f.offset) require(std::isfinite(o), "offset must be finite");
            spec.scale = s;
            spec.offset = {f.offset[0], f.offset[1], f.offset[2]};
            mesh = placed_keyframe_mesh(spec, source);
        } catch (const Error& e) {
            fail(e.status(), name + ": " + e.what());
        }
        out.push_back({f.frame, std::move(mesh)});
    }
    return out;
}

std::vector<float> path_from(const float* points, uint32_t count) {
    require(points != nullptr || count == 0, "path is NULL but path_point_count is " + std::to_string(count));
    return std::vector<float>(points, points + 3 * size_t(count));
}

ForceModel& force_model_of(Swarm& s) {
    auto* m = dynamic_cast<ForceModel*>(s.behavior());
    require(m != nullptr, "the swarm has no force model (swcl_swarm_force_set_model first)");
    return *m;
}

// A new model from `c`, replacing the old only when it builds.
void install(Swarm& s, ForceModelConfig c) { s.set_behavior(std::make_shared<ForceModel>(s, std::move(c))); }

}  // namespace

extern "C" {

swcl_force_model_desc swcl_force_model_desc_default(void) {
    swcl_force_model_desc d;
    std::memset(&d, 0, sizeof(d));
    const ForceModelConfig c;
    d.struct_size = sizeof(d);
    d.r_rep = c.r_rep;
    d.r_ali = c.r_ali;
    d.r_att = c.r_att;
    d.w_rep = c.w_rep;
    d.w_ali = c.w_ali;
    d.w_att = c.w_att;
    d.w_dis = c.w_dis;
    d.w_con = c.w_con;
    d.omega = c.omega;
    d.neighbor_k = c.neighbor_k;
    d.distance_scale = c.distance_scale;
    d.neighbor_sample = c.neighbor_sample;
    d.eta = c.noise.gain * c.noise.scale;
    d.rho = c.noise.scale;
    d.noise_seed = c.noise.seed;
    d.alpha = c.alpha;
    d.max_speed = c.max_speed;
    d.cruise_speed = c.cruise_speed;
    d.speed_relaxation = c.speed_relaxation;
    d.preferred_speed = c.preferred_speed;
    d.speed_spread = c.speed_spread;
    d.min_distance = c.min_distance;
    d.min_spacing = c.min_spacing;
    d.assignment = SWCL_ASSIGN_NEAREST;
    d.sample_seed = c.sample_seed;
    d.obstacle_range = c.obstacle_range;
    d.path_orient = c.path_orient ? 1u : 0u;
    return d;
}

swcl_status swcl_swarm_force_set_model(swcl_swarm swarm, const swcl_force_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        // The first version of the descriptor ended before path_orient.
        check_struct_size(desc, offsetof(swcl_force_model_desc, path_orient), "desc");
        const swcl_force_model_desc& d = *desc;
        ForceModelConfig c;
        c.r_rep = d.r_rep;
        c.r_ali = d.r_ali;
        c.r_att = d.r_att;
        c.w_rep = d.w_rep;
        c.w_ali = d.w_ali;
        c.w_att = d.w_att;
        c.w_dis = d.w_dis;
        c.w_con = d.w_con;
        c.omega = d.omega;
        c.neighbor_k = d.neighbor_k;
        c.distance_scale = d.distance_scale;
        c.neighbor_sample = d.neighbor_sample;
        require(std::isfinite(d.rho) && d.rho > 0.0f, "force model rho must be > 0 (Eq. 4)");
        require(std::isfinite(d.eta) && d.eta >= 0.0f, "force model eta must be >= 0 (Eq. 4)");
        c.noise.scale = d.rho;
        c.noise.gain = d.eta / d.rho;  // Eq. 4 in metres (ForceModelConfig::noise)
        c.noise.seed = d.noise_seed;
        c.alpha = d.alpha;
        c.max_speed = d.max_speed;
        c.cruise_speed = d.cruise_speed;
        c.min_distance = d.min_distance;
        c.min_spacing = d.min_spacing;
        const uint32_t assignment = enum_bits(d.assignment);  // a C caller's value may be any int
        require(assignment == SWCL_ASSIGN_NEAREST || assignment == SWCL_ASSIGN_CURVE,
                "force model assignment (" + c_enum_text(assignment) +
                    ") must be SWCL_ASSIGN_NEAREST or SWCL_ASSIGN_CURVE");
        c.assignment = assignment == SWCL_ASSIGN_CURVE ? Assignment::Curve : Assignment::Nearest;
        c.sample_seed = d.sample_seed;
        c.keyframes = keyframes_from(d.keyframes, d.keyframe_count);
        c.keyframe_period = d.keyframe_period;
        c.path = path_from(d.path, d.path_point_count);
        c.path_speed = d.path_speed;
        require(d.obstacles != nullptr || d.obstacle_count == 0,
                "obstacles is NULL but obstacle_count is " + std::to_string(d.obstacle_count));
        for (uint32_t i = 0; i < d.obstacle_count; ++i)
            c.obstacles.push_back(
                obstacle_boundary(d.obstacles[i], "force model obstacles[" + std::to_string(i) + "]", false));
        c.obstacle_range = d.obstacle_range;
        if (d.struct_size >= offsetof(swcl_force_model_desc, path_orient) + sizeof(d.path_orient)) {
            require(d.path_orient <= 1u, "force model path_orient must be 0 or 1");
            c.path_orient = d.path_orient != 0;
        }
        // Mesh obstacles came after path_orient (older callers: none).
        if (d.struct_size >= offsetof(swcl_force_model_desc, mesh_cell) + sizeof(d.mesh_cell)) {
            require(d.mesh_obstacles != nullptr || d.mesh_obstacle_count == 0,
                    "mesh_obstacles is NULL but mesh_obstacle_count is " + std::to_string(d.mesh_obstacle_count));
            for (uint32_t i = 0; i < d.mesh_obstacle_count; ++i)
                c.mesh_obstacles.push_back(
                    obstacle_mesh(d.mesh_obstacles[i], "force model mesh_obstacles[" + std::to_string(i) + "]"));
            c.mesh_cell = d.mesh_cell;
        }
        // The speed relaxation came after the mesh obstacles (older callers: off).
        if (d.struct_size >= offsetof(swcl_force_model_desc, preferred_speed) + sizeof(d.preferred_speed)) {
            c.speed_relaxation = d.speed_relaxation;
            c.preferred_speed = d.preferred_speed;
        }
        if (d.struct_size >= offsetof(swcl_force_model_desc, speed_spread) + sizeof(d.speed_spread))
            c.speed_spread = d.speed_spread;
        install(s, std::move(c));
    });
}

swcl_status swcl_swarm_force_set_keyframes(swcl_swarm swarm, const swcl_keyframe* keyframes, uint32_t count,
                                           uint32_t period) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        ForceModelConfig c = force_model_of(s).config();
        c.keyframes = keyframes_from(keyframes, count);
        c.keyframe_period = period;
        install(s, std::move(c));
    });
}

swcl_status swcl_swarm_force_set_path(swcl_swarm swarm, const float* points, uint32_t count, float speed) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        ForceModelConfig c = force_model_of(s).config();
        c.path = path_from(points, count);
        c.path_speed = speed;
        install(s, std::move(c));
    });
}

swcl_status swcl_swarm_force_get_targets(swcl_swarm swarm, float* out_xyz, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_out(out_xyz, "out_xyz");
        const size_t all = size_t(s.agent_count()) * s.worlds();  // world by world
        require(count <= all, "count " + std::to_string(count) + " exceeds the agent count " + std::to_string(all) +
                                  (s.worlds() > 1 ? " (all its worlds)" : ""));
        ForceModel& m = force_model_of(s);
        const ShapeTargets* t = m.current_targets();
        require(t != nullptr && m.target_of().size() == all,
                "no keyframe is active yet (targets appear at the first keyframe's frame, after a step)");
        const std::vector<float> placed = m.placed(t->points, s.step_count(), s.config().dt);
        for (size_t a = 0; a < count; ++a)
            for (int k = 0; k < 3; ++k) out_xyz[3 * a + k] = placed[3 * size_t(m.target_of()[a]) + k];
    });
}

}  // extern "C"

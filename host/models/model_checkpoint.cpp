#include "models/model_checkpoint.hpp"

#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "models/energy_model.hpp"
#include "params/param_table.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

// One description of each struct's fields serves both directions (the
// fields() overloads below): Save writes them in order, Load reads them back
// in the same order.  A field added to a config must be added to its
// fields() (the size checks at the end of this file stop the build until it is).
struct Save {
    ByteWriter& w;
    void operator()(const float& v) { w.f32(v); }
    void operator()(const double& v) { w.f64(v); }
    void operator()(const uint32_t& v) { w.u32(v); }
    void operator()(const uint64_t& v) { w.u64(v); }
    void operator()(const bool& v) { w.boolean(v); }
    template <typename E>
    void enumeration(const E& v, int /*max*/) {
        w.u32(uint32_t(v));
    }
    template <typename T, size_t N>
    void operator()(const std::array<T, N>& a) {
        for (const T& v : a) (*this)(v);
    }
    template <typename T>
    void operator()(const std::vector<T>& v) {
        w.u64(v.size());
        for (const T& x : v) (*this)(x);
    }
    template <typename T, typename = decltype(fields(std::declval<Save&>(), std::declval<T&>()))>
    void operator()(const T& s) {
        fields(*this, const_cast<T&>(s));
    }
};

struct Load {
    ByteReader& r;
    void operator()(float& v) { v = r.f32(); }
    void operator()(double& v) { v = r.f64(); }
    void operator()(uint32_t& v) { v = r.u32(); }
    void operator()(uint64_t& v) { v = r.u64(); }
    void operator()(bool& v) { v = r.boolean(); }
    template <typename E>
    void enumeration(E& v, int max) {
        const uint32_t x = r.u32();
        if (x > uint32_t(max)) r.bad("an enumeration value is " + std::to_string(x) + " (at most " + std::to_string(max) + ")");
        v = E(x);
    }
    template <typename T, size_t N>
    void operator()(std::array<T, N>& a) {
        for (T& v : a) (*this)(v);
    }
    template <typename T>
    void operator()(std::vector<T>& v) {
        // Each item takes at least a byte: the count is bounded by the bytes
        // left before anything is allocated.
        const uint64_t n = r.count(std::is_arithmetic<T>::value ? sizeof(T) : 1);
        v.clear();
        v.resize(size_t(n));
        for (T& x : v) (*this)(x);
    }
    template <typename T, typename = decltype(fields(std::declval<Load&>(), std::declval<T&>()))>
    void operator()(T& s) {
        fields(*this, s);
    }
};

}  // namespace

// The fields of every struct a model descriptor holds, in file order.
template <class A>
void fields(A& a, Boundary& b) {
    a.enumeration(b.kind, 2);
    a(b.center), a(b.radius), a(b.half_extents), a(b.normal), a(b.offset);
}
template <class A>
void fields(A& a, NoiseConfig& c) {
    a.enumeration(c.type, 3);
    a(c.scale), a(c.gain), a(c.seed), a(c.time_scale), a(c.boundary_distance), a(c.domain_walls);
    a(c.region_min), a(c.region_max), a(c.boundaries), a(c.baked), a(c.bake_resolution);
    a(c.finite_difference), a(c.fd_step);
}
template <class A>
void fields(A& a, TriangleMesh& m) {
    a(m.vertices), a(m.triangles);
}
template <class A>
void fields(A& a, Goal& g) {
    a.enumeration(g.kind, 2);
    a(g.center), a(g.radius), a(g.half_extents);
}
template <class A>
void fields(A& a, CostWeights& w) {
    a(w.A), a(w.B);
}
template <class A>
void fields(A& a, PathGroup& g) {
    a(g.agents), a(g.goals);
}
template <class A>
void fields(A& a, Keyframe& k) {
    a(k.frame), a(k.mesh);
}
template <class A>
void fields(A& a, EnergyWeights& w) {
    a(w.rep), a(w.oa), a(w.cos), a(w.dir), a(w.acc), a(w.env), a(w.n), a(w.user);
}
template <class A>
void fields(A& a, Stimulus& s) {
    a.enumeration(s.kind, 1);
    a(s.position), a(s.velocity), a(s.d_danger);
}
template <class A>
void fields(A& a, PathTarget& t) {
    a(t.group), a(t.center), a(t.radius);
}
template <class A>
void fields(A& a, PathLamp& l) {
    a(l.enabled), a(l.center), a(l.radius), a(l.probability), a(l.speed), a(l.angle), a(l.keep_out);
}
template <class A>
void fields(A& a, FieldModelConfig& c) {
    a(c.noise), a(c.has_goal), a(c.goal), a(c.goal_radius), a(c.goal_speed), a(c.goal_falloff), a(c.min_distance);
}
template <class A>
void fields(A& a, PathModelConfig& c) {
    a(c.noise), a(c.obstacles), a(c.has_grid_box), a(c.grid_min), a(c.grid_max), a(c.resolution), a(c.weights);
    a(c.second_order), a(c.speed), a(c.goal_falloff), a(c.min_distance), a(c.groups), a(c.waypoints);
    a(c.waypoint_every), a(c.targets), a(c.lamp);
}
template <class A>
void fields(A& a, ForceModelConfig& c) {
    a(c.r_rep), a(c.r_ali), a(c.r_att), a(c.w_rep), a(c.w_ali), a(c.w_att), a(c.w_dis), a(c.neighbor_sample);
    a(c.w_con), a(c.omega), a(c.neighbor_k), a(c.distance_scale), a(c.alpha), a(c.max_speed), a(c.cruise_speed);
    a(c.noise), a(c.min_distance), a(c.min_spacing);
    a.enumeration(c.assignment, 1);
    a(c.sample_seed), a(c.keyframes), a(c.keyframe_period), a(c.path), a(c.path_speed), a(c.path_orient);
    a(c.obstacles), a(c.obstacle_range), a(c.mesh_obstacles), a(c.mesh_cell), a(c.terms);
}
template <class A>
void fields(A& a, EnergyModelConfig& c) {
    a(c.weights), a(c.danger_weights), a(c.rho), a(c.d_rep), a(c.d_att1), a(c.d_att2), a(c.has_fixed_centre);
    a(c.fixed_centre), a(c.span), a(c.accel_time), a(c.exact_attraction), a(c.danger_horizon), a(c.keep_out);
    a(c.noise), a(c.stimuli), a(c.keypoints), a(c.keypoints_closed), a(c.bidirectional), a(c.keypoint_reach);
}

template <class A>
void fields(A& a, RlObstacleBox& b) {
    a(b.center), a(b.half);
}

template <class A>
void fields(A& a, PolicyModelConfig& c) {
    a(c.r_sep), a(c.r_ali), a(c.r_coh), a(c.neighbor_radius), a(c.body_radius), a(c.du_max), a(c.dq_max_deg);
    a(c.u_max), a.enumeration(c.leader_mode, 2), a(c.waypoints), a(c.leader_du_max), a(c.leader_dq_max_deg);
    a(c.reach_radius), a(c.leader_position), a(c.leader_heading), a(c.leader_speed), a(c.obstacles);
}

// MODL v2: a model with a parameter table (params/param_table.hpp) writes
// its table's rows by key (so a parameter added later reads back from an
// older file as its default), then only its structured fields here.
// kTableSince: the first MODL version in which the model's descriptor is
// its table's rows (older versions: fields()).
template <class Config>
constexpr bool kHasTable = false;
template <class Config>
constexpr uint32_t kTableSince = 0;
template <>
constexpr bool kHasTable<FieldModelConfig> = true;
template <>
constexpr uint32_t kTableSince<FieldModelConfig> = 2;
inline const ParamTable& table_of(const FieldModelConfig&) { return field_param_table(); }
template <class A>
void structured_fields(A& a, FieldModelConfig& c) {
    a(c.noise.boundaries);
}
template <>
constexpr bool kHasTable<ForceModelConfig> = true;
template <>
constexpr uint32_t kTableSince<ForceModelConfig> = 3;
inline const ParamTable& table_of(const ForceModelConfig&) { return force_param_table(); }
template <class A>
void structured_fields(A& a, ForceModelConfig& c) {
    a(c.noise.boundaries), a(c.keyframes), a(c.path), a(c.obstacles), a(c.mesh_obstacles);
}
template <>
constexpr bool kHasTable<PathModelConfig> = true;
template <>
constexpr uint32_t kTableSince<PathModelConfig> = 3;
inline const ParamTable& table_of(const PathModelConfig&) { return path_param_table(); }
template <class A>
void structured_fields(A& a, PathModelConfig& c) {
    a(c.noise.boundaries), a(c.obstacles), a(c.groups), a(c.waypoints), a(c.targets);
}
// The energy model: its dataset follows the descriptor (write_model_descriptor).
template <>
constexpr bool kHasTable<EnergyModelConfig> = true;
template <>
constexpr uint32_t kTableSince<EnergyModelConfig> = 3;
inline const ParamTable& table_of(const EnergyModelConfig&) { return energy_param_table(); }
template <class A>
void structured_fields(A& a, EnergyModelConfig& c) {
    a(c.noise.boundaries), a(c.stimuli), a(c.keypoints), a(c.exact_attraction);
}
// The policy model: its weights file follows the descriptor.
template <>
constexpr bool kHasTable<PolicyModelConfig> = true;
template <>
constexpr uint32_t kTableSince<PolicyModelConfig> = 3;
inline const ParamTable& table_of(const PolicyModelConfig&) { return policy_param_table(); }
template <class A>
void structured_fields(A& a, PolicyModelConfig& c) {
    a(c.waypoints), a(c.obstacles);
}

namespace {

// The rows of `t` in `config`: u32 count, then per row its key (string),
// its type (u8, ParamType) and its components.
void write_table_params(ByteWriter& w, const ParamTable& t, void* config) {
    w.u32(uint32_t(t.params().size()));
    for (const Param& p : t.params()) {
        w.string(p.key);
        w.u8(uint8_t(p.type));
        for (int a = 0; a < p.components(); ++a) {
            switch (p.type) {
                case ParamType::Float:
                case ParamType::Vec3: w.f32(float(p.get(config, a))); break;
                case ParamType::Double: w.f64(p.get(config, a)); break;
                case ParamType::UInt32:
                case ParamType::UInt3: w.u32(uint32_t(p.get(config, a))); break;
                case ParamType::UInt64: w.u64(*static_cast<uint64_t*>(p.field(config))); break;
                case ParamType::Bool: w.boolean(p.get(config, a) != 0.0); break;
                case ParamType::Enum: w.i32(int32_t(p.get(config, a))); break;
            }
        }
    }
}

// Rows the file does not hold keep the config's defaults; an unknown key, a
// type other than the table's, a key twice or an enumeration out of range
// is a bad file.
void read_table_params(ByteReader& r, const ParamTable& t, void* config) {
    const uint32_t n = r.u32();
    std::vector<std::string> seen;
    for (uint32_t i = 0; i < n; ++i) {
        const std::string key = r.string();
        const Param* p = t.find(key);
        if (!p) r.bad("the " + t.model() + " model has no parameter '" + key + "'");
        for (const std::string& k : seen)
            if (k == key) r.bad("parameter '" + key + "' is given twice");
        seen.push_back(key);
        const uint8_t type = r.u8();
        if (type != uint8_t(p->type))
            r.bad("parameter '" + key + "' has type " + std::to_string(type) + ", the table's is " +
                  param_type_name(p->type));
        for (int a = 0; a < p->components(); ++a) {
            switch (p->type) {
                case ParamType::Float:
                case ParamType::Vec3: p->set(config, r.f32(), a); break;
                case ParamType::Double: p->set(config, r.f64(), a); break;
                case ParamType::UInt32:
                case ParamType::UInt3: p->set(config, r.u32(), a); break;
                case ParamType::UInt64: *static_cast<uint64_t*>(p->field(config)) = r.u64(); break;
                case ParamType::Bool: p->set(config, r.boolean() ? 1.0 : 0.0, a); break;
                case ParamType::Enum: {
                    const int32_t v = r.i32();
                    if (v < 0 || size_t(v) >= p->enum_names.size())
                        r.bad("parameter '" + key + "' has value " + std::to_string(v) + " (at most " +
                              std::to_string(p->enum_names.size() - 1) + ")");
                    p->set(config, v, a);
                    break;
                }
            }
        }
    }
}

}  // namespace

namespace {

// Meshes are used as they are by the models (no make_mesh on load): every
// index must name a vertex, every vertex be finite.
void check_mesh(const TriangleMesh& m, ByteReader& r) {
    for (const auto& v : m.vertices)
        for (float x : v)
            if (!std::isfinite(x)) r.bad("a mesh vertex is not finite");
    for (const auto& t : m.triangles)
        for (uint32_t i : t)
            if (i >= m.vertices.size())
                r.bad("a mesh triangle names vertex " + std::to_string(i) + " of " + std::to_string(m.vertices.size()));
}

// The fields of a config: its table's rows and its structured fields (from
// MODL version kTableSince<Config>), or every field in fields() order.
template <class Config>
void write_config(ByteWriter& out, const Config& c) {
    Save s{out};
    if constexpr (kHasTable<Config>) {
        Config& m = const_cast<Config&>(c);
        write_table_params(out, table_of(m), &m);
        structured_fields(s, m);
    } else {
        s(c);
    }
}
template <class Config>
void read_config(ByteReader& in, Config& c, uint32_t version) {
    Load l{in};
    if constexpr (kHasTable<Config>) {
        if (version >= kTableSince<Config>) {
            read_table_params(in, table_of(c), &c);
            structured_fields(l, c);
            return;
        }
    }
    l(c);  // before its table, or a model without a table: every field in fields() order
}

template <class Config>
void write_named(ByteWriter& out, const Config& c) {
    out.string(ModelTraits<Config>::name);
    write_config(out, c);
}

// Reads the descriptor of the alternative whose name is `name` (I: its
// index in ModelSpec, tried in order).
template <size_t I = 0>
CheckpointModel read_alternative(const std::string& name, ByteReader& in, uint32_t version) {
    if constexpr (I == std::variant_size_v<ModelSpec>) {
        in.bad("unknown model '" + name + "'");
    } else {
        using Config = std::variant_alternative_t<I, ModelSpec>;
        if (name != ModelTraits<Config>::name) return read_alternative<I + 1>(name, in, version);
        CheckpointModel m;
        if constexpr (std::is_same_v<Config, Ballistic>) {
            m.spec = Ballistic{};
        } else if constexpr (std::is_same_v<Config, EnergySpec>) {
            EnergySpec e;
            read_config(in, e.config, version);
            const std::string bytes = in.string();
            try {
                m.dataset = std::make_shared<const Dataset>(dataset_from_bytes(bytes));
            } catch (const Error& err) {
                in.bad(std::string("the energy model's dataset: ") + err.what());
            }
            m.spec = std::move(e);
        } else if constexpr (std::is_same_v<Config, PolicySpec>) {
            PolicySpec p;
            read_config(in, p.config, version);
            p.weights_bytes = std::make_shared<const std::string>(in.string());
            m.spec = std::move(p);
        } else {
            Config c;
            read_config(in, c, version);
            m.spec = std::move(c);
        }
        return m;
    }
}

}  // namespace

void write_model_descriptor(ByteWriter& out, const FieldModelConfig& c) { write_named(out, c); }
void write_model_descriptor(ByteWriter& out, const PathModelConfig& c) { write_named(out, c); }
void write_model_descriptor(ByteWriter& out, const ForceModelConfig& c) { write_named(out, c); }
void write_model_descriptor(ByteWriter& out, const EnergyModelConfig& c, const Dataset& d) {
    out.string(ModelTraits<EnergySpec>::name);
    write_config(out, c);
    out.string(dataset_to_bytes(d));
}
void write_model_descriptor(ByteWriter& out, const PolicyModelConfig& c, const std::string& weights) {
    out.string(ModelTraits<PolicySpec>::name);
    write_config(out, c);
    out.string(weights);
}
void write_ballistic_descriptor(ByteWriter& out) { out.string(ModelTraits<Ballistic>::name); }

CheckpointModel read_model_descriptor(ByteReader& in, uint32_t version) {
    const std::string name = in.string();
    CheckpointModel m = read_alternative(name, in, version);
    in.expect_end();
    // Meshes anywhere in the descriptor.
    if (auto* p = std::get_if<PathModelConfig>(&m.spec))
        for (const auto& mesh : p->obstacles) check_mesh(mesh, in);
    if (auto* f = std::get_if<ForceModelConfig>(&m.spec)) {
        for (const auto& k : f->keyframes) check_mesh(k.mesh, in);
        for (const auto& mesh : f->mesh_obstacles) check_mesh(mesh, in);
    }
    return m;
}

std::shared_ptr<Behavior> behavior_from_checkpoint(Swarm& swarm, const CheckpointModel& model) {
    if (const auto* e = std::get_if<EnergySpec>(&model.spec))
        return std::make_shared<EnergyModel>(swarm, e->config, model.dataset);
    return make_behavior(swarm, model.spec);
}

// A field added to one of these structs changes its size: add it to fields()
// above (and to docs/checkpoint-format.md), then update the size here.  Sizes
// of the x86-64 Linux ABI (the one CI builds); other platforms skip the check.
#if defined(__x86_64__) && defined(__GLIBCXX__)
static_assert(sizeof(NoiseConfig) == 112, "NoiseConfig changed: update fields(NoiseConfig) and the checkpoint format");
// FieldModelConfig has a parameter table: MODL v2 writes its rows by key
// (tests/test_params.cpp checks every row round-trips); fields() keeps the
// version 1 layout for reading older files.
// PathModelConfig too; its targets are structured fields (fields() below).
static_assert(sizeof(PathTarget) == 20, "PathTarget changed: update its checkpoint fields()");
// ForceModelConfig too (its table's rows by key, then structured_fields).
// PolicyModelConfig too (from MODL v3); its obstacle boxes are structured.
static_assert(sizeof(RlObstacleBox) == 24, "RlObstacleBox changed: update its checkpoint fields()");
// EnergyModelConfig has a parameter table too (MODL v2, as FieldModelConfig).
static_assert(sizeof(Boundary) == 48 && sizeof(Goal) == 32 && sizeof(Stimulus) == 32 && sizeof(EnergyWeights) == 32,
              "an obstacle, goal or stimulus struct changed: update its checkpoint fields()");
#endif

}  // namespace swarmcl

// The path model on a swarm of worlds (docs/architecture.md, "Worlds"):
// parameters per world through the table, the goals per world (which the
// table does not hold: "groups.G.goals.I.center", ".radius",
// ".half_extents"), and the blocks the kernel reads per world.
#include "models/path_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

// A goal's field set per world: "groups.G.goals.I.FIELD", or
// "goals.I.FIELD" for group 0 (a scenario's one-group "goals").
struct GoalKey {
    uint32_t group = 0, goal = 0;
    std::string field;  // "center", "radius" or "half_extents"
    int components() const { return field == "radius" ? 1 : 3; }
    std::string canonical() const {
        return "groups." + std::to_string(group) + ".goals." + std::to_string(goal) + "." + field;
    }
};

bool read_index(const std::string& text, uint32_t* out) {
    if (text.empty() || text.size() > 9 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    *out = uint32_t(std::stoul(text));
    return true;
}

std::optional<GoalKey> parse_goal_key(const std::string& key) {
    std::vector<std::string> parts;
    std::stringstream in(key);
    for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
    GoalKey g;
    size_t at = 0;
    if (parts.size() == 5 && parts[0] == "groups" && parts[2] == "goals") {
        if (!read_index(parts[1], &g.group)) return std::nullopt;
        at = 3;
    } else if (parts.size() == 3 && parts[0] == "goals") {
        at = 1;
    } else {
        return std::nullopt;
    }
    if (!read_index(parts[at], &g.goal)) return std::nullopt;
    g.field = parts[at + 1];
    if (g.field != "center" && g.field != "radius" && g.field != "half_extents") return std::nullopt;
    return g;
}

std::string text_of(double v) {
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
}

// The goal `key` names in `c`, or Error naming what is missing.
Goal& goal_of(PathModelConfig& c, const GoalKey& key, const std::string& name) {
    require(key.group < c.groups.size(), "path model " + name + ": group " + std::to_string(key.group) +
                                             " does not exist (" + std::to_string(c.groups.size()) + " groups)");
    std::vector<Goal>& goals = c.groups[key.group].goals;
    require(key.goal < goals.size(), "path model " + name + ": group " + std::to_string(key.group) + " has " +
                                         std::to_string(goals.size()) + " goals");
    Goal& g = goals[key.goal];
    if (key.field == "radius")
        require(g.kind == Goal::Kind::Sphere, "path model " + name + ": that goal is not a sphere (no radius)");
    if (key.field == "half_extents")
        require(g.kind == Goal::Kind::Box, "path model " + name + ": that goal is not a box (no half extents)");
    return g;
}

float* field_of(Goal& g, const std::string& field) {
    return field == "center" ? g.center.data() : field == "radius" ? &g.radius : g.half_extents.data();
}

bool same_cost_inputs(const PathModelConfig& a, const PathModelConfig& b) {
    if (a.weights.A != b.weights.A || a.weights.B != b.weights.B || a.second_order != b.second_order ||
        a.groups.size() != b.groups.size())
        return false;
    for (size_t g = 0; g < a.groups.size(); ++g) {
        const auto& x = a.groups[g].goals;
        const auto& y = b.groups[g].goals;
        if (x.size() != y.size()) return false;
        for (size_t i = 0; i < x.size(); ++i)
            if (x[i].kind != y[i].kind || x[i].center != y[i].center || x[i].radius != y[i].radius ||
                x[i].half_extents != y[i].half_extents)
                return false;
    }
    return true;
}

}  // namespace

void PathModel::require_one_world(const std::string& what) const {
    require(worlds_.worlds() == 1, what + " does not run on a swarm of several worlds (" +
                                       std::to_string(worlds_.worlds()) +
                                       "); set each world's values with set_world_param");
}

std::vector<cl_float4> PathModel::solve_directions(const PathModelConfig& c, std::vector<double>* slowness,
                                                   std::vector<std::vector<double>>* costs) const {
    const std::vector<double> s = cost_slowness(grid_, phi_, c.weights);
    std::vector<cl_float4> dirs(grid_.count() * c.groups.size());
    std::vector<std::vector<double>> all(c.groups.size());
    for (uint32_t g = 0; g < c.groups.size(); ++g) {
        try {
            all[g] = solve_cost(grid_, s, goals_with_targets(c.groups[g].goals, c.targets, g), c.second_order);
        } catch (const Error& e) {
            throw Error(e.status(), "path model group " + std::to_string(g) + ": " + e.what());
        }
        direction_field(grid_, all[g], phi_, reinterpret_cast<float*>(dirs.data() + size_t(g) * grid_.count()));
    }
    if (slowness) *slowness = s;
    if (costs) *costs = std::move(all);
    return dirs;
}

void PathModel::upload_world_blocks() {
    const uint32_t worlds = worlds_.worlds();
    std::vector<float> blocks;
    if (worlds > 1) {
        blocks = worlds_.device_blocks();
    } else {
        blocks.assign(std::max<size_t>(1, path_param_table().device_floats()), 0.0f);
        path_param_table().write_device_block(const_cast<PathModelConfig*>(&config_), blocks.data());
    }
    std::vector<cl_float4> extra(worlds);
    for (uint32_t k = 0; k < worlds; ++k) {
        const PathModelConfig& c = world(k);
        // The ramp compares the cost with A * falloff (cost per metre of free
        // path: A); phototaxis (§7) turns its pull by the lamp's angle.
        const float inv_falloff = c.goal_falloff > 0.0f ? float(1.0 / (c.weights.A * c.goal_falloff)) : 0.0f;
        extra[k] = cl_float4{{inv_falloff, std::cos(c.lamp.angle), std::sin(c.lamp.angle), 0.0f}};
    }
    params_.reserve(ctx_, blocks.size(), "path model parameter blocks");
    params_.upload(ctx_, blocks.data(), blocks.size());
    world_extra_.reserve(ctx_, extra.size(), "path model world constants");
    world_extra_.upload(ctx_, extra.data(), extra.size());
    if (worlds > 1) {
        noise_blocks_.reserve(ctx_, noise_host_.size(), "noise parameter blocks");
        noise_blocks_.upload(ctx_, noise_host_.data(), noise_host_.size());
        noise_prims_.reserve(ctx_, noise_prims_host_.size(), "noise boundaries of the worlds");
        noise_prims_.upload(ctx_, noise_prims_host_.data(), noise_prims_host_.size());
    }
    blocks_current_ = true;
}

void PathModel::set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) {
    const uint32_t worlds = worlds_.worlds();
    if (worlds == 1) worlds_ = WorldConfigs<PathModelConfig>(path_param_table(), config_, 1);  // the setters' changes
    const std::optional<GoalKey> goal = parse_goal_key(key);
    const bool noise = key.compare(0, 6, "noise.") == 0;
    const bool lamp = key.compare(0, 5, "lamp.") == 0;
    const bool cost = goal || key.compare(0, 5, "cost.") == 0;
    const bool grid = key == "has_grid_box" || key.compare(0, 5, "grid.") == 0;
    std::vector<float> noise_next = noise_host_;
    std::vector<cl_float4> prims_next = noise_prims_host_;
    std::vector<std::vector<cl_float4>> dirs(worlds);
    std::vector<double> slowness0;
    std::vector<std::vector<double>> costs0;
    std::unique_ptr<LocalField> local;  // one world: the noise rebuilt (baked or not)
    const auto also = [&](const PathModelConfig& c, uint32_t k) {
        if (grid) {  // built once, before the first step
            const std::vector<double> now = WorldConfigs<PathModelConfig>(path_param_table(), config_, 1).get(key);
            const std::vector<double> v = WorldConfigs<PathModelConfig>(path_param_table(), c, 1).get(key);
            require(v == now, "path model " + key + " cannot be set per world: the path grid is built once, for "
                                                    "every world");
        }
        if (lamp && c.lamp.enabled) check_lamp(c.lamp);
        if (cost) dirs[k] = solve_directions(c, k == 0 ? &slowness0 : nullptr, k == 0 ? &costs0 : nullptr);
        if (noise && worlds > 1)
            write_world_noise_block(ctx_, noise_with_targets(c.noise, c.targets), &domain_min_, &domain_max_,
                                    *local_.noise, "path model " + key, noise_next, k, &prims_next);
        if (noise && worlds == 1) local = std::make_unique<LocalField>(build_local(c.noise, c.targets));
    };
    const WorldConfigs<PathModelConfig> before = worlds_;
    if (goal) {
        const size_t per = size_t(goal->components());
        const std::string name = goal->canonical();
        if (values == nullptr && count > 0) fail(Status::InvalidArgument, "path model " + name + ": values is NULL");
        if (count != per * worlds)
            fail(Status::InvalidArgument, "path model " + name + ": " + std::to_string(count) + " values given for " +
                                              std::to_string(worlds) + " worlds (" + std::to_string(per * worlds) +
                                              " expected" + (per > 1 ? ", 3 per world" : "") + ")");
        for (size_t i = 0; i < count; ++i) {
            const bool positive = goal->field != "center";
            if (std::isfinite(values[i]) && std::fabs(values[i]) < 3.4e38 && (!positive || float(values[i]) > 0.0f))
                continue;
            fail(Status::InvalidArgument, "path model " + name + (per > 1 ? "[" + std::to_string(i % 3) + "]" : "") +
                                              " = " + text_of(values[i]) + " in world " + std::to_string(i / per) +
                                              " is outside " + (positive ? "(0, inf)" : "(-inf, inf)") +
                                              " (m); nothing was set");
        }
        worlds_.change(
            [&](PathModelConfig& c, uint32_t k) {
                float* v = field_of(goal_of(c, *goal, name), goal->field);
                for (size_t a = 0; a < per; ++a) v[a] = float(values[size_t(k) * per + a]);
            },
            also);
    } else {
        worlds_.set(key, values, count, also);
    }
    // Committed; what follows allocates, and an error there undoes it.
    try {
        if (cost) {
            upload_world_directions(dirs);
            slowness_ = std::move(slowness0);
            costs_ = std::move(costs0);
        }
    } catch (...) {
        worlds_ = before;
        throw;
    }
    if (local) local_ = std::move(*local);
    if (noise) {
        noise_host_ = std::move(noise_next);
        noise_prims_host_ = std::move(prims_next);
    }
    config_ = worlds_[0];
    blocks_current_ = false;
    (void)swarm;
}

void PathModel::upload_world_directions(const std::vector<std::vector<cl_float4>>& dirs) {
    const uint32_t worlds = worlds_.worlds();
    write_buffer(ctx_, dirs_.get(), 0, dirs[0].size() * sizeof(cl_float4), dirs[0].data());
    bool differ = false;
    for (uint32_t k = 1; k < worlds; ++k) differ |= !same_cost_inputs(worlds_[k], worlds_[0]);
    if (differ) {
        const size_t per = dirs[0].size();
        world_dirs_.reserve(ctx_, per * worlds, "path model directions of every world");
        for (uint32_t k = 0; k < worlds; ++k)
            write_buffer(ctx_, world_dirs_.get(), size_t(k) * per * sizeof(cl_float4), per * sizeof(cl_float4),
                         dirs[k].data());
    }
    world_dirs_on_ = differ;
}

void PathModel::resolve_worlds(const std::function<void(PathModelConfig&)>& apply,
                               const std::function<void(const PathModelConfig&, uint32_t)>& also) {
    const uint32_t worlds = worlds_.worlds();
    std::vector<std::vector<cl_float4>> dirs(worlds);
    std::vector<double> slowness0;
    std::vector<std::vector<double>> costs0;
    std::optional<PathModelConfig> first;
    const WorldConfigs<PathModelConfig> before = worlds_;
    worlds_.change([&](PathModelConfig& c, uint32_t) { apply(c); },
                   [&](const PathModelConfig& c, uint32_t k) {
                       if (also) also(c, k);
                       // Worlds with world 0's cost inputs (changed first) share its fields.
                       if (k == 0) first = c;
                       else if (same_cost_inputs(c, *first)) return;
                       dirs[k] = solve_directions(c, k == 0 ? &slowness0 : nullptr, k == 0 ? &costs0 : nullptr);
                   });
    try {
        for (uint32_t k = 1; k < worlds; ++k)
            if (dirs[k].empty()) dirs[k] = dirs[0];
        upload_world_directions(dirs);
    } catch (...) {
        worlds_ = before;
        throw;
    }
    slowness_ = std::move(slowness0);
    costs_ = std::move(costs0);
    config_ = worlds_[0];
}

void PathModel::move_world_goals(const std::array<float, 3>& to) {
    const auto t0 = std::chrono::steady_clock::now();
    resolve_worlds([&](PathModelConfig& c) { c.groups[0].goals = goals_moved_to(c.groups[0].goals, to); }, {});
    ++recomputes_;  // one move, as alone
    recompute_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double PathModel::retarget_worlds(std::vector<PathTarget> targets, const std::vector<PathTarget>& changed) {
    const auto t0 = std::chrono::steady_clock::now();
    LocalField local = build_local(config_.noise, targets, &local_, changed);  // the boundaries: one for all
    std::vector<cl_float> noise_next = noise_host_;
    const std::vector<cl_float> block = local.noise->block();
    const std::vector<cl_float4>& prims = local.noise->prims();  // the targets' balls changed: as many per world
    std::vector<cl_float4> prims_next(std::max<size_t>(2, prims.size() * worlds_.worlds()));  // 2: a buffer to pass
    bool noise_varied = false;
    for (const std::string& key : worlds_.varied_keys()) noise_varied |= key.compare(0, 6, "noise.") == 0;
    resolve_worlds([&](PathModelConfig& c) { c.targets = targets; },
                   [&](const PathModelConfig& c, uint32_t k) {
                       // Each world's noise block with the new boundaries
                       // (world 0's where no world's noise differs).
                       if (noise_varied)
                           write_world_noise_block(ctx_, noise_with_targets(c.noise, c.targets), &domain_min_,
                                                   &domain_max_, *local.noise, "path model targets", noise_next, k,
                                                   &prims_next);
                       else {
                           std::copy(block.begin(), block.end(), noise_next.begin() + size_t(k) * block.size());
                           std::copy(prims.begin(), prims.end(), prims_next.begin() + size_t(k) * prims.size());
                       }
                   });
    local_ = std::move(local);
    noise_host_ = std::move(noise_next);
    noise_prims_host_ = std::move(prims_next);
    blocks_current_ = false;
    ctx_.queue().finish();
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++recomputes_;
    recompute_seconds_ += t;
    return t;
}

std::vector<double> PathModel::world_param(const std::string& key) const {
    const std::optional<GoalKey> goal = parse_goal_key(key);
    if (!goal) {
        if (worlds_.worlds() == 1) return WorldConfigs<PathModelConfig>(path_param_table(), config_, 1).get(key);
        return worlds_.get(key);
    }
    std::vector<double> out;
    for (uint32_t k = 0; k < worlds_.worlds(); ++k) {
        PathModelConfig c = world(k);
        float* v = field_of(goal_of(c, *goal, goal->canonical()), goal->field);
        for (int a = 0; a < goal->components(); ++a) out.push_back(v[a]);
    }
    return out;
}

std::vector<std::string> PathModel::varied_world_params() const {
    if (worlds_.worlds() == 1) return {};
    std::vector<std::string> out = worlds_.varied_keys();
    for (uint32_t g = 0; g < config_.groups.size(); ++g)
        for (uint32_t i = 0; i < config_.groups[g].goals.size(); ++i)
            for (const char* field : {"center", "radius", "half_extents"}) {
                const Goal& first = worlds_[0].groups[g].goals[i];
                if ((std::string(field) == "radius" && first.kind != Goal::Kind::Sphere) ||
                    (std::string(field) == "half_extents" && first.kind != Goal::Kind::Box))
                    continue;
                GoalKey key{g, i, field};
                const std::vector<double> v = world_param(key.canonical());
                const size_t per = size_t(key.components());
                for (size_t j = per; j < v.size(); ++j)
                    if (v[j] != v[j % per]) {
                        out.push_back(key.canonical());
                        break;
                    }
            }
    return out;
}

}  // namespace swarmcl

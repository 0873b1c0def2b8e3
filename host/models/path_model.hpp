// The curl-noise paper's full model (§5-6, Eq. 9): boundary-aware curl noise
// (obstacle meshes included) plus the global velocity field of a minimum
// cost field solved by fast marching, the position update; minimum distance
// enforcement is the swarm's stage after it (stages()).  Beyond the paper: agents form groups ("swarms"),
// each with its own goals and cost field, so swarms can cross (the paper's
// third limitation); a goal can move, which recomputes its group's field.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "fields/cost_field.hpp"
#include "fields/noise_field.hpp"
#include "fields/sdf.hpp"
#include "params/world_params.hpp"
#include "shapes/triangle_mesh.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

struct PathGroup {
    uint32_t agents = 0;  // agents in this group (consecutive ids); the last group takes the rest
    std::vector<Goal> goals;
};

// Chasing (seed 004 §7): a target ball that is both a goal of its group
// (its cost field is recomputed when it moves) and a boundary of Eq. 2 (the
// curl noise goes round it, like round an obstacle).  Its centre may be set
// each step (set_target).
struct PathTarget {
    uint32_t group = 0;
    std::array<float, 3> center{};
    float radius = 0.1f;  // m, > 0
};

// Positive phototaxis (seed 004 §7): "probabilistically added a small
// magnitude of speed towards the lamp holder for each insect".  Each step
// each insect, with probability `probability` (a Bernoulli draw, Philox
// keyed by the noise seed, its id and the step), gets `speed` m/s towards
// the lamp; our additions (docs/path-field.md): the pull is turned by
// `angle` (rad) about the lamp's vertical axis (a light-compass offset: the
// moths circle), and its radial part fades by Eq. 3's ramp within
// `keep_out` m of the lamp's surface (they do not fly into the bulb).
struct PathLamp {
    bool enabled = false;
    std::array<float, 3> center{};
    float radius = 0.1f;       // m, the bulb (> 0)
    float probability = 0.5f;  // per insect per step, in [0, 1]
    float speed = 1.0f;        // m/s added when drawn, >= 0
    float angle = 0.0f;        // rad, in [0, pi/2]: 0 straight at the lamp (the paper's words)
    float keep_out = 0.2f;     // m, > 0
};

struct PathModelConfig {
    NoiseConfig noise;                   // V_l (Eq. 1-3); the meshes join its boundaries (baked: with them)
    std::vector<TriangleMesh> obstacles; // §5.1 obstacles, merged into one signed distance grid
    bool has_grid_box = false;           // false: the swarm's domain
    std::array<float, 3> grid_min{}, grid_max{};
    std::array<uint32_t, 3> resolution{64, 64, 64};  // cells per axis at most (cubic cells)
    CostWeights weights;                 // A, B of Eq. 4
    bool second_order = false;           // fast marching order
    float speed = 1.5f;                  // s0 of Eq. 8, m/s (Table 1, two blocks)
    // Our addition: V_g grows from 0 at a goal to s0 over this many metres of
    // path (cost / A), so arriving insects are not pressed onto the goal's
    // surface (0: at once, the paper's Eq. 8).
    float goal_falloff = 0.0f;
    float min_distance = 0.0f;           // MDE threshold, m; 0: off
    std::vector<PathGroup> groups;       // at least one, each with a goal
    // Chasing (§7) in a scenario: every `waypoint_every` steps group 0's
    // goals move (their centres) to the next waypoint, cyclically.
    // With targets, the waypoints move target 0 instead.
    std::vector<std::array<float, 3>> waypoints;
    uint32_t waypoint_every = 60;
    std::vector<PathTarget> targets;     // chasing targets (a group's goals may then be empty)
    PathLamp lamp;                       // phototaxis (off unless enabled)
};

// Group `group`'s goals with the balls of its chasing targets (§7): what its
// cost field is solved for.
std::vector<Goal> goals_with_targets(std::vector<Goal> goals, const std::vector<PathTarget>& targets,
                                     uint32_t group);

// The noise's configuration with the chasing targets' balls as boundaries
// (§7: after the others).
NoiseConfig noise_with_targets(NoiseConfig noise, const std::vector<PathTarget>& targets);

// A group's goals moved by waypoints (§7 chasing without targets): the first
// goal to `to`, the others keeping their offsets to it.
std::vector<Goal> goals_moved_to(std::vector<Goal> goals, const std::array<float, 3>& to);

// Its parameters, declared once (models/path_params.cpp).
const ParamTable& path_param_table();

class PathModel : public Behavior {
public:
    // Preprocesses (signed distance, cost fields); Error(InvalidArgument)
    // naming the problem, and nothing is kept on error.  Every world of the
    // swarm starts with `config`; chasing targets and waypoints are one for
    // every world (each world's goals and fields move as alone).
    PathModel(Swarm& swarm, PathModelConfig config);

    // Per world (models/path_worlds.cpp): any parameter of the table but the
    // grid's (one grid for every world) and what selects the noise kernel or
    // is baked; and the goals, "groups.G.goals.I.center" / ".radius" /
    // ".half_extents" ("goals.I..." for group 0).  Worlds whose goals or
    // cost weights differ get cost fields of their own.
    void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) override;
    std::vector<double> world_param(const std::string& key) const override;
    std::vector<std::string> varied_world_params() const override;

    void advance(Swarm& swarm, uint64_t step) override;
    // MDE at min_distance (keyed by the noise seed), and step statistics.
    StepStages stages() const override;
    // Checkpoints (swarm/behavior.hpp).
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

    // Replaces group `group`'s goals and recomputes its cost field (chasing,
    // §7); returns the seconds it took.  Validated first: an error changes nothing.
    double set_goals(uint32_t group, std::vector<Goal> goals);

    // Moves target `index` to `center` (chasing, §7): its group's cost field
    // and the curl noise's boundaries (rebaked when baked) are recomputed,
    // only when it moved; returns the seconds it took (0: it did not move).
    // A centre outside the grid or inside an obstacle: Error, nothing changed.
    double set_target(uint32_t index, const std::array<float, 3>& center);
    // Adds a target; returns its index.  Same checks and recomputation.
    uint32_t add_target(const PathTarget& target);
    // Sets (or, with enabled = false, turns off) the lamp; a lamp outside the
    // grid or with no free space around it: Error, nothing changed.
    void set_lamp(const PathLamp& lamp);

    // World 0's configuration (the swarm's, with one world).
    const PathModelConfig& config() const { return config_; }
    const Grid3& grid() const { return grid_; }
    const std::vector<float>& sdf() const { return phi_; }                 // empty: no obstacles
    const std::vector<double>& cost(uint32_t group) const { return costs_.at(group); }
    double preprocess_seconds() const { return preprocess_seconds_; }
    // Cost field recomputations after a goal moved, and their total time.
    uint32_t recomputes() const { return recomputes_; }
    double recompute_seconds() const { return recompute_seconds_; }

private:
    // The path grid as kernel arguments: cells per axis; min corner and cell edge.
    cl_int4 grid_dims_arg() const {
        return cl_int4{{cl_int(grid_.dims[0]), cl_int(grid_.dims[1]), cl_int(grid_.dims[2]), 0}};
    }
    cl_float4 grid_origin_arg() const {
        return cl_float4{{float(grid_.origin[0]), float(grid_.origin[1]), float(grid_.origin[2]), float(grid_.h)}};
    }
    // The curl noise (its boundaries: the config's plus the targets), its
    // mesh-aware bake and the advance kernel built for it.
    struct LocalField {
        std::unique_ptr<NoiseField> noise;
        DeviceBuffer<cl_float4> vl;
        cl_float4 vl_min{}, vl_cell{{1, 1, 1, 1}};
        cl_int4 vl_dims{{2, 2, 2, 0}};
        cl::Kernel advance;
        uint32_t width = 1;
    };
    // With `previous` (a baked mesh-aware field) only the nodes within d0 of
    // the balls in `changed` (targets that moved, old and new places, or
    // appeared) are rebaked, into a copy of previous's nodes.
    LocalField build_local(const NoiseConfig& noise, const std::vector<PathTarget>& targets,
                           const LocalField* previous = nullptr, const std::vector<PathTarget>& changed = {}) const;
    void check_target(const PathTarget& t, const std::string& what) const;
    // Recomputes group `group`'s field and the local field for `targets`,
    // then commits both (an error leaves everything as it was).
    double retarget(std::vector<PathTarget> targets, uint32_t group, const std::vector<PathTarget>& changed);
    void upload_directions(uint32_t group);
    void upload_params();  // the worlds' blocks are uploaded before the next step
    // World k's configuration (config_ with one world, where the run-time
    // setters change it).
    const PathModelConfig& world(uint32_t k) const { return worlds_.worlds() > 1 ? worlds_[k] : config_; }
    // What must not be called on a swarm of several worlds (Error naming it).
    void require_one_world(const std::string& what) const;
    // path_param_table()'s block, world_extra and (several worlds) the noise
    // block of every world.
    void upload_world_blocks();
    // Every world's configuration changed by `apply` (also(c, k) run on each
    // changed one first) and its direction fields solved again, worlds with
    // world 0's cost inputs sharing its solve; commits them, world 0's
    // slowness and costs and config_.  An error changes nothing.
    void resolve_worlds(const std::function<void(PathModelConfig&)>& apply,
                        const std::function<void(const PathModelConfig&, uint32_t)>& also);
    // Waypoints on a swarm of worlds: every world's group 0 goals moved to
    // `to` (goals_moved_to, its own goals: each world as alone) and every
    // world's direction fields solved again; an error changes nothing.
    void move_world_goals(const std::array<float, 3>& to);
    // retarget on a swarm of worlds: the targets (one for every world) into
    // every world's configuration, its fields and noise block; the local
    // field (the targets' boundaries) rebuilt once.
    double retarget_worlds(std::vector<PathTarget> targets, const std::vector<PathTarget>& changed);
    // Commits every world's direction fields (dirs[k], solved from worlds_):
    // world 0's into dirs_, all into world_dirs_ where the worlds' cost
    // inputs differ.
    void upload_world_directions(const std::vector<std::vector<cl_float4>>& dirs);
    // The direction fields of every group of `c` (groups x cells), its
    // slowness and costs into *slowness / *costs when given.
    std::vector<cl_float4> solve_directions(const PathModelConfig& c, std::vector<double>* slowness = nullptr,
                                            std::vector<std::vector<double>>* costs = nullptr) const;
    void check_lamp(const PathLamp& lamp) const;

    PathModelConfig config_;
    Context& ctx_;
    Grid3 grid_;
    std::vector<float> phi_;
    std::vector<double> slowness_;
    std::vector<std::vector<double>> costs_;
    std::array<float, 3> domain_min_{}, domain_max_{};  // the swarm's (noise region fallback)
    bool mesh_noise_ = false;  // the meshes shape the curl noise (path_noise_mesh)
    LocalField local_;
    DeviceBuffer<cl_float4> dirs_;
    DeviceBuffer<cl_float> phi_dev_;
    DeviceBuffer<cl_uint> group_end_;
    DeviceBuffer<cl_float> params_;  // path_param_table()'s device block, one per world
    // Worlds (docs/architecture.md, "Worlds"): each world's configuration
    // (world 0's is config_), its noise block, its row of world_extra_ (1 /
    // (A goal_falloff), cos and sin of the lamp's angle) and, once goals or
    // cost weights differ between worlds, every world's direction fields.
    WorldConfigs<PathModelConfig> worlds_;
    std::vector<cl_float> noise_host_;
    DeviceBuffer<cl_float> noise_blocks_;
    std::vector<cl_float4> noise_prims_host_;  // each world's noise boundaries (a box's rounding is its noise.scale's)
    DeviceBuffer<cl_float4> noise_prims_;
    DeviceBuffer<cl_float4> world_extra_;
    DeviceBuffer<cl_float4> world_dirs_;
    bool world_dirs_on_ = false;
    bool blocks_current_ = false;
    double preprocess_seconds_ = 0.0;
    uint32_t recomputes_ = 0;
    double recompute_seconds_ = 0.0;
};

}  // namespace swarmcl

// The curl-noise paper's full model (§5-6, Eq. 9): boundary-aware curl noise
// (obstacle meshes included) plus the global velocity field of a minimum
// cost field solved by fast marching, the position update; minimum distance
// enforcement is the swarm's stage after it (stages()).  Beyond the paper: agents form groups ("swarms"),
// each with its own goals and cost field, so swarms can cross (the paper's
// third limitation); a goal can move, which recomputes its group's field.
#pragma once
#include <array>
#include <memory>
#include <vector>

#include "fields/cost_field.hpp"
#include "fields/noise_field.hpp"
#include "fields/sdf.hpp"
#include "shapes/triangle_mesh.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

struct PathGroup {
    uint32_t agents = 0;  // agents in this group (consecutive ids); the last group takes the rest
    std::vector<Goal> goals;
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
    std::vector<std::array<float, 3>> waypoints;
    uint32_t waypoint_every = 60;
};

class PathModel : public Behavior {
public:
    // Preprocesses (signed distance, cost fields); Error(InvalidArgument)
    // naming the problem, and nothing is kept on error.
    PathModel(Swarm& swarm, PathModelConfig config);

    void advance(Swarm& swarm, uint64_t step) override;
    // MDE at min_distance (keyed by the noise seed), and step statistics.
    StepStages stages() const override;
    // Checkpoints (swarm/behavior.hpp).
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

    // Replaces group `group`'s goals and recomputes its cost field (chasing,
    // §7); returns the seconds it took.  Validated first: an error changes nothing.
    double set_goals(uint32_t group, std::vector<Goal> goals);

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
    void upload_directions(uint32_t group);
    void bake_local_field(const std::string& defines);

    PathModelConfig config_;
    Context& ctx_;
    Grid3 grid_;
    std::vector<float> phi_;
    std::vector<double> slowness_;
    std::vector<std::vector<double>> costs_;
    std::unique_ptr<NoiseField> noise_;
    cl::Kernel advance_;
    uint32_t width_ = 1;  // agents per work-item of advance_
    DeviceBuffer<cl_float4> dirs_;
    DeviceBuffer<cl_float> phi_dev_;
    // The mesh-aware curl noise baked on the noise's bake grid (noise.baked).
    DeviceBuffer<cl_float4> vl_;
    cl_float4 vl_min_{}, vl_cell_{{1, 1, 1, 1}};
    cl_int4 vl_dims_{{2, 2, 2, 0}};
    DeviceBuffer<cl_uint> group_end_;
    double preprocess_seconds_ = 0.0;
    uint32_t recomputes_ = 0;
    double recompute_seconds_ = 0.0;
};

}  // namespace swarmcl

// The force model of the shape-constrained flying insects paper (Chen et al.
// 2019): internal forces (§4: three-zone interaction, curl noise), external
// forces towards sampled target meshes (§5: shape-constrained and distance
// forces), their union (§3, Eq. 1), a Newton step with a speed limit, the
// obstacle ramp (§6, Eq. 8-9), minimum distance enforcement (the swarm's
// constraint stage, run here on the fine grid), keyframed
// target meshes (morphing) and a global B-spline path.  Kernels:
// kernels/force_model.cl; choices: docs/force-model.md.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "fields/noise_field.hpp"
#include "fields/sdf.hpp"
#include "params/world_params.hpp"
#include "shapes/bspline_path.hpp"
#include "shapes/shape_sampling.hpp"
#include "spatial/point_grid.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

// Which forces are on (kernels/force_model.cl FM_*): all by default; the
// tests switch single terms on to compare them with references.
enum ForceTerm : uint32_t {
    kForceRepulsion = 1,
    kForceAlignment = 2,
    kForceAttraction = 4,
    kForceCurl = 8,
    kForceShape = 16,
    kForceDistance = 32,
    kForceAll = 63,
};

// A target mesh from `frame` (step) on, until the next keyframe.
struct Keyframe {
    uint64_t frame = 0;
    TriangleMesh mesh;
};

// Defaults: Table 1 of the paper where it gives a value.
struct ForceModelConfig {
    float r_rep = 0.3f, r_ali = 10.0f, r_att = 30.0f;  // zone radii, m (Table 1)
    float w_rep = 0.2f, w_ali = 3.0f, w_att = 13.0f;   // Eq. 2 weights (Table 1)
    float w_dis = 4.0f;                                // Eq. 6 (Table 1)
    // > 0: alignment and attraction look at this many agents per agent and
    // step, drawn uniformly from the swarm (Philox); each zone's mean is
    // estimated from the sampled ones within it.  0: every agent within
    // r_att (exact).  Not in the paper: with r_att = 30 m every insect
    // otherwise visits the whole swarm (docs/force-model.md).
    uint32_t neighbor_sample = 0;
    float w_con = 1.0f;       // Eq. 5 has no weight: 1
    float omega = 0.9f;       // Eq. 5: sigma = omega sqrt(A/N) (§5.2: 0.9)
    float neighbor_k = 2.0f;  // §5.2: Manhattan threshold k sqrt(A/N)
    float distance_scale = 0.0f;  // m, normalises d of Eq. 6; 0: 2 sqrt(A/N)
    float alpha = 0.7f;       // Eq. 1 (§3)
    float max_speed = 0.75f;  // m/s (§6, Table 1)
    // m/s: self-propulsion, slower insects are sped up to it (not in the
    // paper; without it aligned insects settle: docs/force-model.md).
    float cruise_speed = 0.375f;
    // 1/s: before the Newton step each insect's speed relaxes towards
    // preferred_speed, exactly over dt: s <- s0 + (s - s0) exp(-k dt), its
    // heading kept (not in the paper: a speed regulation that data-driven
    // fits can shape the speed distribution with; with s0 = 0 a linear drag;
    // docs/force-model.md).  0: off (the paper's).
    float speed_relaxation = 0.0f;
    float preferred_speed = 0.0f;  // m/s, s0 of the relaxation
    // Each insect's own pace (not in the paper; individual variation, which
    // the mosquito tracks show: docs/force-model.md): insect i's forces and
    // speeds (max_speed, cruise_speed, preferred_speed) are scaled by f_i =
    // exp(s z_i - s^2 / 2), z_i ~ N(0, 1) drawn once per insect (Philox keyed
    // by the noise seed and the insect's id), so the f_i have mean 1 and
    // log-sd s = speed_spread.  0: every insect alike (the paper's).
    float speed_spread = 0.0f;
    // Eq. 4: scale = rho 0.32 m, gain = eta / rho = 0.125 / 0.32 (Table 1):
    // the noise module's gain multiplies the curl in noise coordinates, Eq. 4
    // differentiates eta P(r / rho) in metres (docs/force-model.md).
    NoiseConfig noise;
    float min_distance = 0.0f;   // MDE threshold (§6), m; 0: off
    float min_spacing = 0.3f;    // §5.1: meshes scaled so sqrt(A/N) >= this (R_rep); 0: as given
    Assignment assignment = Assignment::Nearest;
    uint64_t sample_seed = 0;    // stratified sampling
    std::vector<Keyframe> keyframes;   // strictly increasing frames; empty: no external force
    uint64_t keyframe_period = 0;      // > 0: the keyframes repeat every this many steps
    std::vector<float> path;           // B-spline control points (packed xyz), empty: none
    float path_speed = 0.0f;           // m/s along the path
    // The shape's frame follows the path (§6): its forward axis +x turned to
    // the path's tangent, its up +z to the path's rotation-minimising up
    // (BSplinePath::frame_at_length).  false: translated only.
    bool path_orient = true;
    std::vector<Boundary> obstacles;   // spheres and boxes (Eq. 8-9)
    float obstacle_range = 1.0f;       // L of Eq. 9, m
    // Mesh obstacles (Eq. 8-9 with the distance of a signed distance grid,
    // fields/sdf.hpp): one grid of cubic cells of edge mesh_cell (0:
    // obstacle_range / 4) over the meshes' bounds grown by obstacle_range
    // and 2 cells, at most kForceMeshMaxCells cells (docs/force-model.md).
    std::vector<TriangleMesh> mesh_obstacles;
    float mesh_cell = 0.0f;
    uint32_t terms = kForceAll;

    ForceModelConfig();  // sets the noise defaults of Table 1
};

// Its parameters, declared once (models/force_params.cpp).
const ParamTable& force_param_table();

// Error(InvalidArgument) naming the field for any invalid parameter: the
// table's ranges, then what they cannot say (zone order, keyframes, meshes).
void validate(const ForceModelConfig& config);

// The most cells of the mesh obstacles' distance grid (64 MiB of floats).
constexpr uint64_t kForceMeshMaxCells = uint64_t(1) << 24;

// The mesh obstacles' distance grid of `config` (Error(InvalidArgument) above
// kForceMeshMaxCells), and its signed distances (compute_sdf).
Grid3 force_mesh_grid(const ForceModelConfig& config);
SdfGrid force_mesh_sdf(Context& ctx, const ForceModelConfig& config);

class ForceModel : public Behavior {
public:
    // Every world of the swarm starts with `config`.  A swarm of several
    // worlds (docs/architecture.md, "Worlds") runs the internal forces,
    // curl noise and MDE per world; target meshes (keyframes), a path,
    // obstacles and mesh obstacles are refused there (InvalidArgument).
    ForceModel(Swarm& swarm, ForceModelConfig config);

    void advance(Swarm& swarm, uint64_t step) override;
    // World 0's configuration (the swarm's, with one world).
    const ForceModelConfig& config() const { return config_; }

    // Per world: the table's parameters but those that choose a kernel or
    // what it runs (the noise's kernel, terms, baking) or that only the
    // host uses once for every world (sample_seed and the target, path and
    // mesh parameters), which are refused when they differ between worlds.
    void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) override;
    std::vector<double> world_param(const std::string& key) const override;
    std::vector<std::string> varied_world_params() const override { return worlds_.varied_keys(); }

    // MDE at min_distance (keyed by the noise seed) on the fine grid, step
    // statistics; a step without agents is not counted.
    StepStages stages() const override;
    void enforce_min_distance(Swarm& swarm, DeviceBuffer<cl_uint>& moved) override;
    // The obstacle push-out after MDE (docs/force-model.md).
    void after_constraints(Swarm& swarm, uint64_t step) override;
    // Checkpoints (swarm/behavior.hpp).
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

    // The mesh obstacles' grid (dims 0 without mesh obstacles).
    const Grid3& mesh_grid() const { return mesh_grid_; }
    // The kernels' sampled mesh obstacle normal and distance (xyz, w) at
    // packed xyz points (tests; w = inf outside the grid).
    std::vector<cl_float4> sample_mesh_obstacles(Swarm& swarm, const std::vector<float>& xyz);

    // Only the force of Eq. 1 at the current state, in slot order (tests).
    void compute_forces(Swarm& swarm, uint64_t step);
    DeviceBuffer<cl_float4>& forces() { return force_; }

    // The keyframe in effect at `step` (-1: none yet), the current targets
    // (shape frame, without the path's placement), target_of[agent id], and
    // the path offset at `step`.
    int keyframe_at(uint64_t step) const;
    const ShapeTargets* current_targets() const { return active_ < 0 ? nullptr : &targets_[size_t(active_)]; }
    const std::vector<uint32_t>& target_of() const { return target_of_; }
    Vec3f path_offset(uint64_t step, float dt) const;
    // Where the shape frame is at `step`: a point p of it is at R p + offset
    // (R the identity without a path or with path_orient off).
    struct Placement {
        std::array<std::array<double, 3>, 3> rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // rows
        Vec3f offset{0.0f, 0.0f, 0.0f};
        bool rotated = false;
    };
    Placement placement(uint64_t step, float dt) const;
    // Packed shape-frame points placed by placement(step, dt).
    std::vector<float> placed(const std::vector<float>& shape_xyz, uint64_t step, float dt) const;
    uint32_t current_keyframe() const { return uint32_t(active_); }

private:
    void prepare(Swarm& swarm);                 // targets for the agent count
    void activate(Swarm& swarm, int keyframe);  // upload targets, assign
    void enqueue_force(Swarm& swarm, uint64_t step);
    // The fine grid of repulsion and MDE over the current positions, and
    // its sorted copy of them (docs/force-model.md, "the fine grid").
    void build_fine_grid(Swarm& swarm);

    void upload_world_blocks(Context& ctx);

    ForceModelConfig config_;  // world 0's (worlds_[0])
    WorldConfigs<ForceModelConfig> worlds_;
    uint32_t world_count_ = 1;
    std::unique_ptr<NoiseField> noise_;
    std::optional<BSplinePath> path_;
    cl::Kernel force_k_, integrate_k_, project_k_, scatter_k_;
    DeviceBuffer<cl_float> params_;  // force_param_table()'s device block, one per world
    DeviceBuffer<cl_float> noise_blocks_;  // NoiseField::block() of each world
    std::vector<cl_float> noise_host_;     // noise_blocks_' contents
    // Each world's noise boundary primitives (NoiseField::prims(), world
    // k's walls at its own domain), one run after another.
    std::vector<cl_float4> noise_prims_host_;
    DeviceBuffer<cl_float4> noise_prims_;
    DeviceBuffer<cl_float> mde_d_min_;     // worlds: each world's min_distance
    DeviceBuffer<cl_ulong> world_seed_;    // each world's noise.seed (MDE of worlds, the insects' paces)
    bool blocks_current_ = false;
    uint32_t width_ = 1;  // agents per work-item of force_k_
    uint32_t prepared_n_ = 0;
    std::vector<ShapeTargets> targets_;  // per keyframe
    std::vector<bool> same_topology_;    // keyframe k corresponds sample by sample to k-1
    int active_ = -1;
    std::vector<uint32_t> target_of_;
    DeviceBuffer<cl_float4> force_, prims_, by_target_;
    DeviceBuffer<cl_uint> target_of_buf_;
    // Per keyframe, uploaded once by prepare(): switching keyframes (every few
    // steps in an animation) binds other buffers instead of uploading, which
    // would wait for the queue.
    struct KeyframeBuffers {
        DeviceBuffer<cl_float4> targets;
        DeviceBuffer<cl_uint> nbr_start, nbr_index;
    };
    std::vector<KeyframeBuffers> kf_buf_;
    uint32_t nprims_ = 0;
    Grid3 mesh_grid_{{0, 0, 0}, 1.0, {0, 0, 0}};  // no mesh obstacles: dims 0
    DeviceBuffer<cl_float> mesh_phi_;
    // The fine grid: a PointGrid at cells of at least R_rep, and the
    // positions in its order (x, y, z blocks) for the repulsion kernels.
    PointGrid fine_;
    cl::Kernel fine_gather_k_, mde_k_, repulsion_k_;
    bool fine_current_ = false;  // built by this step's enqueue_force, slots unchanged since
    uint32_t fine_n_ = 0;        // agents fine_soa_ is laid out for
    DeviceBuffer<cl_float4> rep_;  // repulsion sums by slot
    DeviceBuffer<cl_float> fine_soa_;  // world k's blocks at k 3 (n + pad)
};

}  // namespace swarmcl

// A noise field on the device: one of the four noise functions of the
// data-driven noise paper (§4.2.1) with the boundary-aware curl noise of the
// curl-noise paper (§4, Eq. 1-3), procedural or baked onto a grid
// (kernels/noise_field.cl).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "device/buffer.hpp"
#include "device/context.hpp"
#include "spatial/grid_geometry.hpp"

namespace swarmcl {

// Points per work-item of the explicit-width kernels on `device`: on CPU
// devices 8 where the device prefers 8-float vectors (PoCL with AVX2), else
// 16; 1 elsewhere; $SWARMCL_NOISE_WIDTH = 1, 8 or 16 overrides it
// (docs/noise.md).  Throws InvalidArgument for another value.
uint32_t preferred_noise_width(const DeviceEntry& device);
// Whether the width is forced (set_kernel_width_override or
// $SWARMCL_NOISE_WIDTH), not the device's default.
bool kernel_width_forced();

// A process-wide width for the explicit-width kernels (1, 8 or 16; 0 = none)
// that wins over $SWARMCL_NOISE_WIDTH and the device default, and sets the
// policy model's lanes too.  For tests and embedders that compare kernel
// variants: changing the environment with setenv while PoCL's worker threads
// read it with getenv is a data race (a SEGV seen under ASan).  Kernels
// already built keep their width.  Throws InvalidArgument for another value.
void set_kernel_width_override(uint32_t width);
uint32_t kernel_width_override();

enum class NoiseType : int { Curl = 0, Perlin = 1, White = 2, Gaussian = 3 };

class ParamTable;

// A boundary of the curl potential (Eq. 2): an obstacle or a half space.
struct Boundary {
    enum class Kind { Sphere, Box, Plane } kind = Kind::Sphere;
    std::array<float, 3> center{};
    float radius = 0.0f;                 // sphere radius; box edge rounding radius
    std::array<float, 3> half_extents{};
    std::array<float, 3> normal{};       // plane: unit normal into free space
    float offset = 0.0f;                 // plane: dot(normal, x) >= offset is free
};

struct NoiseConfig {
    NoiseType type = NoiseType::Curl;
    float scale = 0.4f;         // m; Table 1 of the curl-noise paper (two blocks, chasing)
    float gain = 0.25f;         // m/s; Table 1 (two blocks, chasing)
    uint64_t seed = 0;
    float time_scale = 0.0f;    // s per noise unit along time; 0: a static field
    float boundary_distance = 0.4f;  // d0 of Eq. 3, m
    bool domain_walls = false;  // the region box is an "extended boundary"
    std::array<float, 3> region_min{}, region_max{};  // walls and bake region
    std::vector<Boundary> boundaries;
    bool baked = false;
    std::array<uint32_t, 3> bake_resolution{64, 64, 64};  // grid nodes per axis
    bool finite_difference = false;  // curl by central differences (checking)
    float fd_step = 0.0f;            // m; 0: scale / 100

    bool has_region() const;
};

// NoiseConfig's parameters (fields/noise_params.cpp), included by every
// model's table under "noise.".
const ParamTable& noise_param_table();

// The nodes a field is baked on: NoiseConfig::bake_resolution per axis over
// its region, as the kernels take them (min corner; node spacing, w = 1;
// nodes per axis).
struct BakeGrid {
    cl_float4 min{}, cell{};
    cl_int4 dims{};
    size_t nodes() const { return size_t(dims.s[0]) * size_t(dims.s[1]) * size_t(dims.s[2]); }
};
BakeGrid bake_grid(const NoiseConfig& config);

// Runs `kernel` once per node of `grid` into a new buffer of the nodes'
// values: its arguments are set up to the output, argument `out_index`.
// Enqueued only.  NoiseField's bake and the path model's mesh-aware bake.
DeviceBuffer<cl_float4> bake_nodes(Context& ctx, cl::Kernel& kernel, cl_uint out_index, const BakeGrid& grid,
                                   const char* what);

class NoiseField {
public:
    // Validates (Error(InvalidArgument) naming the field) and, if baked,
    // bakes the field.  `fallback_region` is used when config has no region.
    NoiseField(Context& ctx, NoiseConfig config, const std::array<float, 3>* fallback_min = nullptr,
               const std::array<float, 3>* fallback_max = nullptr);

    const NoiseConfig& config() const { return config_; }

    // Appends the NOISE_PARAMS arguments (lib/noise_field.cl: the parameter
    // block, the boundary primitives, the baked grid) from `index` on.
    cl_uint set_args(cl::Kernel& kernel, cl_uint index) const;

    // The noise's parameter block as the kernels read it (NOISE_PARAMS):
    // the noise table's device rows (fields/noise_params.cpp), then what is
    // derived from them (flags, 1/time_scale, the seed's halves, the Perlin
    // channel offsets, the primitive count, the baked grid's placement).
    std::vector<cl_float> block() const;
    // The boundary primitives as uploaded (2 float4 each: the domain walls
    // first where there are any); a swarm of worlds keeps one run a world
    // (lib/noise_field.cl, NOISE_WORLD_PRIMS).
    const std::vector<cl_float4>& prims() const { return prims_host_; }

    // Build options that specialise kernels/noise_field.cl (and files that
    // include it) for this field: -DNOISE_KIND, NOISE_TIMED, NOISE_FD,
    // NOISE_WALLS, NOISE_OBSTACLES, and the block's slots (NOISE_SCALE, ...,
    // NOISE_FLOATS).  The kernel arguments stay the same.
    // On CPU devices also -DNOISE_WIDTH=W (width()).
    std::string defines() const;
    // The block's slots alone (" -DNOISE_TYPE=0 ... -DNOISE_FLOATS=5"), for a
    // model that specialises the noise's kernels itself (the path model's mesh).
    static std::string block_defines();
    // A kernel from `file` built for this field (Context::kernel with
    // defines() and `extra_defines`, e.g. a model's parameter slots).
    cl::Kernel kernel(const std::string& file, const char* name, const std::string& extra_defines = "") const;

    // Points per work-item of the explicit-width kernels (noise_sample_w,
    // field_model_advance_w: launch ceil(n / width()) work-items), or 1 when
    // the one-point-per-work-item kernels are to be used.  > 1 on CPU devices
    // for the configurations the wide path covers (curl / Perlin vector
    // without obstacles or finite differences, baked); $SWARMCL_NOISE_WIDTH
    // = 1, 8 or 16 overrides the device default (docs/noise.md).
    uint32_t width() const;
    // The device's (or $SWARMCL_NOISE_WIDTH's) width for kernels that have an
    // explicit-width variant whatever this field's boundaries (1, 8 or 16).
    uint32_t preferred_width() const { return preferred_width_; }

    // Samples at n packed xyz points into out (packed xyz); point i counts as
    // agent i for the random noise types.
    void sample(const float* xyz, size_t n, float time, uint32_t step, float* out);
    // The sampling kernel for this field (noise_sample_w when width() > 1,
    // else noise_sample), and its launch on n device points into out
    // (float4 each; enqueued only): for models that sample every agent.
    cl::Kernel sample_kernel() const;
    void enqueue_sample(cl::Kernel& kernel, const DeviceBuffer<cl_float4>& points, uint32_t n, float time,
                        uint32_t step, DeviceBuffer<cl_float4>& out);

    static void validate(const NoiseConfig& config);

private:
    void bake();
    void upload_block();

    Context& ctx_;
    NoiseConfig config_;
    std::array<cl_uint4, 3> offsets_{};
    DeviceBuffer<cl_float> block_;  // block(), uploaded at construction and after a bake
    DeviceBuffer<cl_float4> prims_;
    std::vector<cl_float4> prims_host_;
    uint32_t prim_count_ = 0;
    DeviceBuffer<cl_float4> baked_;
    cl_float4 bake_min_{}, bake_cell_{};
    cl_int4 bake_dims_{};
    bool baked_ready_ = false;
    uint32_t preferred_width_ = 1;  // device default or $SWARMCL_NOISE_WIDTH
};

// World `world`'s noise block for a swarm of worlds (docs/architecture.md,
// "Worlds"): `config`'s block() written at blocks[world * floats, ...) and,
// with `prims`, its boundary primitives (the walls at its region, or at the
// world's domain without one) at prims[world * current's count, ...).  The
// noise kernel is built once for every world, so what selects it
// (defines()) must stay `current`'s, and a baked field is one grid:
// Error(InvalidArgument) starting with `what` ("field model noise.scale")
// otherwise, nothing written.
void write_world_noise_block(Context& ctx, const NoiseConfig& config, const std::array<float, 3>* domain_min,
                             const std::array<float, 3>* domain_max, const NoiseField& current,
                             const std::string& what, std::vector<cl_float>& blocks, uint32_t world,
                             std::vector<cl_float4>* prims = nullptr);
// The boundary primitives of worlds in `domains` (one a world), each
// world's `current`'s; where the domains differ and the noise has no region
// (its walls at the domain), each world's written for its own domain, with
// its block in `blocks` (write_world_noise_block).
std::vector<cl_float4> world_noise_prims(Context& ctx, const std::vector<Domain>& domains, const NoiseConfig& config,
                                         const NoiseField& current, const std::string& what,
                                         std::vector<cl_float>& blocks);

// Worlds of their own domains (SwarmConfig::world_domains): each world's
// walls follow its domain (its own primitives, write_world_noise_block), but
// a baked noise is one grid, which without a region would cover world 0's
// domain: Error(InvalidArgument) starting with `what` where the domains
// differ; nothing else in the noise depends on the domain.
void check_noise_for_world_domains(const NoiseConfig& config, const std::vector<Domain>& domains,
                                   const std::string& what);

}  // namespace swarmcl

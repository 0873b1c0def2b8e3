#include "fields/noise_field.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "core/philox.hpp"
#include "params/param_table.hpp"

namespace swarmcl {
namespace {

// Kernel-side primitive codes (curl_noise.cl, SWCL_PRIM_*) and flags
// (noise_field.cl, NOISE_FLAG_*).
constexpr float kPrimBoxInterior = 1, kPrimSphere = 2, kPrimBox = 3, kPrimPlane = 4;
constexpr int kFlagTimed = 1, kFlagFiniteDifference = 2, kFlagBaked = 4;
constexpr uint32_t kStreamPerlinOffset = 2;  // SWCL_STREAM_PERLIN_OFFSET
constexpr uint64_t kMaxBakedNodes = uint64_t(1) << 27;

// Explicit-width kernels: SWCL_W points per work-item (perlin.cl).  CPU
// devices only by default: PoCL does not vectorise the scalar kernels across
// work-items, GPUs run them one point per work-item.  16 lanes, or 8 where
// the device prefers 8 floats a vector (PoCL with AVX2 and no AVX-512: a
// 16-lane vector is two registers there; 8 lanes measured 7-21 % faster in
// the noise, neighbour count, force and policy observation kernels and no
// slower in the others, docs/benchmarks.md "Eight lanes with AVX2").
constexpr uint32_t kCpuNoiseWidth = 16;
uint32_t cpu_noise_width(const DeviceEntry& device) { return device.preferred_float_width == 8 ? 8u : kCpuNoiseWidth; }

std::atomic<uint32_t> g_width_override{0};

}  // namespace

void set_kernel_width_override(uint32_t width) {
    require(width == 0 || width == 1 || width == 8 || width == 16,
            "kernel width override must be 0 (none), 1, 8 or 16 (got " + std::to_string(width) + ")");
    g_width_override.store(width);
}

uint32_t kernel_width_override() { return g_width_override.load(); }

bool kernel_width_forced() {
    const char* env = std::getenv("SWARMCL_NOISE_WIDTH");
    return g_width_override.load() != 0 || (env && *env);
}

uint32_t preferred_noise_width(const DeviceEntry& device) {
    if (const uint32_t w = g_width_override.load()) return w;
    const char* env = std::getenv("SWARMCL_NOISE_WIDTH");
    if (env && *env) {
        const std::string v(env);
        if (v == "1") return 1;
        if (v == "8") return 8;
        if (v == "16") return 16;
        fail(Status::InvalidArgument, "SWARMCL_NOISE_WIDTH must be 1, 8 or 16 (got '" + v + "')");
    }
    return device.cpu_profile ? cpu_noise_width(device) : 1;
}

namespace {

bool finite3(const std::array<float, 3>& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

void check_positive(float v, const char* name) {
    require(std::isfinite(v) && v > 0.0f, std::string("noise ") + name + " must be a finite number > 0");
}

void check_boundary(const Boundary& b, size_t i) {
    const std::string where = "noise boundaries[" + std::to_string(i) + "]";
    switch (b.kind) {
        case Boundary::Kind::Sphere:
            require(finite3(b.center), where + ".center must be finite");
            require(std::isfinite(b.radius) && b.radius > 0.0f, where + ": sphere radius must be > 0");
            break;
        case Boundary::Kind::Box:
            require(finite3(b.center), where + ".center must be finite");
            require(finite3(b.half_extents) && b.half_extents[0] > 0 && b.half_extents[1] > 0 && b.half_extents[2] > 0,
                    where + ": box half_extents must be > 0 (an empty box bounds nothing)");
            require(std::isfinite(b.radius) && b.radius >= 0.0f &&
                        b.radius <= *std::min_element(b.half_extents.begin(), b.half_extents.end()),
                    where + ": box edge radius must be in [0, smallest half extent]");
            break;
        case Boundary::Kind::Plane: {
            require(finite3(b.normal) && std::isfinite(b.offset), where + ": plane normal and offset must be finite");
            const float len = std::hypot(b.normal[0], b.normal[1], b.normal[2]);
            require(len > 0.0f, where + ": plane normal must not be zero");
            break;
        }
        default: fail(Status::InvalidArgument, where + ": unknown boundary type");
    }
}

}  // namespace

bool NoiseConfig::has_region() const {
    return region_min[0] < region_max[0] || region_min[1] < region_max[1] || region_min[2] < region_max[2];
}

void NoiseField::validate(const NoiseConfig& c) {
    const int type = int(c.type);
    require(type >= 0 && type <= 3, "noise type " + std::to_string(type) + " is not one of CURL, PERLIN, WHITE, GAUSSIAN");
    check_positive(c.scale, "scale");
    require(std::isfinite(c.gain) && c.gain >= 0.0f, "noise gain must be a finite number >= 0");
    require(std::isfinite(c.time_scale) && c.time_scale >= 0.0f, "noise time_scale must be a finite number >= 0 (0: static)");
    check_positive(c.boundary_distance, "boundary_distance (d0)");
    require(finite3(c.region_min) && finite3(c.region_max), "noise region bounds must be finite");
    if (c.has_region())
        for (int a = 0; a < 3; ++a)
            require(c.region_min[a] < c.region_max[a],
                    "noise region_min[" + std::to_string(a) + "] must be below region_max[" + std::to_string(a) + "]");
    for (size_t i = 0; i < c.boundaries.size(); ++i) check_boundary(c.boundaries[i], i);
    require(std::isfinite(c.fd_step) && c.fd_step >= 0.0f, "noise fd_step must be a finite number >= 0");
    if (c.baked) {
        require(c.type == NoiseType::Curl || c.type == NoiseType::Perlin,
                "only CURL and PERLIN noise can be baked (WHITE and GAUSSIAN are not fields of space)");
        require(c.time_scale == 0.0f, "a time-varying noise (time_scale > 0) cannot be baked");
        uint64_t nodes = 1;
        for (int a = 0; a < 3; ++a) {
            require(c.bake_resolution[a] >= 2 && c.bake_resolution[a] <= 4096,
                    "noise bake_resolution[" + std::to_string(a) + "] must be in [2, 4096]");
            nodes *= c.bake_resolution[a];
        }
        require(nodes <= kMaxBakedNodes, "noise bake_resolution has more than 2^27 nodes");
    }
}

NoiseField::NoiseField(Context& ctx, NoiseConfig config, const std::array<float, 3>* fallback_min,
                       const std::array<float, 3>* fallback_max)
    : ctx_(ctx), config_(std::move(config)) {
    if (!config_.has_region() && fallback_min && fallback_max) {
        config_.region_min = *fallback_min;
        config_.region_max = *fallback_max;
    }
    validate(config_);
    if ((config_.domain_walls || config_.baked) && !config_.has_region())
        fail(Status::InvalidArgument, std::string("noise ") + (config_.baked ? "baking" : "domain_walls") +
                                          " needs a region (region_min < region_max)");
    if (config_.fd_step == 0.0f) config_.fd_step = config_.scale / 100.0f;
    preferred_width_ = preferred_noise_width(ctx_.device());

    // Independent potentials: one Philox draw per channel (perlin.cl).
    for (uint32_t k = 0; k < 3; ++k) {
        const auto r = philox_for(config_.seed, k, 0, kStreamPerlinOffset);
        offsets_[k] = cl_uint4{{r[0], r[1], r[2], r[3]}};
    }

    std::vector<cl_float4> prims;
    auto push = [&](float type, std::array<float, 3> a, std::array<float, 4> b) {
        prims.push_back(cl_float4{{a[0], a[1], a[2], type}});
        prims.push_back(cl_float4{{b[0], b[1], b[2], b[3]}});
    };
    if (config_.domain_walls)
        push(kPrimBoxInterior, config_.region_min,
             {config_.region_max[0], config_.region_max[1], config_.region_max[2], 0.0f});
    for (const Boundary& b : config_.boundaries) {
        switch (b.kind) {
            case Boundary::Kind::Sphere: push(kPrimSphere, b.center, {b.radius, 0, 0, 0}); break;
            case Boundary::Kind::Box: {
                // A C^2 distance needs rounded edges (curl_noise.cl): radius 0
                // means "a small default", an eighth of the noise scale.
                const float hmin = *std::min_element(b.half_extents.begin(), b.half_extents.end());
                const float rr = b.radius > 0.0f ? b.radius : std::min(hmin, config_.scale / 8.0f);
                push(kPrimBox, b.center, {b.half_extents[0], b.half_extents[1], b.half_extents[2], rr});
                break;
            }
            case Boundary::Kind::Plane: {
                const float len = std::hypot(b.normal[0], b.normal[1], b.normal[2]);
                push(kPrimPlane, {b.normal[0] / len, b.normal[1] / len, b.normal[2] / len}, {b.offset / len, 0, 0, 0});
                break;
            }
        }
    }
    prim_count_ = uint32_t(prims.size() / 2);
    prims_.allocate(ctx_, std::max<size_t>(prims.size(), 2), "noise boundaries");
    prims_.upload(ctx_, prims.data(), prims.size());
    prims_host_ = std::move(prims);
    baked_.allocate(ctx_, 1, "baked noise");
    upload_block();
    if (config_.baked) bake();
}

std::vector<cl_float> NoiseField::block() const {
    const auto& c = config_;
    const ParamTable& table = noise_param_table();
    // The derived slots, in lib/noise_field.cl's order (NOISE_SLOT_*).
    constexpr uint32_t kDerivedFloats = 29;
    std::vector<cl_float> b(table.device_floats() + kDerivedFloats, 0.0f);
    NoiseConfig resolved = c;
    table.write_device_block(&resolved, b.data());
    size_t at = table.device_floats();
    const auto put_uint = [&](uint32_t u) { std::memcpy(&b[at++], &u, sizeof u); };
    const auto put_float4 = [&](const cl_float4& v) {
        for (int a = 0; a < 4; ++a) b[at++] = v.s[a];
    };
    int flags = 0;
    if (c.time_scale > 0.0f) flags |= kFlagTimed;
    if (c.finite_difference) flags |= kFlagFiniteDifference;
    if (baked_ready_) flags |= kFlagBaked;
    put_uint(uint32_t(flags));
    b[at++] = c.time_scale > 0.0f ? 1.0f / c.time_scale : 0.0f;
    put_uint(uint32_t(c.seed));
    put_uint(uint32_t(c.seed >> 32));
    for (const auto& o : offsets_)
        for (int a = 0; a < 4; ++a) put_uint(o.s[a]);
    put_uint(prim_count_);
    put_float4(bake_min_);
    put_float4(bake_cell_);
    for (int a = 0; a < 4; ++a) put_uint(uint32_t(bake_dims_.s[a]));
    if (at != b.size()) fail(Status::Internal, "noise block: layout out of step with lib/noise_field.cl");
    return b;
}

void NoiseField::upload_block() {
    const std::vector<cl_float> b = block();
    block_.allocate(ctx_, b.size(), "noise parameter block");
    block_.upload(ctx_, b.data(), b.size());
}

cl_uint NoiseField::set_args(cl::Kernel& k, cl_uint i) const {
    k.setArg(i++, block_.get());
    k.setArg(i++, prims_.get());
    k.setArg(i++, baked_.get());
    return i;
}

uint32_t NoiseField::width() const {
    const auto& c = config_;
    // The configurations noise_field.cl's explicit-width path covers
    // (NOISE_WIDE): baked, or curl / Perlin vector without finite differences
    // and, for curl, without obstacles.
    const bool wide = baked_ready_ || (c.type == NoiseType::Perlin) ||
                      (c.type == NoiseType::Curl && !c.finite_difference && c.boundaries.empty());
    return wide ? preferred_width_ : 1;
}

std::string NoiseField::defines() const {
    const auto& c = config_;
    const uint32_t w = width();
    const std::string wd = w > 1 ? " -DNOISE_WIDTH=" + std::to_string(w) : "";
    const std::string slots = block_defines();
    if (baked_ready_) return "-DNOISE_KIND=4" + wd + slots;  // NOISE_KIND_BAKED
    std::string d = "-DNOISE_KIND=" + std::to_string(int(c.type));
    if (c.type == NoiseType::Curl || c.type == NoiseType::Perlin)
        d += std::string(" -DNOISE_TIMED=") + (c.time_scale > 0.0f ? "1" : "0");
    if (c.type == NoiseType::Curl) {
        d += std::string(" -DNOISE_FD=") + (c.finite_difference ? "1" : "0");
        d += std::string(" -DNOISE_WALLS=") + (c.domain_walls ? "1" : "0");
        d += std::string(" -DNOISE_OBSTACLES=") + (c.boundaries.empty() ? "0" : "1");
    }
    return d + wd + slots;
}

std::string NoiseField::block_defines() { return noise_param_table().device_defines("NOISE"); }

cl::Kernel NoiseField::kernel(const std::string& file, const char* name, const std::string& extra_defines) const {
    return ctx_.kernel(file, name, defines() + extra_defines);
}

BakeGrid bake_grid(const NoiseConfig& c) {
    BakeGrid g;
    for (int a = 0; a < 3; ++a) {
        g.min.s[a] = c.region_min[a];
        g.cell.s[a] = (c.region_max[a] - c.region_min[a]) / float(c.bake_resolution[a] - 1);
        g.dims.s[a] = cl_int(c.bake_resolution[a]);
    }
    g.cell.s[3] = 1.0f;
    return g;
}

DeviceBuffer<cl_float4> bake_nodes(Context& ctx, cl::Kernel& kernel, cl_uint out_index, const BakeGrid& grid,
                                   const char* what) {
    const size_t nodes = grid.nodes();
    DeviceBuffer<cl_float4> values(ctx, nodes, what);
    kernel.setArg(out_index, values.get());
    check_arg_count(kernel, out_index + 1);
    launch(ctx, kernel, nodes);
    return values;
}

void NoiseField::bake() {
    const BakeGrid g = bake_grid(config_);
    bake_min_ = g.min;
    bake_cell_ = g.cell;
    bake_dims_ = g.dims;
    upload_block();  // the grid's placement
    cl::Kernel kernel = this->kernel("noise_field.cl", "noise_bake");
    const cl_uint i = set_args(kernel, 0);  // procedural: baked_ready_ is false
    DeviceBuffer<cl_float4> grid = bake_nodes(ctx_, kernel, i, g, "baked noise");
    ctx_.queue().finish();
    baked_ = std::move(grid);
    baked_ready_ = true;
    upload_block();  // the baked flag
}

cl::Kernel NoiseField::sample_kernel() const {
    return kernel("noise_field.cl", width() > 1 ? "noise_sample_w" : "noise_sample");
}

void NoiseField::enqueue_sample(cl::Kernel& kernel, const DeviceBuffer<cl_float4>& points, uint32_t n, float time,
                                uint32_t step, DeviceBuffer<cl_float4>& out) {
    cl_uint i = 0;
    kernel.setArg(i++, points.get());
    kernel.setArg(i++, cl_uint(n));
    kernel.setArg(i++, time);
    kernel.setArg(i++, step);
    i = set_args(kernel, i);
    kernel.setArg(i, out.get());
    check_arg_count(kernel, i + 1);
    const uint32_t w = width();
    launch(ctx_, kernel, (size_t(n) + w - 1) / w);
}

void NoiseField::sample(const float* xyz, size_t n, float time, uint32_t step, float* out) {
    require(xyz != nullptr || n == 0, "noise sample: points is NULL");
    require(out != nullptr || n == 0, "noise sample: out is NULL");
    require(std::isfinite(time), "noise sample: time must be finite");
    require(n <= 0xFFFFFFFFu, "noise sample: more than 2^32 - 1 points");
    std::vector<cl_float4> points(n);
    for (size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            const float v = xyz[3 * i + a];
            if (!std::isfinite(v))
                fail(Status::InvalidArgument, "noise sample: point " + std::to_string(i) + " is not finite");
            points[i].s[a] = v;
        }
        points[i].s[3] = 0.0f;
    }
    if (n == 0) return;
    DeviceBuffer<cl_float4> in(ctx_, n, "noise sample points"), result(ctx_, n, "noise sample results");
    in.upload(ctx_, points.data(), n);
    cl::Kernel kernel = sample_kernel();
    enqueue_sample(kernel, in, uint32_t(n), time, step, result);
    result.download(ctx_, points.data(), n);
    for (size_t p = 0; p < n; ++p)
        for (int a = 0; a < 3; ++a) out[3 * p + a] = points[p].s[a];
}

void write_world_noise_block(Context& ctx, const NoiseConfig& config, const std::array<float, 3>* domain_min,
                             const std::array<float, 3>* domain_max, const NoiseField& current,
                             const std::string& what, std::vector<cl_float>& blocks, uint32_t world,
                             std::vector<cl_float4>* prims) {
    const NoiseField field(ctx, config, domain_min, domain_max);
    if (field.defines() != current.defines())
        fail(Status::InvalidArgument, what + " cannot differ between worlds here: it selects the noise kernel "
                                             "(noise.type, a time scale of 0 or not, finite differences and baking "
                                             "are the same in every world)");
    if (config.baked)
        fail(Status::InvalidArgument, what + ": a baked noise field is the same in every world (bake it off to vary "
                                             "the noise per world)");
    const std::vector<cl_float> block = field.block();
    const std::vector<cl_float4>& p = field.prims();
    if (prims && p.size() != current.prims().size())
        fail(Status::Internal, what + ": the noise boundaries of a world must be as many as every world's");
    std::copy(block.begin(), block.end(), blocks.begin() + size_t(world) * block.size());
    if (prims) std::copy(p.begin(), p.end(), prims->begin() + size_t(world) * p.size());
}

std::vector<cl_float4> world_noise_prims(Context& ctx, const std::vector<Domain>& domains, const NoiseConfig& config,
                                         const NoiseField& current, const std::string& what,
                                         std::vector<cl_float>& blocks) {
    std::vector<cl_float4> prims;
    for (size_t k = 0; k < domains.size(); ++k)
        prims.insert(prims.end(), current.prims().begin(), current.prims().end());
    const bool same = same_domains(domains);
    if (prims.empty()) prims.resize(2, cl_float4{});  // a buffer to pass; none is read
    if (same || config.has_region()) return prims;
    for (size_t k = 0; k < domains.size(); ++k)
        write_world_noise_block(ctx, config, &domains[k].min, &domains[k].max, current, what, blocks, uint32_t(k),
                                &prims);
    return prims;
}

void check_noise_for_world_domains(const NoiseConfig& c, const std::vector<Domain>& domains,
                                   const std::string& what) {
    const bool same = same_domains(domains);
    if (same || c.has_region() || !c.baked) return;
    fail(Status::InvalidArgument, what + ": a baked noise without region_min/max would cover world 0's domain, "
                                         "and the worlds' domains differ; give the noise a region");
}

}  // namespace swarmcl

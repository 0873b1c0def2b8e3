#include "shapes/shape_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include <nanoflann.hpp>

#include "core/error.hpp"

namespace swarmcl {
namespace {

// nanoflann's dataset adaptor over packed xyz floats.
struct PointCloud {
    const std::vector<float>& xyz;
    size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(size_t i, size_t d) const { return xyz[3 * i + d]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

template <class Metric>
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<Metric, PointCloud, 3, uint32_t>;

// Skilling's transpose form of the Hilbert index ("Programming the Hilbert
// curve", 2004): `x` (b bits per axis) becomes the transposed index; the
// interleaved bits (x0 high bit first) are the position along the curve.
uint64_t hilbert_index(std::array<uint32_t, 3> x, int bits) {
    const uint32_t m = 1u << (bits - 1);
    for (uint32_t q = m; q > 1; q >>= 1) {  // inverse undo
        const uint32_t p = q - 1;
        for (int i = 0; i < 3; ++i) {
            if (x[i] & q) {
                x[0] ^= p;
            } else {
                const uint32_t t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
    }
    for (int i = 1; i < 3; ++i) x[i] ^= x[i - 1];  // Gray encode
    uint32_t t = 0;
    for (uint32_t q = m; q > 1; q >>= 1)
        if (x[2] & q) t ^= q - 1;
    for (int i = 0; i < 3; ++i) x[i] ^= t;
    uint64_t h = 0;
    for (int b = bits - 1; b >= 0; --b)
        for (int i = 0; i < 3; ++i) h = (h << 1) | ((x[i] >> b) & 1u);
    return h;
}

// Indices of the points ordered along the Hilbert curve of their own
// bounding box (each axis normalised separately), ties by index.
std::vector<uint32_t> hilbert_order(const std::vector<float>& xyz) {
    const size_t n = xyz.size() / 3;
    std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(xyz[3 * i + a]));
            hi[a] = std::max(hi[a], double(xyz[3 * i + a]));
        }
    constexpr int kBits = 16;
    const double top = double((1u << kBits) - 1);
    std::vector<uint64_t> key(n);
    for (size_t i = 0; i < n; ++i) {
        std::array<uint32_t, 3> q{};
        for (int a = 0; a < 3; ++a) {
            const double ext = hi[a] - lo[a];
            const double f = ext > 0.0 ? (xyz[3 * i + a] - lo[a]) / ext : 0.5;
            q[a] = uint32_t(std::lround(std::clamp(f, 0.0, 1.0) * top));
        }
        key[i] = hilbert_index(q, kBits);
    }
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key[a] < key[b]; });
    return order;
}

}  // namespace

std::vector<SurfaceSample> stratified_samples(const TriangleMesh& mesh, uint32_t n, uint64_t seed) {
    require(n > 0, "shape sampling: the number of targets must be > 0");
    require(mesh.triangle_count() > 0, "shape sampling: the mesh has no triangles");
    std::vector<double> cdf(mesh.triangle_count());
    double acc = 0.0;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const auto c = mesh.corners(t);
        acc += triangle_area(c[0], c[1], c[2]);
        cdf[t] = acc;
    }
    require(acc > 0.0 && std::isfinite(acc), "shape sampling: the mesh has no area");
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<SurfaceSample> out(n);
    const double stratum = acc / n;
    for (uint32_t i = 0; i < n; ++i) {
        // One uniform point in stratum i of the cumulative area.
        const double a = (i + unit(rng)) * stratum;
        const size_t t = std::min<size_t>(size_t(std::upper_bound(cdf.begin(), cdf.end(), a) - cdf.begin()),
                                          cdf.size() - 1);
        // Uniform in the triangle: fold the unit square onto it.
        double u = unit(rng), v = unit(rng);
        if (u + v > 1.0) {
            u = 1.0 - u;
            v = 1.0 - v;
        }
        out[i] = SurfaceSample{uint32_t(t), float(u), float(v)};
    }
    return out;
}

std::vector<float> sample_points(const TriangleMesh& mesh, const std::vector<SurfaceSample>& samples) {
    std::vector<float> xyz(3 * samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const SurfaceSample& s = samples[i];
        require(s.triangle < mesh.triangle_count(), "shape sampling: sample on a triangle the mesh lacks");
        const auto c = mesh.corners(s.triangle);
        const double w0 = 1.0 - double(s.u) - double(s.v);
        for (int a = 0; a < 3; ++a)
            xyz[3 * i + a] = float(w0 * c[0][a] + double(s.u) * c[1][a] + double(s.v) * c[2][a]);
    }
    return xyz;
}

TriangleMesh scaled_for_spacing(const TriangleMesh& mesh, uint32_t n, float min_spacing) {
    require(std::isfinite(min_spacing) && min_spacing >= 0.0f, "shape sampling: min_spacing must be >= 0");
    require(n > 0, "shape sampling: the number of targets must be > 0");
    const double spacing = std::sqrt(surface_area(mesh) / n);
    if (min_spacing == 0.0f || spacing >= min_spacing) return mesh;
    const float f = float(min_spacing / spacing);
    const MeshBounds b = bounds(mesh);
    Vec3f offset{};
    for (int a = 0; a < 3; ++a) offset[a] = 0.5f * (b.min[a] + b.max[a]) * (1.0f - f);
    return transformed(mesh, {f, f, f}, offset);
}

void manhattan_neighbors(const std::vector<float>& points, double threshold, std::vector<uint32_t>& start,
                         std::vector<uint32_t>& index) {
    require(std::isfinite(threshold) && threshold > 0.0, "shape sampling: neighbour threshold must be > 0");
    const size_t n = points.size() / 3;
    PointCloud cloud{points};
    KdTree<nanoflann::L1_Adaptor<float, PointCloud>> tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    start.assign(n + 1, 0);
    index.clear();
    std::vector<std::pair<uint32_t, float>> found;
    for (size_t i = 0; i < n; ++i) {
        found.clear();
        // L1 metric: the radius is the Manhattan distance itself.
        tree.radiusSearch(&points[3 * i], float(threshold), found, nanoflann::SearchParams(32, 0.0f, false));
        std::vector<uint32_t> ids;
        ids.reserve(found.size());
        for (const auto& f : found)
            if (f.first != i) ids.push_back(f.first);
        std::sort(ids.begin(), ids.end());
        index.insert(index.end(), ids.begin(), ids.end());
        start[i + 1] = uint32_t(index.size());
    }
}

ShapeTargets make_targets(const TriangleMesh& mesh, uint32_t n, uint64_t seed, float min_spacing,
                          double neighbor_k, const std::vector<SurfaceSample>* reuse) {
    require(std::isfinite(neighbor_k) && neighbor_k > 0.0, "shape sampling: neighbour factor k must be > 0");
    ShapeTargets t;
    const TriangleMesh scaled = scaled_for_spacing(mesh, n, min_spacing);
    const bool same = reuse && reuse->size() == n &&
                      std::all_of(reuse->begin(), reuse->end(),
                                  [&](const SurfaceSample& s) { return s.triangle < scaled.triangle_count(); });
    t.samples = same ? *reuse : stratified_samples(scaled, n, seed);
    t.points = sample_points(scaled, t.samples);
    t.area = surface_area(scaled);
    t.spacing = std::sqrt(t.area / n);
    manhattan_neighbors(t.points, neighbor_k * t.spacing, t.nbr_start, t.nbr_index);
    return t;
}

std::vector<uint32_t> assign_targets(const std::vector<float>& agents, const std::vector<float>& targets,
                                     Assignment method) {
    const size_t n = agents.size() / 3;
    require(targets.size() / 3 == n, "target assignment: " + std::to_string(targets.size() / 3) + " targets for " +
                                         std::to_string(n) + " insects (the counts must be equal)");
    std::vector<uint32_t> target_of(n);
    if (n == 0) return target_of;
    if (method == Assignment::Curve) {
        const auto oa = hilbert_order(agents), ot = hilbert_order(targets);
        for (size_t r = 0; r < n; ++r) target_of[oa[r]] = ot[r];
        return target_of;
    }
    PointCloud cloud{targets};
    KdTree<nanoflann::L2_Simple_Adaptor<float, PointCloud>> tree(3, cloud,
                                                                 nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    // Free targets, compacted (swap-remove), for agents whose 64 nearest
    // targets are all taken: those scan what is left instead of asking the
    // tree for ever more neighbours.
    std::vector<uint32_t> free_list(n), where(n);
    std::iota(free_list.begin(), free_list.end(), 0u);
    std::iota(where.begin(), where.end(), 0u);
    auto take = [&](size_t a, uint32_t t) {
        target_of[a] = t;
        const uint32_t last = free_list.back();
        free_list[where[t]] = last;
        where[last] = where[t];
        free_list.pop_back();
        where[t] = uint32_t(-1);
    };
    const size_t k = std::min<size_t>(64, n);
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    for (size_t a = 0; a < n; ++a) {
        const size_t got = tree.knnSearch(&agents[3 * a], k, idx.data(), d2.data());
        bool done = false;
        for (size_t j = 0; j < got && !done; ++j)
            if (where[idx[j]] != uint32_t(-1)) {
                take(a, idx[j]);
                done = true;
            }
        if (done) continue;
        // Nearest free target by a scan (ties: the lowest index, as the tree).
        uint32_t best = free_list.front();
        double best_d = HUGE_VAL;
        for (uint32_t t : free_list) {
            double d = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double x = double(agents[3 * a + c]) - targets[3 * size_t(t) + c];
                d += x * x;
            }
            if (d < best_d || (d == best_d && t < best)) best_d = d, best = t;
        }
        take(a, best);
    }
    return target_of;
}

double total_travel(const std::vector<float>& agents, const std::vector<float>& targets,
                    const std::vector<uint32_t>& target_of) {
    double sum = 0.0;
    for (size_t a = 0; a < target_of.size(); ++a) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double d = double(agents[3 * a + k]) - targets[3 * size_t(target_of[a]) + k];
            d2 += d * d;
        }
        sum += std::sqrt(d2);
    }
    return sum;
}

}  // namespace swarmcl

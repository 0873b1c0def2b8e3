// Target points of a shape-constrained swarm (shape-constrained flying
// insects paper, §5.1-5.3): area-weighted stratified sampling of a triangle
// mesh, the sample neighbour lists of Eq. 5 (Manhattan threshold, kd-tree),
// and the assignment of insects to targets (§5.3, "direct correspondences").
#pragma once
#include <cstdint>
#include <vector>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

// Where a sample lies on its mesh: triangle and barycentric weights of
// corners 1 and 2.  Meshes of the same topology (same vertex and triangle
// count, as keyframes of one animation) map one sample set onto each other
// through these, so an insect keeps its target across keyframes.
struct SurfaceSample {
    uint32_t triangle = 0;
    float u = 0.0f, v = 0.0f;
};

struct ShapeTargets {
    std::vector<float> points;        // packed xyz, one per target
    std::vector<SurfaceSample> samples;
    std::vector<uint32_t> nbr_start;  // CSR: neighbours of target t are
    std::vector<uint32_t> nbr_index;  // nbr_index[nbr_start[t] .. nbr_start[t+1])
    double area = 0.0;                // of the (scaled) mesh, m^2
    double spacing = 0.0;             // sqrt(area / N), m
    size_t count() const { return points.size() / 3; }
};

// §5.1: N samples, one per stratum of equal area A/N along the mesh's
// cumulative area (triangles in index order), uniform within its triangle.
// Deterministic for the seed.  Error(InvalidArgument) for n == 0.
std::vector<SurfaceSample> stratified_samples(const TriangleMesh& mesh, uint32_t n, uint64_t seed);
std::vector<float> sample_points(const TriangleMesh& mesh, const std::vector<SurfaceSample>& samples);

// §5.1 "we appropriately scale the inputted guidance meshes to meet the
// minimum distance requirement": the mesh scaled about its bounding-box
// centre by the smallest factor >= 1 that makes the mean sample spacing
// sqrt(A/N) at least `min_spacing` (0: unchanged).
TriangleMesh scaled_for_spacing(const TriangleMesh& mesh, uint32_t n, float min_spacing);

// §5.2: for each point, the other points within Manhattan distance
// `threshold` (the paper: k sqrt(A/N), k = 2), found with a nanoflann kd-tree
// under the L1 metric; lists sorted by index.
void manhattan_neighbors(const std::vector<float>& points, double threshold, std::vector<uint32_t>& start,
                         std::vector<uint32_t>& index);

// Everything for one target mesh: scaled, sampled (or mapped through
// `reuse` when given and the topology matches), neighbours at k sqrt(A/N).
ShapeTargets make_targets(const TriangleMesh& mesh, uint32_t n, uint64_t seed, float min_spacing,
                          double neighbor_k, const std::vector<SurfaceSample>* reuse = nullptr);

// §5.3 assignment of agents to targets (equal counts; Error(InvalidArgument)
// otherwise).  Returns target[agent].
enum class Assignment {
    // Agents in id order each take the nearest target still free.
    Nearest,
    // Both point sets, normalised to their bounding boxes, are ordered along
    // a 3-D Hilbert curve and matched by rank: the layout of the swarm is
    // carried onto the shape (left stays left), so morphs do not cross.
    Curve,
};
std::vector<uint32_t> assign_targets(const std::vector<float>& agents, const std::vector<float>& targets,
                                     Assignment method);
// Sum over agents of |agent - target[agent]| (m): what an assignment costs.
double total_travel(const std::vector<float>& agents, const std::vector<float>& targets,
                    const std::vector<uint32_t>& target_of);

}  // namespace swarmcl

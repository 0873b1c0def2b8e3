// Signed distance benchmark (curl-noise paper §5.1, Eq. 5): swarmcl's
// compute_sdf (exact band on the OpenCL device + fast marching beyond) on a
// ~10k-triangle sphere mesh at 128^3, beside OpenVDB's
// tools::meshToSignedDistanceField on the same mesh, voxel size and cell
// centres in the same run: once with a 3-voxel narrow band (OpenVDB's usual
// sparse use) and once with a band wide enough to fill the whole grid, as
// swarmcl does.  Errors are against the analytic distance to the sphere the
// mesh approximates (the mesh's own facet error is printed too).
//
//   sdf_bench [--n 128] [--rings 50] [--segments 100] [--repeats 3] [--json PATH]
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "device/context.hpp"
#include "fields/sdf.hpp"
#include "roofline.hpp"
#include "shapes/triangle_mesh.hpp"

#ifndef SWARMCL_BENCH_RESULTS_DIR
#define SWARMCL_BENCH_RESULTS_DIR "bench/results"
#endif

using namespace swarmcl;
using namespace swarmcl::bench;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct VdbResult {
    double seconds = 0, max_err_band = 0;
    size_t active = 0;
};

VdbResult run_vdb(const TriangleMesh& mesh, const Grid3& g, float band, int repeats, double R) {
    std::vector<openvdb::Vec3s> pts;
    std::vector<openvdb::Vec3I> tris;
    // Index space: voxel (i, j, k) is the cell centre origin + (i + 0.5) h.
    for (const auto& v : mesh.vertices)
        pts.emplace_back(float((v[0] - g.origin[0]) / g.h - 0.5), float((v[1] - g.origin[1]) / g.h - 0.5),
                         float((v[2] - g.origin[2]) / g.h - 0.5));
    for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    std::vector<openvdb::Vec4I> quads;
    auto xform = openvdb::math::Transform::createLinearTransform(g.h);
    std::vector<double> times;
    openvdb::FloatGrid::Ptr grid;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
            *openvdb::math::Transform::createLinearTransform(1.0), pts, tris, quads, band, band);
        times.push_back(since(t0));
    }
    (void)xform;
    VdbResult res;
    res.seconds = median(times);
    res.active = grid->activeVoxelCount();
    const double c = 0.5 * g.dims[0] * g.h;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const auto ijk = it.getCoord();
        if (ijk.x() < 0 || ijk.y() < 0 || ijk.z() < 0 || ijk.x() >= int(g.dims[0]) || ijk.y() >= int(g.dims[1]) ||
            ijk.z() >= int(g.dims[2]))
            continue;
        const auto p = g.center(ijk.x(), ijk.y(), ijk.z());
        const double exact = std::hypot(p[0] - c, p[1] - c, p[2] - c) - R;
        if (std::fabs(exact) <= 3 * g.h) res.max_err_band = std::max(res.max_err_band, std::fabs(*it * g.h - exact));
    }
    return res;
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t n = 128, rings = 50, segments = 100;
    int repeats = 3;
    std::string json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/sdf.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--n") n = uint32_t(std::atoi(next().c_str()));
        else if (a == "--rings") rings = uint32_t(std::atoi(next().c_str()));
        else if (a == "--segments") segments = uint32_t(std::atoi(next().c_str()));
        else if (a == "--repeats") repeats = std::atoi(next().c_str());
        else if (a == "--json") json = next();
        else { std::fprintf(stderr, "usage: sdf_bench [--n 128] [--rings 50] [--segments 100] [--repeats 3] [--json PATH]\n"); return 2; }
    }
    openvdb::initialize();
    Context ctx("", "");
    const double L = 1.0, R = 0.35;
    Grid3 g;
    g.origin = {0, 0, 0};
    g.h = L / n;
    g.dims = {n, n, n};
    const TriangleMesh mesh = sphere_mesh({0.5f, 0.5f, 0.5f}, float(R), rings, segments);
    std::printf("sdf_bench: %zu-triangle sphere mesh (r %.2f) on a %u^3 grid (h %.5f m), device %s, load %.2f\n",
                mesh.triangle_count(), R, n, g.h, ctx.device().device_name.c_str(), load_average());

    // swarmcl: one untimed warm-up (kernel compile), then the median of repeats.
    compute_sdf(ctx, mesh, g);
    std::vector<double> times;
    SdfGrid sdf;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        sdf = compute_sdf(ctx, mesh, g);
        times.push_back(since(t0));
    }
    double err_all = 0, err_band = 0;
    for (uint32_t k = 0; k < n; ++k)
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const auto p = g.center(i, j, k);
                const double exact = std::hypot(p[0] - 0.5, p[1] - 0.5, p[2] - 0.5) - R;
                const double e = std::fabs(sdf.phi[g.index(i, j, k)] - exact);
                err_all = std::max(err_all, e);
                if (std::fabs(exact) <= 3 * g.h) err_band = std::max(err_band, e);
            }
    const double ours = median(times);
    // The facets' own distance from the sphere: r (1 - cos(pi / rings)) at most.
    const double facet = R * (1 - std::cos(3.14159265358979 / std::min(rings, segments / 2)));
    const VdbResult narrow = run_vdb(mesh, g, 3.0f, repeats, R);
    const VdbResult full = run_vdb(mesh, g, float(n), 1, R);
    std::printf("  swarmcl compute_sdf (dense %u^3)   %8.3f s   max error: band %.2e m, everywhere %.2e m (%.2f cells)\n",
                n, ours, err_band, err_all, err_all / g.h);
    std::printf("  OpenVDB narrow band (3 voxels)     %8.3f s   max error in band %.2e m  (%zu active voxels)\n",
                narrow.seconds, narrow.max_err_band, narrow.active);
    std::printf("  OpenVDB dense (band %u voxels)     %8.3f s   max error in band %.2e m  (%zu active voxels)\n", n,
                full.seconds, full.max_err_band, full.active);
    std::printf("  ratios: OpenVDB narrow / swarmcl %.2f, OpenVDB dense / swarmcl %.2f; facet error of the mesh %.1e m\n",
                narrow.seconds / ours, full.seconds / ours, facet);
    // The roofline (issue 29): at the least each cell's distance is written
    // (a float on the device, a double for the fast marching beyond the band)
    // and read back: 16 B a cell, beside the device's copy kernel.
    const double cells = double(n) * n * n, copy_gbs = copy_bandwidth_gbs(ctx, size_t(cells) / 4);
    const std::vector<RooflineRow> roof = {roofline_row("compute_sdf, whole grid (per cell)", 16, cells, 1e3 * ours,
                                                        copy_gbs)};
    print_roofline(roof, copy_gbs);
    std::ofstream out(json);
    out << "{\n  \"benchmark\": \"sdf_bench\",\n  \"date\": \"" << utc_now() << "\",\n  \"load_average\": " << load_average()
        << ",\n  \"device\": \"" << json_escape(ctx.device().device_name) << "\",\n  \"triangles\": " << mesh.triangle_count()
        << ",\n  \"grid\": " << n << ",\n  \"swarmcl_seconds\": " << ours << ",\n  \"swarmcl_runs\": "
        << json_array(times, 1.0) << ",\n  \"swarmcl_max_error_band_m\": " << err_band
        << ",\n  \"swarmcl_max_error_m\": " << err_all << ",\n  \"openvdb_narrow_seconds\": " << narrow.seconds
        << ",\n  \"openvdb_narrow_max_error_m\": " << narrow.max_err_band << ",\n  \"openvdb_dense_seconds\": "
        << full.seconds << ",\n  \"openvdb_dense_max_error_m\": " << full.max_err_band << ",\n  \"cell_m\": " << g.h
        << ",\n  \"roofline\": " << roofline_json(roof, copy_gbs) << "\n}\n";
    std::printf("  wrote %s\n", json.c_str());
    return 0;
}

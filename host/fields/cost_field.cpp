#include "fields/cost_field.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace swarmcl {
namespace {

// Cells within this many cells of a goal start with their exact cost (the
// march starts from a ball, not a one-cell seed: the first-order error of a
// point source then stays below 1.5 cells over 40 cells, tests/test_path_field).
constexpr double kGoalRing = 3.0;

// Distance from p to the goal region (0 inside).
double goal_distance(const Goal& g, const std::array<double, 3>& p) {
    double d2 = 0.0;
    switch (g.kind) {
        case Goal::Kind::Point:
        case Goal::Kind::Sphere: {
            for (int a = 0; a < 3; ++a) d2 += (p[a] - g.center[a]) * (p[a] - g.center[a]);
            return std::max(0.0, std::sqrt(d2) - (g.kind == Goal::Kind::Sphere ? g.radius : 0.0));
        }
        case Goal::Kind::Box:
            for (int a = 0; a < 3; ++a) {
                const double q = std::max(0.0, std::fabs(p[a] - g.center[a]) - g.half_extents[a]);
                d2 += q * q;
            }
            return std::sqrt(d2);
    }
    return kInf;
}

// Cells within `reach` of the goal: a box of cells around its bounds.
template <typename F>
void for_cells_near(const Grid3& grid, const Goal& g, double reach, F&& f) {
    std::array<double, 3> ext{0, 0, 0};
    if (g.kind == Goal::Kind::Sphere) ext = {g.radius, g.radius, g.radius};
    if (g.kind == Goal::Kind::Box) ext = {g.half_extents[0], g.half_extents[1], g.half_extents[2]};
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(0, int(std::floor((g.center[a] - ext[a] - reach - grid.origin[a]) / grid.h - 0.5)));
        hi[a] = std::min(int(grid.dims[a]) - 1, int(std::ceil((g.center[a] + ext[a] + reach - grid.origin[a]) / grid.h - 0.5)));
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i) {
                const double d = goal_distance(g, grid.center(i, j, k));
                if (d <= reach) f(grid.index(i, j, k), d);
            }
}

}  // namespace

double repulsion(double phi, double cell) {
    const double r = phi / (2.0 * std::sqrt(2.0) * cell);
    if (r < 0.0) return 1.0;
    if (r > 1.0) return 0.0;
    const double r2 = r * r, r4 = r2 * r2;
    return 1.0 - (4.0 / 9.0) * r4 * r2 + (17.0 / 9.0) * r4 - (22.0 / 9.0) * r2;
}

std::vector<double> cost_slowness(const Grid3& grid, const std::vector<float>& phi, const CostWeights& w) {
    require(std::isfinite(w.A) && std::isfinite(w.B) && w.A > 0.0 && w.B >= 0.0,
            "cost weights: A must be > 0 and B >= 0 (|grad C| = A + B g must stay positive)");
    std::vector<double> f(grid.count(), w.A);
    if (phi.empty()) return f;
    require(phi.size() == grid.count(), "cost: the signed distance does not match the grid");
    for (size_t c = 0; c < f.size(); ++c)
        f[c] = phi[c] <= 0.0f ? kInf : w.A + w.B * repulsion(phi[c], grid.h);
    return f;
}

void check_goals(const Grid3& grid, const std::vector<Goal>& goals, const std::vector<double>& slowness) {
    require(!goals.empty(), "path field: at least one goal is needed");
    const auto top = grid.max_corner();
    for (size_t i = 0; i < goals.size(); ++i) {
        const Goal& g = goals[i];
        const std::string w = "goal " + std::to_string(i);
        for (int a = 0; a < 3; ++a) require(std::isfinite(g.center[a]), w + ": center must be finite");
        if (g.kind == Goal::Kind::Sphere) require(std::isfinite(g.radius) && g.radius > 0.0f, w + ": sphere radius must be > 0");
        if (g.kind == Goal::Kind::Box)
            for (int a = 0; a < 3; ++a)
                require(std::isfinite(g.half_extents[a]) && g.half_extents[a] > 0.0f, w + ": box half extents must be > 0");
        bool inside_grid = false, free = false;
        for_cells_near(grid, g, grid.h, [&](size_t c, double) {
            inside_grid = true;
            free |= std::isfinite(slowness[c]);
        });
        require(inside_grid, w + " is outside the grid [" + std::to_string(grid.origin[0]) + ", " +
                                 std::to_string(top[0]) + "] x [" + std::to_string(grid.origin[1]) + ", " +
                                 std::to_string(top[1]) + "] x [" + std::to_string(grid.origin[2]) + ", " +
                                 std::to_string(top[2]) + "]");
        require(free, w + " lies inside an obstacle (no free cell within one cell of it)");
    }
}

std::vector<double> solve_cost(const Grid3& grid, const std::vector<double>& slowness, const std::vector<Goal>& goals,
                               bool second_order, unsigned threads) {
    check_goals(grid, goals, slowness);
    std::vector<double> u(grid.count(), kInf);
    for (const Goal& g : goals)
        for_cells_near(grid, g, kGoalRing * grid.h, [&](size_t c, double d) {
            if (std::isfinite(slowness[c])) u[c] = std::min(u[c], slowness[c] * d);
        });
    FastMarchingOptions o;
    o.second_order = second_order;
    o.threads = threads;
    fast_march(grid, slowness, u, o);
    return u;
}

void direction_field(const Grid3& grid, const std::vector<double>& C, const std::vector<float>& phi, float* out) {
    const int64_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
    const int64_t stride[3] = {1, nx, nx * ny}, dim[3] = {nx, ny, nz};
    for (int64_t z = 0; z < nz; ++z)
        for (int64_t y = 0; y < ny; ++y)
            for (int64_t x = 0; x < nx; ++x) {
                const int64_t pos[3] = {x, y, z};
                const size_t c = size_t(x + nx * (y + ny * z));
                double v[3] = {0, 0, 0};
                float* o = out + 4 * c;
                if (!std::isfinite(C[c])) {
                    // Impassable: out of the obstacle, along grad phi.
                    for (int a = 0; a < 3; ++a) {
                        const size_t lo = pos[a] > 0 ? c - stride[a] : c, hi = pos[a] + 1 < dim[a] ? c + stride[a] : c;
                        v[a] = phi.empty() ? 0.0 : double(phi[hi]) - double(phi[lo]);
                    }
                } else if (C[c] > 0.0) {
                    double lowest = C[c];
                    int low_axis = -1, low_side = 0;
                    for (int a = 0; a < 3; ++a) {
                        double nb[2] = {kInf, kInf};
                        for (int s = 0; s < 2; ++s) {
                            const int64_t xa = pos[a] + (s ? 1 : -1);
                            if (xa >= 0 && xa < dim[a]) nb[s] = C[c + (s ? 1 : -1) * stride[a]];
                            if (nb[s] < lowest) { lowest = nb[s]; low_axis = a; low_side = s ? 1 : -1; }
                        }
                        if (std::isfinite(nb[0]) && std::isfinite(nb[1])) v[a] = (nb[0] - nb[1]) * 0.5;
                        else if (std::isfinite(nb[0])) v[a] = nb[0] - C[c];
                        else if (std::isfinite(nb[1])) v[a] = C[c] - nb[1];
                    }
                    if (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] < 1e-24 && low_axis >= 0) v[low_axis] = low_side;
                }
                const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                for (int a = 0; a < 3; ++a) o[a] = len > 0 ? float(v[a] / len) : 0.0f;
                o[3] = std::isfinite(C[c]) ? float(C[c]) : 1e30f;
            }
}

}  // namespace swarmcl

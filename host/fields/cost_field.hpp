// The minimum cost field of the curl-noise paper (§5, Eq. 4, 6, 7) and the
// global velocity directions it gives (Eq. 8), on the host in double.
#pragma once
#include <array>
#include <vector>

#include "fields/fast_marching.hpp"
#include "fields/grid3.hpp"

namespace swarmcl {

// A goal region: where the cost is 0.
struct Goal {
    enum class Kind { Point, Sphere, Box } kind = Kind::Point;
    std::array<float, 3> center{};
    float radius = 0.0f;                  // sphere
    std::array<float, 3> half_extents{};  // box
};

struct CostWeights {
    double A = 0.6;  // path length weight (§5, "0.6 and 0.4")
    double B = 0.4;  // repulsion weight
};

// Eq. 6: the bell function h(r) of Wyvill et al. with r = phi / (2a),
// a = sqrt(2) l (l: the cell edge).  1 inside obstacles, 0 beyond 2a.
double repulsion(double phi, double cell);

// |grad C| = A + B g(phi) per cell (Eq. 4 as an eikonal equation; Eq. 7
// writes it per cell).  Cells whose centre lies inside an obstacle
// (phi <= 0) are impassable: +inf.  phi may be empty (no obstacles).
std::vector<double> cost_slowness(const Grid3& grid, const std::vector<float>& phi, const CostWeights& w);

// Validates goals against the grid: each must be finite, reach the grid and
// (with `slowness`) not lie only in impassable cells.  Error(InvalidArgument)
// naming goal `i`.
void check_goals(const Grid3& grid, const std::vector<Goal>& goals, const std::vector<double>& slowness);

// C by fast marching from the goals: cells within a goal get 0; cells
// within 3 cells of a goal get slowness * distance to it, exactly (the
// march starts from a ring, as scikit-fmm does, so a point goal is not a
// one-cell square).  Impassable and unreachable cells keep +inf.  threads:
// FastMarchingOptions::threads (0: a second thread on large grids; 1: none).
std::vector<double> solve_cost(const Grid3& grid, const std::vector<double>& slowness, const std::vector<Goal>& goals,
                               bool second_order = false, unsigned threads = 0);

// Eq. 8 without s0: -grad C / |grad C| per cell, by central differences where
// both neighbours are finite and one-sided ones otherwise; where that
// vanishes (a plateau) towards the lowest neighbour; 0 inside goals (C = 0).
// Inside obstacles (C = inf) the direction leads out: +grad phi.  xyz per cell
// in out[4c..4c+2], out[4c+3] = C (1e30 where C is infinite).
void direction_field(const Grid3& grid, const std::vector<double>& cost, const std::vector<float>& phi,
                     float* out);

}  // namespace swarmcl

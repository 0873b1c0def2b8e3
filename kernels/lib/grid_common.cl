// Kernel-side helpers of the uniform neighbour grid, shared by every kernel
// that iterates neighbours (queries here, the behaviour models later).
//
// The grid covers the swarm's domain with cubic cells of edge `cell`; cell
// (x, y, z) has index x + dims.x * (y + dims.y * z), so the cells of one
// x-row are contiguous and so are their agents after the sort: a search box
// is walked row by row, one agent range per row.
//
// Agents outside the domain are clamped into the border cells.  Clamping is
// monotone and 1-Lipschitz, so every agent within distance r of p still lies
// in the clamped box [cell(p - r), cell(p + r)]: queries stay exact, only
// slower when many agents are outside.

// No fused multiply-add: distances round as in the C++ references, so the
// decision "within r" is the same on every device.
#pragma OPENCL FP_CONTRACT OFF

typedef struct {
    float4 origin;        // domain minimum corner (w unused)
    float inv_cell;       // 1 / cell edge
    int4 dims;            // cells per axis (w unused)
    __global const uint* cell_start;  // agent range of cell c: [start[c], start[c+1]) - slot_base
    uint slot_base;       // first slot of the grid's world (0 without worlds)
} Grid;

#define GRID_PARAMS float4 grid_origin, float grid_inv_cell, int4 grid_dims, \
                    __global const uint* grid_cell_start
#define GRID_MAKE() grid_make(grid_origin, grid_inv_cell, grid_dims, grid_cell_start)

static inline Grid grid_make(float4 origin, float inv_cell, int4 dims, __global const uint* cell_start) {
    Grid g;
    g.origin = origin;
    g.inv_cell = inv_cell;
    g.dims = dims;
    g.cell_start = cell_start;
    g.slot_base = 0u;
    return g;
}

// Worlds (docs/architecture.md, "Worlds"): a swarm of W worlds of n agents
// each keeps world w's agents in slots [w n, (w + 1) n) and its cells in a
// range of one cell_start array (the grid's keys are the world's first cell
// + cell, kernels/grid.cl).  Each world has the grid of its own domain:
// grid_worlds[2 w] holds its origin (xyz) and 1 / cell edge (w),
// grid_worlds[2 w + 1] its cells per axis (xyz, int bits) and its first
// cell (w, uint bits); the host writes the values a swarm alone passes as
// GRID_PARAMS.  A kernel launched over (work-items, W) works on world
// get_global_id(1): it offsets its per-agent pointers by w n, and sees its
// world's grid through this view, whose ranges are slots of the world (from
// 0), so the kernel body is the one of a swarm alone, and world w gives
// bitwise that swarm's run.  The view is compiled in with -DSWCL_WORLDS only
// (a swarm of several worlds): on sm_90 world offsets cost the field model's
// kernel registers, so a swarm of one world keeps the kernels as they were.
#define GRID_WORLD_PARAMS GRID_PARAMS, __global const float4* grid_worlds
#ifdef SWCL_WORLDS
#define GRID_MAKE_WORLD(n) grid_world_view(GRID_MAKE(), grid_worlds, (n))
#else
#define GRID_MAKE_WORLD(n) GRID_MAKE()
#endif
// World w's grid (its cell ranges still count slots from the swarm's first).
static inline Grid grid_of_world(Grid g, __global const float4* worlds, uint w) {
    const float4 a = worlds[2u * w], b = worlds[2u * w + 1u];
    g.origin = (float4)(a.xyz, 0.0f);
    g.inv_cell = a.w;
    g.dims = (int4)(as_int(b.x), as_int(b.y), as_int(b.z), 0);
    g.cell_start += as_uint(b.w);
    return g;
}
static inline Grid grid_world_view(Grid g, __global const float4* worlds, uint n) {
    const uint w = (uint)get_global_id(1);
    g = grid_of_world(g, worlds, w);
    g.slot_base = w * n;
    return g;
}

// Cell coordinate of one axis, clamped to [0, n-1].  Clamped in float first,
// so huge coordinates cannot overflow the int conversion, then truncated:
// on [0, n-1] truncation is floor, and below 0 or above n-1 both orders give
// the same bound.  Several times faster on PoCL than floor() then clamp.
static inline int grid_axis(float x, float origin, float inv_cell, int n) {
    return (int)clamp((x - origin) * inv_cell, 0.0f, (float)(n - 1));
}

static inline int4 grid_cell_of(const Grid* g, float4 p) {
    return (int4)(grid_axis(p.x, g->origin.x, g->inv_cell, g->dims.x),
                  grid_axis(p.y, g->origin.y, g->inv_cell, g->dims.y),
                  grid_axis(p.z, g->origin.z, g->inv_cell, g->dims.z), 0);
}

static inline uint grid_cell_index(const Grid* g, int4 c) {
    return (uint)c.x + (uint)g->dims.x * ((uint)c.y + (uint)g->dims.y * (uint)c.z);
}

// The box of cells holding every agent within distance r of p.
static inline void grid_search_box(const Grid* g, float4 p, float r, int4* lo, int4* hi) {
    *lo = grid_cell_of(g, p - (float4)(r, r, r, 0.0f));
    *hi = grid_cell_of(g, p + (float4)(r, r, r, 0.0f));
}

// Agent slots of the cells x0..x1 of row (y, z): [range.x, range.y).
static inline uint2 grid_row_range(const Grid* g, int x0, int x1, int y, int z) {
    const uint row = (uint)g->dims.x * ((uint)y + (uint)g->dims.y * (uint)z);
    return (uint2)(g->cell_start[row + (uint)x0], g->cell_start[row + (uint)x1 + 1u]) - g->slot_base;
}

// Iterates the slots j of every agent that may lie within r of p:
//   GRID_FOR_EACH_CANDIDATE(&g, p, r, j) { ... uses j ... } GRID_END_FOR
#define GRID_FOR_EACH_CANDIDATE(gp, p, r, j)                                   \
    {                                                                          \
        int4 grid_lo_, grid_hi_;                                               \
        grid_search_box((gp), (p), (r), &grid_lo_, &grid_hi_);                 \
        for (int grid_z_ = grid_lo_.z; grid_z_ <= grid_hi_.z; ++grid_z_)       \
            for (int grid_y_ = grid_lo_.y; grid_y_ <= grid_hi_.y; ++grid_y_) { \
                const uint2 grid_rng_ = grid_row_range((gp), grid_lo_.x, grid_hi_.x, grid_y_, grid_z_); \
                for (uint j = grid_rng_.x; j < grid_rng_.y; ++j)
#define GRID_END_FOR }}

// The slot ranges of the cells of box [lo, hi] outside the previous box
// [plo, phi] (none: plo > phi), row by row (z, y, then x ascending), as a
// nearest-neighbour search that grows its box one cell a side each time
// visits them: a row outside the previous box whole, a row through it in
// the parts left and right of it.
//   GRID_FOR_EACH_NEW_RANGE(&g, lo, hi, plo, phi, rg) { ... rg.x, rg.y ... } GRID_END_NEW_RANGE
#define GRID_FOR_EACH_NEW_RANGE(gp, lo, hi, plo, phi, rg)                                                    \
    for (int gn_z_ = (lo).z; gn_z_ <= (hi).z; ++gn_z_)                                                     \
        for (int gn_y_ = (lo).y; gn_y_ <= (hi).y; ++gn_y_)                                                 \
            for (int gn_part_ = 0; gn_part_ < 2; ++gn_part_) {                                             \
                const bool gn_inner_ = gn_z_ >= (plo).z && gn_z_ <= (phi).z && gn_y_ >= (plo).y && gn_y_ <= (phi).y; \
                if (!gn_inner_ && gn_part_ == 1) break;                                                     \
                const int gn_x0_ = !gn_inner_ || gn_part_ == 0 ? (lo).x : (phi).x + 1;                      \
                const int gn_x1_ = !gn_inner_ || gn_part_ == 1 ? (hi).x : (plo).x - 1;                      \
                if (gn_x0_ > gn_x1_) continue;                                                              \
                const uint2 rg = grid_row_range((gp), gn_x0_, gn_x1_, gn_y_, gn_z_);
#define GRID_END_NEW_RANGE }

static inline float dist2(float4 a, float4 b) {
    const float4 d = a - b;
    return d.x * d.x + d.y * d.y + d.z * d.z;
}

// Rows of the search box trimmed to the balls of radius r around the points
// of the box [a, b] (one point: a = b = p): row (y, z) can hold an agent
// within r of one of them only if r^2 >= ey^2 + ez^2, where ey (ez) is the
// distance from the box's interval along y (z) to the row's slab; border
// slabs extend to infinity (agents outside the domain are clamped into
// them).  Then the agent's x lies in [a.x - rx, b.x + rx], rx = sqrt(r^2 -
// ey^2 - ez^2), so the row's cells [cell(a.x - rx), cell(b.x + rx)] hold all
// of them (cell() is monotone); each point's own range lies inside (its slab
// distances are at least the box's).  Returns false for a row that can hold
// none.  About half the cells of the box for r = 2 cells and one point.  The
// slab distances are shrunk by a tolerance far above their float rounding (a
// few ulp of the coordinates' magnitude), so rounding never drops an agent;
// r is widened likewise.
#include "lib/inline.cl"
SWCL_ALWAYS_INLINE static inline float grid_slab_distance_iv(float a, float b, float origin, float cell, int k,
                                                              int n) {
    const float lo = k == 0 ? -INFINITY : origin + (float)k * cell;
    const float hi = k == n - 1 ? INFINITY : origin + (float)(k + 1) * cell;
    const float tol = 2e-6f * (fmax(fabs(a), fabs(b)) + fabs(origin) + cell * (float)n);
    return fmax(0.0f, fmax(lo - b, a - hi) - tol);
}
SWCL_ALWAYS_INLINE static inline float grid_slab_distance(float x, float origin, float cell, int k, int n) {
    return grid_slab_distance_iv(x, x, origin, cell, k, n);
}

SWCL_ALWAYS_INLINE static inline bool grid_row_x_range_box(const Grid* g, float4 a, float4 b, float r, int y, int z,
                                                           int* x0, int* x1) {
    const float cell = 1.0f / g->inv_cell;
    const float ey = grid_slab_distance_iv(a.y, b.y, g->origin.y, cell, y, g->dims.y);
    const float ez = grid_slab_distance_iv(a.z, b.z, g->origin.z, cell, z, g->dims.z);
    const float rr = r * 1.00001f;
    const float rem = rr * rr - ey * ey - ez * ez;
    if (rem < 0.0f) return false;
    const float rx = sqrt(rem);
    *x0 = grid_axis(a.x - rx, g->origin.x, g->inv_cell, g->dims.x);
    *x1 = grid_axis(b.x + rx, g->origin.x, g->inv_cell, g->dims.x);
    return true;
}
SWCL_ALWAYS_INLINE static inline bool grid_row_x_range(const Grid* g, float4 p, float r, int y, int z, int* x0, int* x1) {
    return grid_row_x_range_box(g, p, p, r, y, z, x0, x1);
}

// grid_axis and grid_slab_distance for 8 cells at once (k: their
// coordinates along the axis), the same operations lane by lane, so the same
// results: a caller trims 8 rows of the search box with one vector pass.
static inline int8 grid_axis8(float8 x, float origin, float inv_cell, int n) {
    return convert_int8(clamp((x - origin) * inv_cell, 0.0f, (float)(n - 1)));
}

static inline float8 grid_slab_distance8(float x, float origin, float cell, int8 k, int n) {
    const float8 lo = select(origin + convert_float8(k) * cell, (float8)(-INFINITY), k == (int8)(0));
    const float8 hi = select(origin + convert_float8(k + 1) * cell, (float8)(INFINITY), k == (int8)(n - 1));
    const float tol = 2e-6f * (fabs(x) + fabs(origin) + cell * (float)n);
    return fmax((float8)(0.0f), fmax(lo - x, x - hi) - tol);
}

// The grid of a geometry buffer (point_grid.cl, spatial/point_grid.hpp):
// geo[0] = origin xyz and 1 / cell edge in w; geo[1] = cells per axis and
// their product, as int bits.
static inline Grid grid_from_geometry(__global const float4* geo, __global const uint* cell_start) {
    const float4 a = geo[0], b = geo[1];
    return grid_make((float4)(a.xyz, 0.0f), a.w, (int4)(as_int(b.x), as_int(b.y), as_int(b.z), 0), cell_start);
}


// Lower bound of the distance from p to any agent outside the cell box
// [lo, hi]: the distance to the nearest box face, where faces on the grid's
// border are at infinity (border cells also hold the clamped agents beyond).
// Shrunk slightly so float rounding of cell assignment cannot make it too big.
SWCL_INLINE float grid_outside_bound(const Grid* g, float4 p, int4 lo, int4 hi) {
    const float cell = 1.0f / g->inv_cell;
    float bound = INFINITY;
    const float pc[3] = {p.x, p.y, p.z};
    const float oc[3] = {g->origin.x, g->origin.y, g->origin.z};
    const int l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    const int d[3] = {g->dims.x, g->dims.y, g->dims.z};
    for (int a = 0; a < 3; ++a) {
        if (l[a] > 0) {
            const float face = oc[a] + (float)l[a] * cell;
            bound = fmin(bound, pc[a] - face - 1e-5f * (fabs(face) + cell));
        }
        if (h[a] < d[a] - 1) {
            const float face = oc[a] + (float)(h[a] + 1) * cell;
            bound = fmin(bound, face - pc[a] - 1e-5f * (fabs(face) + cell));
        }
    }
    return bound;
}

// force_model_repulsion (SWCL_BW = 1) and force_model_repulsion_w (SWCL_BW =
// SWCL_W, CPU devices; launch ceil(n / SWCL_W)): §4.1, Eq. 2-3, the
// repulsion zone of SWCL_BW consecutive agents of the fine grid's order
// (neighbours in a row of fine cells): every agent within R_rep through the
// fine grid (exact), in the fine grid's order; the agent itself (r_ij = 0)
// is skipped with any coincident one.  rep[slot] = (the sum, its count as
// uint bits); the force kernels read it by slot.  The lanes are taken a row
// (y, z) of their cells at a time, and the union of those lanes' R_rep boxes
// is walked once, each candidate tested against all of them.  A lane's own
// box lies inside the union and both walks go row by row in slot order, so
// each lane meets its neighbours in the order of its own box with the same
// arithmetic at every width (the extra candidates are farther than R_rep and
// fail the test).  Included by force_model.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(force_model_repulsion)(__global const float* fine_soa, __global const uint* fine_slot,
                                                 uint n, __global const float4* fine_geo,
                                                 __global const uint* fine_start, __global const float* params,
                                                 __global float4* rep_out) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
    // Worlds: the world's fine cells, sorted copy and parameters
    // (force_model.cl); rep_out is by slot of the swarm, as fine_slot.
    FM_FINE_WORLD_VIEW(fine_geo, fine_start, fine_slot)
    FM_SOA_WORLD(fine_soa)
    FM_WORLD_PARAMS(params)
    // A world whose force kernel sums the repulsion zone itself.
    if (FM_REP_IN_WALK(as_uint(params[FORCE_TERMS]), as_uint(params[FORCE_NEIGHBOR_SAMPLE]), params[FORCE_R_REP],
                       params[FORCE_R_ATT], n))
        return;
    Grid fg = fm_fine_grid(fine_geo, fine_start);
    FM_FINE_SLOT_BASE(fg)
    const uint stride = n + FM_SOA_PAD;
    // FM_SOA_PAD >= SWCL_W - 1 readable floats after each block.
    const swcl_bf px = SWCL_BVLOAD(fine_soa + base), py = SWCL_BVLOAD(fine_soa + stride + base),
                  pz = SWCL_BVLOAD(fine_soa + 2 * stride + base);
    const swcl_bu k = (swcl_bu)(base) + SWCL_BLANE_IDS;
    const swcl_bi live = k < n;
    const float r_rep = params[FORCE_R_REP];  // the parameter block (force_params.cpp)
    const float r_rep2 = r_rep * r_rep;
    // Each lane's row of fine cells (only groups the lanes).
    const swcl_bi row = swcl_bcvt_i(clamp((py - fg.origin.y) * fg.inv_cell, 0.0f, (float)(fg.dims.y - 1))) +
                        fg.dims.y * swcl_bcvt_i(clamp((pz - fg.origin.z) * fg.inv_cell, 0.0f, (float)(fg.dims.z - 1)));
    const swcl_bf zero = (swcl_bf)(0.0f);
    swcl_bf rep_x = zero, rep_y = zero, rep_z = zero;
    swcl_bu n_rep = (swcl_bu)(0u);
    swcl_bi todo = live;
    while (SWCL_BANY(todo)) {
        int r0 = 0;
        bool found = false;
#define FM_FIRST_ROW_(l) if (!found && SWCL_BLANE(todo, l)) { r0 = SWCL_BLANE(row, l); found = true; }
        SWCL_BEACH_LANE(FM_FIRST_ROW_)
#undef FM_FIRST_ROW_
        const swcl_bi on = todo & (row == r0);
        todo &= ~on;
        FM_LANES_WALK(&fg, px, py, pz, on, r_rep, FM_ALL_Z, j) {
            const float qx = fine_soa[j], qy = fine_soa[stride + j], qz = fine_soa[2 * stride + j];
            const swcl_bf dx = qx - px, dy = qy - py, dz = qz - pz;
            const swcl_bf d2 = fma(dz, dz, fma(dy, dy, dx * dx));  // as the zone walk's (fm_zone_s)
            const swcl_bi hit = on & (d2 < r_rep2) & (d2 != 0.0f);
            if (SWCL_BANY(hit)) {
                const swcl_bf rs = rsqrt(d2);
                rep_x = select(rep_x, fma(-dx, rs, rep_x), hit);
                rep_y = select(rep_y, fma(-dy, rs, rep_y), hit);
                rep_z = select(rep_z, fma(-dz, rs, rep_z), hit);
                SWCL_BCOUNT_IF(n_rep, hit);
            }
        }
        FM_LANES_WALK_END
    }
#define FM_STORE_REP_(l)                                                                                        \
    if (base + SWCL_BLANE_I(l) < n)                                                                             \
        rep_out[fine_slot[base + SWCL_BLANE_I(l)]] = (float4)(SWCL_BLANE(rep_x, l), SWCL_BLANE(rep_y, l),         \
                                                              SWCL_BLANE(rep_z, l), as_float(SWCL_BLANE(n_rep, l)));
    SWCL_BEACH_LANE(FM_STORE_REP_)
#undef FM_STORE_REP_
}

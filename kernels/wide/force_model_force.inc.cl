// force_model_force (SWCL_BW = 1: one agent per work-item) and
// force_model_force_w (SWCL_BW = SWCL_W consecutive slots per work-item, CPU
// devices; launch ceil(n / SWCL_W)): the union force of Eq. 1 for each agent,
// one body, so every term has the same tests and arithmetic in the same
// order at every width (bitwise the same forces: tests/test_force_model.cpp).
// PoCL does not vectorise the scalar kernel across work-items, so on CPUs
// the wide one runs every term in floatW lanes: each candidate of the shared
// sample and of the union of the lanes' R_att boxes (exact zones) is loaded
// once and tested against all lanes (fm_ali_att_w; at width 1 fm_ali_att_s
// branches as the scalar code always did); Eq. 5's target neighbours are
// gathered per lane.  Repulsion comes from force_model_repulsion(_w), in the
// fine grid's order, read by slot.  Included by force_model.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(force_model_force)(FM_FORCE_PARAMS) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1) (force_model.cl, "worlds"): its agents, forces,
    // repulsion sums, parameter and noise blocks; the grid's view of its
    // cells; its agents' targets (target_of, by id) and their positions by
    // target (by_target).  The targets themselves are one for every world.
    FM_WORLD_AGENTS(target_of)
    FM_WORLD_AGENTS(by_target)
    FM_WORLD_AGENTS(pos)
    FM_WORLD_AGENTS(vel)
    FM_WORLD_AGENTS(ids)
    FM_WORLD_AGENTS(force)
    FM_WORLD_AGENTS(rep_in)
    FM_WORLD_PARAMS(params)
    noise_block += get_global_id(1) * NOISE_BLOCK_FLOATS;
    noise_prims += get_global_id(1) * 2u * NOISE_B_UINT(NOISE_SLOT_NPRIMS);  // its walls at its own domain
#endif
    swcl_bf px, py, pz, ux, uy, uz;
    SWCL_BFN(fm_load_xyz)(pos, base, n, &px, &py, &pz);
    SWCL_BFN(fm_load_xyz)(vel, base, n, &ux, &uy, &uz);
    const Grid g = GRID_MAKE_WORLD(n);
    // The parameter block as the arguments they replace: the zone radii and
    // sigma = omega sqrt(A/N) (Eq. 5); the weights of Eq. 2 and 6; alpha,
    // w_con and the distance scale (0: 2 sqrt(A/N)).
    const float4 zones = (float4)(params[FORCE_R_REP], params[FORCE_R_ALI], params[FORCE_R_ATT],
                                  params[FORCE_OMEGA] * spacing);
    const float4 weights = (float4)(params[FORCE_W_REP], params[FORCE_W_ALI], params[FORCE_W_ATT], params[FORCE_W_DIS]);
    const float dscale = params[FORCE_DISTANCE_SCALE] > 0.0f ? params[FORCE_DISTANCE_SCALE] : 2.0f * spacing;
    const float4 blend = (float4)(params[FORCE_ALPHA], params[FORCE_W_CON], dscale, 0.0f);
    const uint terms = as_uint(params[FORCE_TERMS]), sample_cap = as_uint(params[FORCE_NEIGHBOR_SAMPLE]);

    // §4.1, Eq. 2-3: each neighbour counts in exactly one zone (S = -1, 0, 1
    // below R_rep, below R_ali, up to R_att); each zone's sum is averaged over
    // its own neighbours.  S = +-1 leaves the unit direction r_ij/|r_ij|
    // (towards the neighbour for attraction, away for repulsion); S = 0
    // leaves the unit velocity difference.  The paper's u_ij = u_i - u_j
    // would steer an insect away from its neighbours' velocity
    // (anti-alignment, against the zone's name and the paper's ref. 5), so
    // alignment uses u_j - u_i.  Coincident agents (r_ij = 0) have no
    // direction and are skipped; equal velocities add 0 but count.
    const swcl_bu self = (swcl_bu)(base) + SWCL_BLANE_IDS;
    const float r_rep2 = zones.x * zones.x, r_ali2 = zones.y * zones.y, r_att2 = zones.z * zones.z;
    const swcl_bf zero = (swcl_bf)(0.0f);
    swcl_bf rep_x = zero, rep_y = zero, rep_z = zero, ali_x = zero, ali_y = zero, ali_z = zero;
    swcl_bf att_x = zero, att_y = zero, att_z = zero;
    swcl_bu n_rep = (swcl_bu)(0u), n_ali = (swcl_bu)(0u), n_att = (swcl_bu)(0u);

    const swcl_bi live = self < n;
    // The repulsion zone in the walk of the exact zones below, or
    // force_model_repulsion(_w)'s sums and counts, by slot.
    const bool rep_in_walk = FM_REP_IN_WALK(terms, sample_cap, zones.x, zones.z, n);
    if ((terms & FM_REP) && !rep_in_walk)
        SWCL_BFN(fm_load_rep)(rep_in, base, n, &rep_x, &rep_y, &rep_z, &n_rep);
    // The exact zones walk the union of the lanes' R_att boxes (many cells
    // each, so the union adds few), each candidate tested against all lanes.
    // A lane's own box lies inside the union and both walks go row by row
    // (z, y) in slot order, so each lane meets its neighbours in the order of
    // its own box; the extra candidates are farther than R_att from it and
    // fail its distance test.  (Width 1: float4 sums around the pass,
    // fm_zones_begin_s.)
    if (terms & (FM_ALI | FM_ATT)) {
        SWCL_BFN(fm_zones_begin)
        // The swarm grid was built on pos this step (ForceModel::advance).
        const int2 zs = fm_occupied_z(&g, pos, n);
        if (sample_cap == 0u && rep_in_walk) {
            FM_LANES_WALK(&g, px, py, pz, live, zones.z, zs, j) {
                SWCL_BFN(fm_rep_ali_att)(j);
            }
            FM_LANES_WALK_END
        } else if (sample_cap == 0u) {
            FM_LANES_WALK(&g, px, py, pz, live, zones.z, zs, j) {
                SWCL_BFN(fm_ali_att)(j);
            }
            FM_LANES_WALK_END
        } else {
            // Sampled (not in the paper; docs/force-model.md): sample_cap
            // agents of the whole swarm, j = start + k * stride (mod n) with
            // start and stride drawn per sample group and step by Philox
            // (fm_sample_start): for each agent every other agent is equally
            // likely to be sampled, and slots being in cell order, a large
            // stride spreads the sample over the swarm.  The 16 agents of a
            // group (neighbours in cell order) share the sample, so the lanes
            // (SWCL_W divides FM_SAMPLE_GROUP) load each sampled agent once.
            // Those within R_att count in their zone, so each zone's mean in
            // Eq. 2 is estimated from its sampled neighbours, at O(cap) per
            // agent instead of the O(N) that R_att = 30 m costs when the swarm
            // is smaller than that.
            uint stride;
            uint j = fm_sample_start(seed, base / FM_SAMPLE_GROUP, step, n, &stride);
            for (uint k = 0; k < sample_cap; ++k) {
                SWCL_BFN(fm_ali_att)(j);
                j += stride;
                if (j >= n) j -= n;
            }
        }
        SWCL_BFN(fm_zones_end)
    }

    swcl_bf fx = zero, fy = zero, fz = zero;
    if (terms & FM_REP) {
        FM_ADD_MEAN(fx, weights.x, n_rep, rep_x);
        FM_ADD_MEAN(fy, weights.x, n_rep, rep_y);
        FM_ADD_MEAN(fz, weights.x, n_rep, rep_z);
    }
    if (terms & FM_ALI) {
        FM_ADD_MEAN(fx, weights.y, n_ali, ali_x);
        FM_ADD_MEAN(fy, weights.y, n_ali, ali_y);
        FM_ADD_MEAN(fz, weights.y, n_ali, ali_z);
    }
    if (terms & FM_ATT) {
        FM_ADD_MEAN(fx, weights.z, n_att, att_x);
        FM_ADD_MEAN(fy, weights.z, n_att, att_y);
        FM_ADD_MEAN(fz, weights.z, n_att, att_z);
    }
    // §4.2, Eq. 4: curl of the Perlin potential (p(s1), p(s2), p(s3))(r / rho)
    // * eta, from the noise module with scale = rho and gain = eta / rho (the
    // module takes the curl in noise coordinates, Eq. 4 in metres).  The
    // agent id matters to the random noises only (width 1).
    if (terms & FM_CUR) {
        swcl_bf cx, cy, cz;
        NOISE_VELOCITY_B(px, py, pz, t, ids[base], step, &cx, &cy, &cz);
        fx += cx; fy += cy; fz += cz;
    }

    swcl_bf ex = zero, ey = zero, ez = zero;
    if (has_targets) {
        // Each lane's target (lanes at or above n: agent n - 1's).
        const swcl_bu tgt = SWCL_BFN(fm_gather_u)(target_of, SWCL_BFN(fm_gather_u)(ids, SWCL_BLAST(self, n)));
        if (terms & FM_CON) {
            // §5.2, Eq. 5 on the insects: the sample neighbours of this
            // insect's target are the targets of other insects; their current
            // positions push this insect away with a Gaussian of the Manhattan
            // distance, spreading the swarm over the surface ("we use F_con to
            // scatter the insects along the mesh").  sigma is a length
            // (docs/force-model.md); w_con times the mean.  In lanes: each
            // lane's target neighbours, up to the longest list; finished
            // lanes read slot 0 (always there) and add nothing.
            const swcl_bu k0 = SWCL_BFN(fm_gather_u)(nbr_start, tgt);
            const swcl_bu cnt = select((swcl_bu)(0u), SWCL_BFN(fm_gather_u)(nbr_start, tgt + 1u) - k0, live);
            uint longest = 0;
#define FM_LONGEST_(k) longest = max(longest, SWCL_BLANE(cnt, k));
            SWCL_BEACH_LANE(FM_LONGEST_)
#undef FM_LONGEST_
            const float inv2s2 = 1.0f / (2.0f * zones.w * zones.w);
            __global const float* bf = (__global const float*)by_target;
            swcl_bf cx = zero, cy = zero, cz = zero;
            for (uint k = 0; k < longest; ++k) {
                const swcl_bi act = (swcl_bu)(k) < cnt;
                const swcl_bu at = select((swcl_bu)(0u), k0 + k, act);
                const swcl_bu o = select((swcl_bu)(0u), SWCL_BFN(fm_gather_u)(nbr_index, at), act);
                const swcl_bf qx = px - SWCL_BFN(fm_gather)(bf, o, 0), qy = py - SWCL_BFN(fm_gather)(bf, o, 1),
                              qz = pz - SWCL_BFN(fm_gather)(bf, o, 2);
                const swcl_bf m = fabs(qx) + fabs(qy) + fabs(qz);
                const swcl_bf l = sqrt(qx * qx + qy * qy + qz * qz);
                const swcl_bf el = exp(-m * m * inv2s2) / l;  // one division, not three
                const swcl_bi on = act & (l > 0.0f);
                cx = select(cx, cx + el * qx, on);
                cy = select(cy, cy + el * qy, on);
                cz = select(cz, cz + el * qz, on);
            }
            const swcl_bf wc = blend.y / swcl_bcvt_f(cnt);
            const swcl_bi some = cnt != 0u;
            ex += select(zero, wc * cx, some);
            ey += select(zero, wc * cy, some);
            ez += select(zero, wc * cz, some);
        }
        // §5.3, Eq. 6-7: the harmonic distance force along the unit vector to
        // the target, with d normalised by the distance scale and clamped to
        // 1 (the paper's H(d) = 0 beyond 1 would leave far insects with no
        // pull at all).  4 (d - 0.5)^(1/3) + 0.5 is positive (towards the
        // target) above d = 0.498 and negative below: insects hover about
        // their target instead of sitting on it.
        if (terms & FM_DIS) {
            __global const float* tf = (__global const float*)targets;
            const swcl_bf tx = SWCL_BFN(fm_gather)(tf, tgt, 0), ty = SWCL_BFN(fm_gather)(tf, tgt, 1),
                          tz = SWCL_BFN(fm_gather)(tf, tgt, 2);
            const swcl_bf rx = FM_ROW(frame_x, tx, ty, tz) - px, ry = FM_ROW(frame_y, tx, ty, tz) - py,
                          rz = FM_ROW(frame_z, tx, ty, tz) - pz;
            const swcl_bf dd = sqrt(rx * rx + ry * ry + rz * rz);
            const swcl_bf dn = fmin(dd / blend.z, 1.0f);
            const swcl_bf h = weights.w * (4.0f * cbrt(dn - 0.5f) + 0.5f) / dd;
            const swcl_bi on = dd > 0.0f;
            ex = select(ex, ex + h * rx, on);
            ey = select(ey, ey + h * ry, on);
            ez = select(ez, ez + h * rz, on);
        }
    }
    // §3, Eq. 1.
    SWCL_BFN(fm_store)(force, base, n, blend.x * fx + (1.0f - blend.x) * ex, blend.x * fy + (1.0f - blend.x) * ey,
                       blend.x * fz + (1.0f - blend.x) * ez);
}

// Minimum distance enforcement (curl-noise paper §6, after Treuille et al.
// 2006): every pair closer than d_min is pushed apart, each agent by half the
// overlap along the pair's direction.  Jacobi style — every agent reads the
// positions before the pass and writes a new array — so the result does not
// depend on the order agents are processed in.
#include "grid_common.cl"
#include "philox.cl"

#define SWCL_STREAM_MDE 3u

// Direction for two agents on the same point: a Philox direction keyed by the
// pair, pointing opposite ways for the two, so they separate deterministically.
inline float3 coincident_direction(ulong seed, uint self, uint other) {
    const uint lo = min(self, other), hi = max(self, other);
    const float4 u = swcl_rand_uniform4(seed, lo, hi, SWCL_STREAM_MDE);
    float3 d = (float3)(2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f, 2.0f * u.z - 1.0f + 1e-3f);
    d = normalize(d);
    return self < other ? d : -d;
}

__kernel void min_distance_enforce(__global const float4* pos, __global const uint* ids, uint n,
                                   GRID_PARAMS, float d_min, ulong seed, __global float4* out,
                                   __global volatile uint* moved) {
    // moved[0]: agents moved in this pass; moved[1]: summed over passes.
    const uint i = get_global_id(0);
    if (i >= n) return;
    const Grid g = GRID_MAKE();
    const float4 p = pos[i];
    const float d2_min = d_min * d_min;
    float3 push = (float3)(0.0f);
    bool touched = false;
    GRID_FOR_EACH_CANDIDATE(&g, p, d_min, j) {
        if (j == i) continue;
        const float d2 = dist2(p, pos[j]);
        if (d2 >= d2_min) continue;
        const float d = sqrt(d2);
        const float3 dir = d > 0.0f ? (p.xyz - pos[j].xyz) / d : coincident_direction(seed, ids[i], ids[j]);
        push += 0.5f * (d_min - d) * dir;
        touched = true;
    } GRID_END_FOR
    out[i] = (float4)(p.xyz + push, 0.0f);
    if (touched) {
        atomic_inc(&moved[0]);
        atomic_inc(&moved[1]);
    }
}

// The pair rule of minimum distance enforcement (curl-noise paper §6), shared
// by the MDE pass (min_distance.cl) and the force model's own pass over its
// fine grid (force_model.cl), so both push alike.
#include "lib/grid_common.cl"
#include "lib/philox.cl"

#define SWCL_STREAM_MDE 3u

// Direction for two agents on the same point: a Philox direction keyed by the
// pair, pointing opposite ways for the two, so they separate deterministically.
static inline float3 coincident_direction(ulong seed, uint self, uint other) {
    const uint lo = min(self, other), hi = max(self, other);
    const float4 u = swcl_rand_uniform4(seed, lo, hi, SWCL_STREAM_MDE);
    float3 d = (float3)(2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f, 2.0f * u.z - 1.0f + 1e-3f);
    d = normalize(d);
    return self < other ? d : -d;
}

// One candidate of a pass: the agent in slot i at p is pushed away from the
// one in slot j by half their overlap when they are closer than d_min.  Uses
// the caller's pos, ids, seed, d_min, d2_min, p, push and touched.
#define MDE_CANDIDATE(i, j)                                                                          \
    {                                                                                                \
        const float4 q_ = pos[j];                                                                    \
        const float d2_ = dist2(p, q_);                                                              \
        if ((j) != (i) && d2_ < d2_min) {                                                            \
            const float d_ = sqrt(d2_);                                                              \
            const float3 dir_ = d_ > 0.0f ? (p.xyz - q_.xyz) / d_ : coincident_direction(seed, ids[i], ids[j]); \
            push += 0.5f * (d_min - d_) * dir_;                                                      \
            touched = true;                                                                          \
        }                                                                                            \
    }

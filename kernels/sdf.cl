// Signed distance to a triangle mesh on a grid (curl-noise paper §5.1,
// Eq. 5; Baerentzen & Aanaes 2005 for the sign), narrow band only: every
// cell centre within `band` of the mesh gets its exact distance, the sign
// of the angle-weighted pseudonormal of the closest feature and the closest
// point; the host fills the rest by propagating closest points
// (host/fields/sdf.cpp).
//
// The host bins triangles into bricks of SDF_BRICK^3 cells (4: shorter lists than 8, 2-3x faster at 128^3): a brick lists
// every triangle whose bounding box, grown by `band`, meets the brick, so
// every triangle within `band` of a cell is in its brick's list.
// Plain C++ reference: tests/reference/sdf_reference.hpp (same algorithm in double).
#pragma OPENCL FP_CONTRACT OFF

#ifndef SDF_BRICK
#define SDF_BRICK 4
#endif

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
// Detection, 5.1.5) and the feature it lies on: 0 face, 1-3 vertex a/b/c,
// 4-6 edge ab/bc/ca.
static inline float3 sdf_closest(float3 p, float3 a, float3 b, float3 c, int* feature) {
    const float3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) { *feature = 1; return a; }
    const float3 bp = p - b;
    const float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) { *feature = 2; return b; }
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) { *feature = 4; return a + (d1 / (d1 - d3)) * ab; }
    const float3 cp = p - c;
    const float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) { *feature = 3; return c; }
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) { *feature = 6; return a + (d2 / (d2 - d6)) * ac; }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
        *feature = 5;
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    const float denom = 1.0f / (va + vb + vc);
    *feature = 0;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// tris: per triangle SDF_TRI_STRIDE float4: corners a, b, c, then the
// pseudonormals of the face, vertices a, b, c, edges ab, bc, ca (feature order).
#define SDF_TRI_STRIDE 10

// One work-item per cell of the active bricks (brick_ids[get_global_id(0) /
// SDF_BRICK^3]); phi is the whole grid, written only for cells within band.
__kernel void sdf_band(__global const float4* tris, __global const uint* brick_start,
                       __global const uint* brick_tris, __global const uint* active, uint nactive,
                       int4 dims, int4 bricks, float4 origin_h, float band, __global float* phi,
                       __global float4* closest) {
    const uint gid = get_global_id(0);
    const uint per = SDF_BRICK * SDF_BRICK * SDF_BRICK;
    if (gid >= nactive * per) return;
    const uint brick = active[gid / per], cell = gid % per;
    const int bx = (int)(brick % (uint)bricks.x), by = (int)((brick / (uint)bricks.x) % (uint)bricks.y),
              bz = (int)(brick / (uint)(bricks.x * bricks.y));
    const int x = bx * SDF_BRICK + (int)(cell % SDF_BRICK);
    const int y = by * SDF_BRICK + (int)((cell / SDF_BRICK) % SDF_BRICK);
    const int z = bz * SDF_BRICK + (int)(cell / (SDF_BRICK * SDF_BRICK));
    if (x >= dims.x || y >= dims.y || z >= dims.z) return;
    const float h = origin_h.w;
    const float3 p = (float3)(origin_h.x + ((float)x + 0.5f) * h, origin_h.y + ((float)y + 0.5f) * h,
                              origin_h.z + ((float)z + 0.5f) * h);
    float best = MAXFLOAT;
    float3 best_q = p;
    uint best_t = 0;
    int best_f = 0;
    for (uint k = brick_start[brick]; k < brick_start[brick + 1]; ++k) {
        const uint t = brick_tris[k];
        __global const float4* T = tris + SDF_TRI_STRIDE * t;
        int f;
        const float3 q = sdf_closest(p, T[0].xyz, T[1].xyz, T[2].xyz, &f);
        const float3 d = p - q;
        const float d2 = dot(d, d);
        if (d2 < best) { best = d2; best_q = q; best_t = t; best_f = f; }
    }
    const float dist = sqrt(best);
    if (!(dist <= band)) return;
    const float3 n = tris[SDF_TRI_STRIDE * best_t + 3 + best_f].xyz;
    const float s = dot(p - best_q, n) < 0.0f ? -1.0f : 1.0f;
    const size_t c = x + (size_t)dims.x * (y + (size_t)dims.y * z);
    phi[c] = s * dist;
    closest[c] = (float4)(best_q, s);  // where the exact transform beyond the band starts
}

// swarmcl — kernels/curl_noise.cl
//
// Curl noise (Bridson, Hourihan, Nordenstam 2007, "Curl-noise for procedural
// fluid flow") with the boundary-aware potential of the curl-noise paper
// (inherent-noise-aware swarm, §4, Eq. 1-3). OpenCL C 1.2, float only.
//
//   potential   psi(x)  = gain * (P1, P2, P3)(x / scale)                §4, P
//   boundary    N(x)    = alpha psi + (1 - alpha) (n . psi) n          §4, Eq. 2
//               alpha   = ramp(d(x) / d0),
//               ramp(r) = 15r/8 - 10r^3/8 + 3r^5/8 (r <= 1), 1 above    §4, Eq. 3
//   velocity    V(x)    = scale * curl_x N(x)                           §4, Eq. 1
//
// Choices where the paper is vague (also in docs/):
//  * Units of V. The paper writes V = curl N with P(x/scale)*gain; taken
//    literally |V| ~ gain/scale. We multiply by `scale`, i.e. take the curl
//    in noise coordinates u = x/scale, so `gain` alone sets the speed
//    (m/s) and `scale` (m) only the feature size; a constant factor keeps
//    div V = 0 and V.n = 0 on boundaries.
//  * "The closer x is to the boundaries, the larger value alpha has" (§4) is
//    a typo: Eq. 3 gives alpha(0) = 0 at the boundary and 1 for d >= d0, so
//    near a boundary only the normal part of psi survives (as Bridson).
//  * Product rule. N is differentiated as a whole (n = g/|g|, g = grad d):
//      dN_i/dx_j = psi_i da_j + alpha J_ij
//                  + (1 - alpha) (n_i dphi_j + phi G_ij) - phi n_i da_j,
//      phi = n . psi,  dphi = G^T psi + J^T n,  da = alpha'(r)/d0 g,
//      G = grad n = (I - n n^T) H / |g|   (= H for an exact distance),
//    with J = d psi/dx and H the Hessian of d. curl N is then the exact curl
//    of a C^1 potential: div V = 0 up to float rounding. On the boundary
//    (alpha = 0): curl N = da x psi + dphi x n + phi curl n; da is parallel
//    to n and curl n = grad(1/|g|) x g is perpendicular to n, so V.n = 0
//    exactly there. Dropping grad alpha or grad n (a common shortcut)
//    breaks both properties, hence d, g AND H are inputs.
//  * Several boundaries. Eq. 2 is applied once per boundary part, in
//    order, each time on the already modulated (N, J). Parts farther than d0
//    are the identity. This is smooth everywhere (no crease where the
//    nearest boundary changes, as min-distance would give) and exact
//    (V.n = 0) on every part whose d0 zone overlaps no other part, and on
//    mutually perpendicular planes (box interior = 6 planes, edges and
//    corners included). Where zones of non-perpendicular boundaries overlap,
//    V.n on the earlier part is small but not zero. div V = 0 everywhere.
//  * d < 0 (inside an obstacle) is clamped to r = 0 (Eq. 3: "r should never
//    be negative"): N = (n.psi) n there.
//  * V is continuous only where d is C^2. Exact distances to polyhedra and
//    rounded boxes are only C^1 (curvature jumps at face/edge region
//    borders: V would jump tangentially there), and sharp edges have
//    curvature 1/d (V ~ |psi|/d). Box obstacles therefore use a C^2 L4
//    rounded-box distance with edge radius rr > 0 (swcl_dist_box); speeds
//    near its edges grow like 1/rr (x1.7 rms at rr = scale/8 in the tests).
//
// Boundary plug-in: anything that gives swcl_dist {d, g = grad d, Hessian
// of d} at a point can be passed to swcl_modulate(). Analytic planes, box
// interiors, spheres and rounded boxes are below and in a packed primitive
// array (2 float4 each, see SWCL_PRIM_*). A mesh SDF later can supply d, g
// and a Hessian from a C^2 (e.g. tricubic B-spline) interpolant, or use the
// finite-difference mode, which needs only d and g (swcl_modulate_value +
// swcl_curl_noise_fd) but is div-free only to O(h^2).
// Plain C++ reference: tests/reference/noise_reference.hpp.

#ifndef SWCL_CURL_NOISE_CL
#define SWCL_CURL_NOISE_CL

#include "lib/perlin.cl"

/* ---------------------------------------------------------------- 3x3 */

/* J.r{i} is row i: J.r0.y = d psi_x / d y. */
typedef struct { float3 r0, r1, r2; } swcl_mat3;

SWCL_INLINE float3 swcl_mat3_curl(swcl_mat3 J)
{
    return (float3)(J.r2.y - J.r1.z, J.r0.z - J.r2.x, J.r1.x - J.r0.y);
}
SWCL_INLINE float3 swcl_mat3_tmul(swcl_mat3 J, float3 v)   /* J^T v */
{
    return v.x * J.r0 + v.y * J.r1 + v.z * J.r2;
}

/* ------------------------------------------------------------ distance */

/* Signed distance d to a boundary (> 0 in free space), its gradient g and
 * its Hessian H (symmetric): hd = (Hxx, Hyy, Hzz), ho = (Hyz, Hxz, Hxy).
 * d need not be an exact distance (|g| = 1): swcl_modulate uses the unit
 * normal n = g/|g| and its exact gradient grad n = (I - n n^T) H / |g|.
 * d must be C^2 in the d0 band for V to be continuous there. */
typedef struct { float d; float3 g; float3 hd; float3 ho; } swcl_dist;

SWCL_INLINE float3 swcl_hess_mul(swcl_dist b, float3 v)    /* H v */
{
    return (float3)(b.hd.x * v.x + b.ho.z * v.y + b.ho.y * v.z,
                    b.ho.z * v.x + b.hd.y * v.y + b.ho.x * v.z,
                    b.ho.y * v.x + b.ho.x * v.y + b.hd.z * v.z);
}

/* Half space dot(n, p) >= c (n unit, into free space): H = 0. */
SWCL_INLINE swcl_dist swcl_dist_plane(float3 p, float3 n, float c)
{
    swcl_dist b;
    b.d = dot(n, p) - c; b.g = n; b.hd = (float3)(0.0f); b.ho = (float3)(0.0f);
    return b;
}

/* Outside of a sphere obstacle (centre c, radius r): d = |p - c| - r,
 * g = n, H = (I - n n^T) / |p - c|. */
SWCL_INLINE swcl_dist swcl_dist_sphere(float3 p, float3 c, float r)
{
    swcl_dist b;
    float3 q = p - c;
    float s = length(q);
    b.d = s - r;
    b.g = (s > 0.0f) ? q / s : (float3)(0.0f, 0.0f, 1.0f);
    float k = 1.0f / fmax(s, 1e-6f);
    b.hd = ((float3)(1.0f) - b.g * b.g) * k;
    b.ho = -(float3)(b.g.y * b.g.z, b.g.x * b.g.z, b.g.x * b.g.y) * k;
    return b;
}

/* Outside of a box obstacle (centre c, half extents h), edges rounded by rr
 * (0 < rr <= min h). The exact distance to a rounded box is only C^1 (its
 * curvature jumps from 0 to 1/(d + rr) where a face region meets an edge
 * region), which makes V jump there. We use instead the C^2 (in fact C^3)
 *     d = e - rr,   e = || max(|p - c| - (h - rr), 0) ||_4        (L4 norm)
 * exact (= plane distance) in face regions, within a factor 2^(1/4) of the
 * Euclidean one near edges and corners; the surface d = 0 is the box with
 * superelliptic edges of radius rr. With w_i = max(q_i, 0) / e:
 *     de/dq_i = w_i^3,   d2e/dq_i dq_j = 3/e (w_i^2 delta_ij - w_i^3 w_j^3).
 * Inside the inner box (e = 0, d <= -rr: deep in the obstacle) the
 * nearest face is used, with H = 0. */
SWCL_INLINE swcl_dist swcl_dist_box(float3 p, float3 c, float3 h, float rr)
{
    swcl_dist b;
    float3 rel = p - c;
    float3 sg = (float3)(rel.x < 0.0f ? -1.0f : 1.0f, rel.y < 0.0f ? -1.0f : 1.0f,
                         rel.z < 0.0f ? -1.0f : 1.0f);
    float3 q = fabs(rel) - (h - rr);
    float3 qa = fmax(q, (float3)(0.0f));
    float m = fmax(qa.x, fmax(qa.y, qa.z));
    if (m > 0.0f) {
        float3 t = qa / m, t2 = t * t;
        float e = m * sqrt(sqrt(dot(t2, t2)));          /* || qa ||_4, scaled */
        float3 w = qa / e, w2 = w * w, w3 = w2 * w;
        b.d = e - rr;
        b.g = sg * w3;
        float k = 3.0f / e;
        b.hd = k * (w2 - w3 * w3);
        b.ho = -k * (float3)(w3.y * w3.z * sg.y * sg.z, w3.x * w3.z * sg.x * sg.z,
                             w3.x * w3.y * sg.x * sg.y);
    } else {
        float mq = fmax(q.x, fmax(q.y, q.z));
        b.d = mq - rr;
        b.g = (q.x == mq) ? (float3)(sg.x, 0.0f, 0.0f)
            : ((q.y == mq) ? (float3)(0.0f, sg.y, 0.0f) : (float3)(0.0f, 0.0f, sg.z));
        b.hd = (float3)(0.0f); b.ho = (float3)(0.0f);
    }
    return b;
}

/* ----------------------------------------------------- Eq. 2-3 modulation */

/* Eq. 3, r clamped to [0, 1] ("r should never be negative"). */
SWCL_INLINE float swcl_ramp(float r)
{
    r = clamp(r, 0.0f, 1.0f);
    float r2 = r * r;
    return r * (15.0f + r2 * (-10.0f + 3.0f * r2)) * 0.125f;
}
/* d ramp / dr = 15/8 (1 - r^2)^2 for 0 < r < 1, 0 outside (C^1 at r = 1). */
SWCL_INLINE float swcl_dramp(float r)
{
    if (r <= 0.0f || r >= 1.0f) return 0.0f;
    float t = 1.0f - r * r;
    return 1.875f * t * t;
}

/* Unit normal n = g / |g| (g = 0 only deep inside obstacles: any unit). */
SWCL_INLINE float3 swcl_dist_normal(swcl_dist b, float* glen)
{
    float l = length(b.g);
    *glen = l;
    return (l > 0.0f) ? b.g / l : (float3)(0.0f, 0.0f, 1.0f);
}

/* Eq. 2 on a value only (finite-difference mode; needs d and g, not H). */
SWCL_INLINE float3 swcl_modulate_value(swcl_dist b, float d0, float3 psi)
{
    float r = b.d / d0;
    if (r >= 1.0f) return psi;
    float a = swcl_ramp(r), gl;
    float3 n = swcl_dist_normal(b, &gl);
    return a * psi + (1.0f - a) * dot(n, psi) * n;
}

/* Eq. 2 on (psi, J = d psi/dx) in place, product rule included (header):
 *   dN_i/dx_j = psi_i da_j + a J_ij + (1-a)(n_i dphi_j + phi G_ij) - phi n_i da_j
 *   G = grad n = (I - n n^T) H / |g|,  dphi = G^T psi + J^T n,  da = a'(r)/d0 g */
SWCL_INLINE void swcl_modulate(swcl_dist b, float d0, float3* psi, swcl_mat3* J)
{
    float r = b.d / d0;
    if (r >= 1.0f) return;
    float a = swcl_ramp(r), gl;
    float3 n = swcl_dist_normal(b, &gl);
    float3 da = (swcl_dramp(r) / d0) * b.g;             /* grad alpha */
    float ig = gl > 0.0f ? 1.0f / gl : 0.0f;
    float3 Hn = swcl_hess_mul(b, n);
    swcl_mat3 G;                                        /* rows of grad n */
    G.r0 = ((float3)(b.hd.x, b.ho.z, b.ho.y) - n.x * Hn) * ig;
    G.r1 = ((float3)(b.ho.z, b.hd.y, b.ho.x) - n.y * Hn) * ig;
    G.r2 = ((float3)(b.ho.y, b.ho.x, b.hd.z) - n.z * Hn) * ig;
    float3 ps = *psi;
    swcl_mat3 Jp = *J;
    float phi = dot(n, ps);                             /* n . psi */
    float3 dphi = swcl_mat3_tmul(G, ps) + swcl_mat3_tmul(Jp, n);
    float ia = 1.0f - a;
    J->r0 = ps.x * da + a * Jp.r0 + ia * (n.x * dphi + phi * G.r0) - phi * n.x * da;
    J->r1 = ps.y * da + a * Jp.r1 + ia * (n.y * dphi + phi * G.r1) - phi * n.y * da;
    J->r2 = ps.z * da + a * Jp.r2 + ia * (n.z * dphi + phi * G.r2) - phi * n.z * da;
    *psi = a * ps + ia * phi * n;
}

/* ------------------------------------------------- packed boundary list */

/* A boundary primitive is 2 float4 (a, b) in a buffer; a.w is the type.
 *  SWCL_PRIM_BOX_INTERIOR  domain walls, inside [a.xyz, b.xyz] is free (6 planes)
 *  SWCL_PRIM_SPHERE        obstacle, centre a.xyz, radius b.x
 *  SWCL_PRIM_BOX           obstacle, centre a.xyz, half extents b.xyz, edge radius b.w
 *  SWCL_PRIM_PLANE         half space dot(a.xyz, p) >= b.x free, a.xyz unit  */
#define SWCL_PRIM_NONE         0
#define SWCL_PRIM_BOX_INTERIOR 1
#define SWCL_PRIM_SPHERE       2
#define SWCL_PRIM_BOX          3
#define SWCL_PRIM_PLANE        4

SWCL_INLINE int swcl_prim_type(float4 a) { return (int)a.w; }
SWCL_INLINE int swcl_prim_parts(float4 a) { return swcl_prim_type(a) == SWCL_PRIM_BOX_INTERIOR ? 6 : 1; }

SWCL_INLINE swcl_dist swcl_prim_dist(float4 a, float4 b, int part, float3 p)
{
    switch (swcl_prim_type(a)) {
    case SWCL_PRIM_BOX_INTERIOR: {
        int ax = part >> 1;                      /* 0,1: x lo/hi; 2,3: y; 4,5: z */
        float3 n = (float3)(ax == 0 ? 1.0f : 0.0f, ax == 1 ? 1.0f : 0.0f, ax == 2 ? 1.0f : 0.0f);
        float lo = ax == 0 ? a.x : (ax == 1 ? a.y : a.z);
        float hi = ax == 0 ? b.x : (ax == 1 ? b.y : b.z);
        return (part & 1) ? swcl_dist_plane(p, -n, -hi) : swcl_dist_plane(p, n, lo);
    }
    case SWCL_PRIM_SPHERE: return swcl_dist_sphere(p, a.xyz, b.x);
    case SWCL_PRIM_BOX:    return swcl_dist_box(p, a.xyz, b.xyz, b.w);
    case SWCL_PRIM_PLANE:  return swcl_dist_plane(p, a.xyz, b.x);
    default: {
        swcl_dist z; z.d = MAXFLOAT; z.g = (float3)(0.0f, 0.0f, 1.0f);
        z.hd = (float3)(0.0f); z.ho = (float3)(0.0f);
        return z;
    }
    }
}

/* ------------------------------------------------------------ curl noise */

typedef struct {
    float scale, inv_scale;  /* noise feature size (m), u = x / scale           */
    float gain;              /* speed (m/s): |V| ~ gain away from boundaries      */
    float d0;                /* boundary ramp width (m), Eq. 3; > 0               */
    float inv_time_scale;    /* time-varying mode: 4th noise coordinate = t / T   */
    uint4 off[3];            /* per-channel Philox domain offsets (perlin.cl)     */
} swcl_curl_params;

SWCL_INLINE swcl_curl_params swcl_curl_params_make(float scale, float gain, float d0,
                                              float time_scale, ulong seed)
{
    swcl_curl_params c;
    c.scale = scale; c.inv_scale = 1.0f / scale; c.gain = gain; c.d0 = d0;
    c.inv_time_scale = time_scale > 0.0f ? 1.0f / time_scale : 0.0f;
    for (uint k = 0; k < 3; ++k) c.off[k] = swcl_perlin_offset(seed, k);
    return c;
}

/* Modulated potential and its Jacobian in plain scalars (the fast path):
 * p = psi, jRC = d psi_R / d x_C. */
typedef struct {
    float p0, p1, p2;
    float j00, j01, j02, j10, j11, j12, j20, j21, j22;
} swcl_pj;

/* psi = gain * (P1, P2, P3)(x / scale) and J = d psi / dx (analytic), scalar
 * core. timed != 0: P_k are 4D noise at (x / scale, t / time_scale); pass a
 * compile-time constant so that the other branch folds away. */
SWCL_INLINE void swcl_noise_potential_s(float x, float y, float z, float t, int timed,
                                        float inv_scale, float gain, float inv_time_scale,
                                        uint4 o0, uint4 o1, uint4 o2, swcl_pj* N)
{
    const float ux = x * inv_scale, uy = y * inv_scale, uz = z * inv_scale;
    const float jg = gain * inv_scale;
    float v0, a0, a1, a2, v1, b0, b1, b2, v2, c0, c1, c2;
    if (timed) {
        const float uw = t * inv_time_scale;
        float w0, w1, w2;
        swcl_perlin4_seeded_s(ux, uy, uz, uw, o0, &v0, &a0, &a1, &a2, &w0);
        swcl_perlin4_seeded_s(ux, uy, uz, uw, o1, &v1, &b0, &b1, &b2, &w1);
        swcl_perlin4_seeded_s(ux, uy, uz, uw, o2, &v2, &c0, &c1, &c2, &w2);
    } else {
        swcl_perlin3_seeded_s(ux, uy, uz, o0, &v0, &a0, &a1, &a2);
        swcl_perlin3_seeded_s(ux, uy, uz, o1, &v1, &b0, &b1, &b2);
        swcl_perlin3_seeded_s(ux, uy, uz, o2, &v2, &c0, &c1, &c2);
    }
    N->p0 = gain * v0; N->p1 = gain * v1; N->p2 = gain * v2;
    N->j00 = jg * a0; N->j01 = jg * a1; N->j02 = jg * a2;
    N->j10 = jg * b0; N->j11 = jg * b1; N->j12 = jg * b2;
    N->j20 = jg * c0; N->j21 = jg * c1; N->j22 = jg * c2;
}

/* Eq. 2 for the half space s x_K >= s c (an axis-aligned wall: n = s e_K,
 * H = 0, so grad n = 0), branch free. Eq. 2 reduces to: the rows i != K of
 * psi and J scale by alpha, and column K of those rows gains psi_i dalpha/dx_K;
 * row K is unchanged. At r >= 1 (alpha = 1, alpha' = 0) this is exactly the
 * identity, so it needs no test of the distance. */
#define SWCL_WALL_ROW(i, K, a, dak)                                         \
    do {                                                                    \
        const float q = N->p##i;                                            \
        N->p##i = (a) * q;                                                  \
        N->j##i##0 = (a) * N->j##i##0 + ((K) == 0 ? q * (dak) : 0.0f);      \
        N->j##i##1 = (a) * N->j##i##1 + ((K) == 1 ? q * (dak) : 0.0f);      \
        N->j##i##2 = (a) * N->j##i##2 + ((K) == 2 ? q * (dak) : 0.0f);      \
    } while (0)

SWCL_INLINE void swcl_modulate_wall_s(swcl_pj* N, int K, float s, float d, float inv_d0)
{
    const float r = d * inv_d0;
    const float rc = r < 0.0f ? 0.0f : (r > 1.0f ? 1.0f : r);
    const float r2 = rc * rc;
    const float a = rc * (15.0f + r2 * (-10.0f + 3.0f * r2)) * 0.125f;   /* swcl_ramp */
    const float om = 1.0f - r2;
    const float dak = (r > 0.0f ? 1.875f * om * om : 0.0f) * inv_d0 * s; /* swcl_dramp / d0 * g_K */
    if (K != 0) SWCL_WALL_ROW(0, K, a, dak);
    if (K != 1) SWCL_WALL_ROW(1, K, a, dak);
    if (K != 2) SWCL_WALL_ROW(2, K, a, dak);
}

/* The six walls of a box interior [lo, hi] (SWCL_PRIM_BOX_INTERIOR), in the
 * order of swcl_prim_dist: x lo, x hi, y lo, y hi, z lo, z hi. */
SWCL_INLINE void swcl_modulate_box_interior_s(swcl_pj* N, float x, float y, float z,
                                              float lx, float ly, float lz,
                                              float hx, float hy, float hz, float inv_d0)
{
    swcl_modulate_wall_s(N, 0,  1.0f, x - lx, inv_d0);
    swcl_modulate_wall_s(N, 0, -1.0f, hx - x, inv_d0);
    swcl_modulate_wall_s(N, 1,  1.0f, y - ly, inv_d0);
    swcl_modulate_wall_s(N, 1, -1.0f, hy - y, inv_d0);
    swcl_modulate_wall_s(N, 2,  1.0f, z - lz, inv_d0);
    swcl_modulate_wall_s(N, 2, -1.0f, hz - z, inv_d0);
}

/* V = scale curl N: the curl is taken in noise units, V = scale * curl_x N. */
SWCL_INLINE void swcl_pj_curl(const swcl_pj* N, float scale, float* vx, float* vy, float* vz)
{
    *vx = scale * (N->j21 - N->j12);
    *vy = scale * (N->j02 - N->j20);
    *vz = scale * (N->j10 - N->j01);
}

SWCL_INLINE void swcl_pj_get(const swcl_pj* N, float3* psi, swcl_mat3* J)
{
    *psi = (float3)(N->p0, N->p1, N->p2);
    J->r0 = (float3)(N->j00, N->j01, N->j02);
    J->r1 = (float3)(N->j10, N->j11, N->j12);
    J->r2 = (float3)(N->j20, N->j21, N->j22);
}
SWCL_INLINE void swcl_pj_set(swcl_pj* N, float3 psi, swcl_mat3 J)
{
    N->p0 = psi.x; N->p1 = psi.y; N->p2 = psi.z;
    N->j00 = J.r0.x; N->j01 = J.r0.y; N->j02 = J.r0.z;
    N->j10 = J.r1.x; N->j11 = J.r1.y; N->j12 = J.r1.z;
    N->j20 = J.r2.x; N->j21 = J.r2.y; N->j22 = J.r2.z;
}

/* psi = gain * (P1, P2, P3)(x / scale) and J = d psi / dx (analytic).
 * timed != 0: P_k are 4D noise at (x / scale, t / time_scale). */
SWCL_INLINE void swcl_noise_potential(float3 x, float t, int timed, swcl_curl_params c,
                                      float3* psi, swcl_mat3* J)
{
    swcl_pj N;
    if (timed)
        swcl_noise_potential_s(x.x, x.y, x.z, t, 1, c.inv_scale, c.gain, c.inv_time_scale,
                               c.off[0], c.off[1], c.off[2], &N);
    else
        swcl_noise_potential_s(x.x, x.y, x.z, t, 0, c.inv_scale, c.gain, c.inv_time_scale,
                               c.off[0], c.off[1], c.off[2], &N);
    swcl_pj_get(&N, psi, J);
}

/* Apply Eq. 2 for every part of every primitive from `first` on, in order
 * (scalar state; box interiors take the wall fast path, the others the
 * general swcl_modulate). */
SWCL_INLINE void swcl_modulate_prims_s(swcl_pj* N, float x, float y, float z, float d0,
                                       __global const float4* prims, uint first, uint nprims)
{
    __global const float* pf = (__global const float*)prims;
    for (uint i = first; i < nprims; ++i) {
        __global const float* q = pf + 8 * i;
        if ((int)q[3] == SWCL_PRIM_BOX_INTERIOR) {
            swcl_modulate_box_interior_s(N, x, y, z, q[0], q[1], q[2], q[4], q[5], q[6], 1.0f / d0);
        } else {
            const float4 a = prims[2 * i], b = prims[2 * i + 1];
            float3 psi; swcl_mat3 J;
            swcl_pj_get(N, &psi, &J);
            swcl_modulate(swcl_prim_dist(a, b, 0, (float3)(x, y, z)), d0, &psi, &J);
            swcl_pj_set(N, psi, J);
        }
    }
}

/* Apply Eq. 2 for every part of every primitive, in order. */
SWCL_INLINE void swcl_modulate_prims(float3 x, float d0, __global const float4* prims, uint nprims,
                                     float3* psi, swcl_mat3* J)
{
    swcl_pj N;
    swcl_pj_set(&N, *psi, *J);
    swcl_modulate_prims_s(&N, x.x, x.y, x.z, d0, prims, 0u, nprims);
    swcl_pj_get(&N, psi, J);
}

/* Modulated potential N(x) (value only): what the FD mode differentiates. */
static inline float3 swcl_curl_noise_potential(float3 x, float t, int timed, swcl_curl_params c,
                                        __global const float4* prims, uint nprims)
{
    float3 psi; swcl_mat3 J;
    swcl_noise_potential(x, t, timed, c, &psi, &J);
    for (uint i = 0; i < nprims; ++i) {
        float4 a = prims[2 * i], b = prims[2 * i + 1];
        int np = swcl_prim_parts(a);
        for (int part = 0; part < np; ++part)
            psi = swcl_modulate_value(swcl_prim_dist(a, b, part, x), c.d0, psi);
    }
    return psi;
}

/* V(x) = scale * curl N(x), analytic (Eq. 1-3). timed: 4D noise at time t. */
SWCL_INLINE float3 swcl_curl_noise(float3 x, float t, int timed, swcl_curl_params c,
                              __global const float4* prims, uint nprims)
{
    float3 psi; swcl_mat3 J;
    swcl_noise_potential(x, t, timed, c, &psi, &J);
    swcl_modulate_prims(x, c.d0, prims, nprims, &psi, &J);
    return c.scale * swcl_mat3_curl(J);
}

/* V(x) by central differences of N with step h (m): for checks, and for
 * boundaries that provide only d and n. O(h^2) accurate. */
static inline float3 swcl_curl_noise_fd(float3 x, float h, float t, int timed, swcl_curl_params c,
                                 __global const float4* prims, uint nprims)
{
    float3 ex = (float3)(h, 0.0f, 0.0f), ey = (float3)(0.0f, h, 0.0f), ez = (float3)(0.0f, 0.0f, h);
    float3 dx = swcl_curl_noise_potential(x + ex, t, timed, c, prims, nprims)
              - swcl_curl_noise_potential(x - ex, t, timed, c, prims, nprims);
    float3 dy = swcl_curl_noise_potential(x + ey, t, timed, c, prims, nprims)
              - swcl_curl_noise_potential(x - ey, t, timed, c, prims, nprims);
    float3 dz = swcl_curl_noise_potential(x + ez, t, timed, c, prims, nprims)
              - swcl_curl_noise_potential(x - ez, t, timed, c, prims, nprims);
    /* curl = (dNz/dy - dNy/dz, dNx/dz - dNz/dx, dNy/dx - dNx/dy) */
    return c.scale * (float3)(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x) / (2.0f * h);
}

/* ---- explicit-width variants (CPU devices, NOISE_WIDTH = 8 or 16) ----
 * swcl_noise_potential_s, swcl_modulate_wall_s and swcl_pj_curl on SWCL_W
 * points at once (perlin.cl), same operations in the same order. */
#ifdef SWCL_W
typedef struct {
    swcl_fw p0, p1, p2;
    swcl_fw j00, j01, j02, j10, j11, j12, j20, j21, j22;
} swcl_pjw;

SWCL_INLINE void swcl_noise_potential_w(swcl_fw x, swcl_fw y, swcl_fw z, float t, int timed,
                                        float inv_scale, float gain, float inv_time_scale,
                                        uint4 o0, uint4 o1, uint4 o2, swcl_pjw* N)
{
    const swcl_fw ux = x * inv_scale, uy = y * inv_scale, uz = z * inv_scale;
    const float jg = gain * inv_scale;
    swcl_fw v0, a0, a1, a2, v1, b0, b1, b2, v2, c0, c1, c2;
    if (timed) {
        const swcl_fw uw = (swcl_fw)(t * inv_time_scale);
        swcl_fw w0, w1, w2;
        swcl_perlin4_seeded_w(ux, uy, uz, uw, o0, &v0, &a0, &a1, &a2, &w0);
        swcl_perlin4_seeded_w(ux, uy, uz, uw, o1, &v1, &b0, &b1, &b2, &w1);
        swcl_perlin4_seeded_w(ux, uy, uz, uw, o2, &v2, &c0, &c1, &c2, &w2);
    } else {
        swcl_perlin3_seeded_w(ux, uy, uz, o0, &v0, &a0, &a1, &a2);
        swcl_perlin3_seeded_w(ux, uy, uz, o1, &v1, &b0, &b1, &b2);
        swcl_perlin3_seeded_w(ux, uy, uz, o2, &v2, &c0, &c1, &c2);
    }
    N->p0 = gain * v0; N->p1 = gain * v1; N->p2 = gain * v2;
    N->j00 = jg * a0; N->j01 = jg * a1; N->j02 = jg * a2;
    N->j10 = jg * b0; N->j11 = jg * b1; N->j12 = jg * b2;
    N->j20 = jg * c0; N->j21 = jg * c1; N->j22 = jg * c2;
}

#define SWCL_WALL_ROW_W(i, K, a, dak)                                       \
    do {                                                                    \
        const swcl_fw q = N->p##i;                                          \
        N->p##i = (a) * q;                                                  \
        N->j##i##0 = (a) * N->j##i##0 + ((K) == 0 ? q * (dak) : (swcl_fw)(0.0f)); \
        N->j##i##1 = (a) * N->j##i##1 + ((K) == 1 ? q * (dak) : (swcl_fw)(0.0f)); \
        N->j##i##2 = (a) * N->j##i##2 + ((K) == 2 ? q * (dak) : (swcl_fw)(0.0f)); \
    } while (0)

SWCL_INLINE void swcl_modulate_wall_w(swcl_pjw* N, int K, float s, swcl_fw d, float inv_d0)
{
    const swcl_fw zero = (swcl_fw)(0.0f), one = (swcl_fw)(1.0f);
    const swcl_fw r = d * inv_d0;
    const swcl_fw rc = select(select(r, one, r > 1.0f), zero, r < 0.0f);
    const swcl_fw r2 = rc * rc;
    const swcl_fw a = rc * (15.0f + r2 * (-10.0f + 3.0f * r2)) * 0.125f;   /* swcl_ramp */
    const swcl_fw om = 1.0f - r2;
    const swcl_fw dak = select(zero, 1.875f * om * om, r > 0.0f) * inv_d0 * s;
    if (K != 0) SWCL_WALL_ROW_W(0, K, a, dak);
    if (K != 1) SWCL_WALL_ROW_W(1, K, a, dak);
    if (K != 2) SWCL_WALL_ROW_W(2, K, a, dak);
}

SWCL_INLINE void swcl_modulate_box_interior_w(swcl_pjw* N, swcl_fw x, swcl_fw y, swcl_fw z,
                                              float lx, float ly, float lz,
                                              float hx, float hy, float hz, float inv_d0)
{
    swcl_modulate_wall_w(N, 0,  1.0f, x - lx, inv_d0);
    swcl_modulate_wall_w(N, 0, -1.0f, hx - x, inv_d0);
    swcl_modulate_wall_w(N, 1,  1.0f, y - ly, inv_d0);
    swcl_modulate_wall_w(N, 1, -1.0f, hy - y, inv_d0);
    swcl_modulate_wall_w(N, 2,  1.0f, z - lz, inv_d0);
    swcl_modulate_wall_w(N, 2, -1.0f, hz - z, inv_d0);
}

SWCL_INLINE void swcl_pjw_curl(const swcl_pjw* N, float scale, swcl_fw* vx, swcl_fw* vy, swcl_fw* vz)
{
    *vx = scale * (N->j21 - N->j12);
    *vy = scale * (N->j02 - N->j20);
    *vz = scale * (N->j10 - N->j01);
}
#endif /* SWCL_W */

#endif /* SWCL_CURL_NOISE_CL */

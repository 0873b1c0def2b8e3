// swarmcl — tests/reference/noise_reference.hpp
//
// Plain C++17, double precision, header-only reference for kernels/philox.cl,
// kernels/perlin.cl and kernels/curl_noise.cl. Written to be obviously
// correct rather than fast: Perlin's 2002 reference function literally, the
// noise gradient as an explicit sum over lattice corners (a different
// derivation from the kernel's nested lerps), Eq. 2 of the curl-noise paper
// with full 3x3 matrices. Tests compare the float kernels against this.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace swcl_ref {

using u32 = std::uint32_t;
using u4 = std::array<u32, 4>;
using V3 = std::array<double, 3>;
using M3 = std::array<V3, 3>;  // M[i][j], row i

// ------------------------------------------------------------- Philox4x32-10
// Salmon et al. 2011; constants as in Random123 philox.h.
inline u4 philox4x32_10(u4 c, std::array<u32, 2> k) {
  for (int r = 0; r < 10; ++r) {
    if (r > 0) { k[0] += 0x9E3779B9u; k[1] += 0xBB67AE85u; }
    std::uint64_t p0 = std::uint64_t(0xD2511F53u) * c[0];
    std::uint64_t p1 = std::uint64_t(0xCD9E8D57u) * c[2];
    c = {u32(p1 >> 32) ^ c[1] ^ k[0], u32(p1), u32(p0 >> 32) ^ c[3] ^ k[1], u32(p0)};
  }
  return c;
}
inline std::array<u32, 2> seed_key(std::uint64_t seed) { return {u32(seed), u32(seed >> 32)}; }
// Counter layout of philox.cl: (agent, step, stream, sub), key = seed.
inline u4 rand_u4(std::uint64_t seed, u32 agent, u32 step, u32 stream, u32 sub) {
  return philox4x32_10({agent, step, stream, sub}, seed_key(seed));
}
constexpr u32 STREAM_WHITE_NOISE = 0, STREAM_GAUSSIAN_NOISE = 1, STREAM_PERLIN_OFFSET = 2;
inline double u01_co(u32 x) { return double(x >> 8) / 16777216.0; }         // [0,1)
inline double u01_oc(u32 x) { return double((x >> 8) + 1u) / 16777216.0; }  // (0,1]
// Box–Muller (data-driven noise paper §4.2.1): (r sin th, r cos th).
inline std::array<double, 2> box_muller(u32 a, u32 b) {
  const double pi = 3.14159265358979323846;
  double r = std::sqrt(-2.0 * std::log(u01_oc(a))), th = 2.0 * pi * u01_co(b);
  return {r * std::sin(th), r * std::cos(th)};
}

// -------------------------------------------------------------- Perlin 2002
inline const int* perm() {
  static const int p[256] = {
      151,160,137,91,90,15,131,13,201,95,96,53,194,233,7,225,140,36,103,30,69,142,
      8,99,37,240,21,10,23,190,6,148,247,120,234,75,0,26,197,62,94,252,219,203,117,
      35,11,32,57,177,33,88,237,149,56,87,174,20,125,136,171,168,68,175,74,165,71,
      134,139,48,27,166,77,146,158,231,83,111,229,122,60,211,133,230,220,105,92,41,
      55,46,245,40,244,102,143,54,65,25,63,161,1,216,80,73,209,76,132,187,208,89,
      18,169,200,196,135,130,116,188,159,86,164,100,109,198,173,186,3,64,52,217,226,
      250,124,123,5,202,38,147,118,126,255,82,85,212,207,206,59,227,47,16,58,17,182,
      189,28,42,223,183,170,213,119,248,152,2,44,154,163,70,221,153,101,155,167,43,
      172,9,129,22,39,253,19,98,108,110,79,113,224,232,178,185,112,104,218,246,97,
      228,251,34,242,193,238,210,144,12,191,179,162,241,81,51,145,235,249,14,239,
      107,49,192,214,31,181,199,106,157,184,84,204,176,115,121,50,45,127,4,150,254,
      138,236,205,93,222,114,67,29,24,72,243,141,128,195,78,66,215,61,156,180};
  return p;
}
inline int P(int i) { return perm()[i & 255]; }  // == Perlin's p[512] for i < 512
inline double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
inline double dfade(double t) { return 30 * t * t * (t - 1) * (t - 1); }
inline double lerp(double t, double a, double b) { return a + t * (b - a); }
inline double grad(int hash, double x, double y, double z) {  // Perlin 2002, verbatim
  int h = hash & 15;
  double u = h < 8 ? x : y, v = h < 4 ? y : h == 12 || h == 14 ? x : z;
  return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}
// Perlin's reference noise(x, y, z), lattice shifted by (ox, oy, oz) cells.
inline double noise3(double x, double y, double z, int ox = 0, int oy = 0, int oz = 0) {
  int X = (int(std::floor(x)) + ox) & 255, Y = (int(std::floor(y)) + oy) & 255,
      Z = (int(std::floor(z)) + oz) & 255;
  x -= std::floor(x); y -= std::floor(y); z -= std::floor(z);
  double u = fade(x), v = fade(y), w = fade(z);
  int A = P(X) + Y, AA = P(A) + Z, AB = P(A + 1) + Z, B = P(X + 1) + Y, BA = P(B) + Z, BB = P(B + 1) + Z;
  return lerp(w, lerp(v, lerp(u, grad(P(AA), x, y, z), grad(P(BA), x - 1, y, z)),
                         lerp(u, grad(P(AB), x, y - 1, z), grad(P(BB), x - 1, y - 1, z))),
                 lerp(v, lerp(u, grad(P(AA + 1), x, y, z - 1), grad(P(BA + 1), x - 1, y, z - 1)),
                         lerp(u, grad(P(AB + 1), x, y - 1, z - 1), grad(P(BB + 1), x - 1, y - 1, z - 1))));
}
// Gradient of noise3 as a sum over the 8 corners c of the cell:
//   n = sum_c W_c(f) g_c.(f - c),  W_c = prod_k (c_k ? s(f_k) : 1 - s(f_k)), s = fade
//   dn/dx_j = sum_c [dW_c/dx_j g_c.(f - c) + W_c g_c,j]
// with g_c read off grad() on the unit vectors.
inline V3 noise3_grad(double x, double y, double z, int ox = 0, int oy = 0, int oz = 0) {
  int L[3] = {int(std::floor(x)) + ox, int(std::floor(y)) + oy, int(std::floor(z)) + oz};
  double f[3] = {x - std::floor(x), y - std::floor(y), z - std::floor(z)};
  V3 out{0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    int cc[3] = {c & 1, (c >> 1) & 1, (c >> 2) & 1};
    int h = P(P(P(L[0] + cc[0]) + L[1] + cc[1]) + L[2] + cc[2]);
    double g[3] = {grad(h, 1, 0, 0), grad(h, 0, 1, 0), grad(h, 0, 0, 1)};
    double dot = 0, w = 1, wk[3], dwk[3];
    for (int k = 0; k < 3; ++k) {
      dot += g[k] * (f[k] - cc[k]);
      wk[k] = cc[k] ? fade(f[k]) : 1 - fade(f[k]);
      dwk[k] = cc[k] ? dfade(f[k]) : -dfade(f[k]);
      w *= wk[k];
    }
    for (int j = 0; j < 3; ++j) {
      double dw = dwk[j];
      for (int k = 0; k < 3; ++k) if (k != j) dw *= wk[k];
      out[j] += dw * dot + w * g[j];
    }
  }
  return out;
}
// 4D gradient set of perlin.cl: one zero axis (h >> 3), signs from bits 0..2.
inline std::array<double, 4> grad4(int h) {
  h &= 31;
  std::array<double, 4> g{};
  int zero = h >> 3, bit = 0;
  for (int k = 0; k < 4; ++k) g[k] = k == zero ? 0.0 : ((h >> bit++) & 1 ? -1.0 : 1.0);
  return g;
}
// 4D noise value and gradient by the corner sum (16 corners).
inline std::array<double, 5> noise4_vg(const double p[4], const int off[4]) {
  int L[4]; double f[4];
  for (int k = 0; k < 4; ++k) { L[k] = int(std::floor(p[k])) + off[k]; f[k] = p[k] - std::floor(p[k]); }
  std::array<double, 5> out{};  // value, d/dx, d/dy, d/dz, d/dw
  for (int c = 0; c < 16; ++c) {
    int cc[4] = {c & 1, (c >> 1) & 1, (c >> 2) & 1, (c >> 3) & 1};
    auto g = grad4(P(P(P(P(L[0] + cc[0]) + L[1] + cc[1]) + L[2] + cc[2]) + L[3] + cc[3]));
    double dot = 0, w = 1, wk[4], dwk[4];
    for (int k = 0; k < 4; ++k) {
      dot += g[k] * (f[k] - cc[k]);
      wk[k] = cc[k] ? fade(f[k]) : 1 - fade(f[k]);
      dwk[k] = cc[k] ? dfade(f[k]) : -dfade(f[k]);
      w *= wk[k];
    }
    out[0] += w * dot;
    for (int j = 0; j < 4; ++j) {
      double dw = dwk[j];
      for (int k = 0; k < 4; ++k) if (k != j) dw *= wk[k];
      out[1 + j] += dw * dot + w * g[j];
    }
  }
  return out;
}
// Seed scheme of perlin.cl: whole cells o >> 24, fraction (o & 0xffffff) 2^-24.
inline u4 perlin_offset(std::uint64_t seed, u32 channel) {
  return rand_u4(seed, channel, 0, STREAM_PERLIN_OFFSET, 0);
}
inline double offset_frac(u32 o) { return double(o & 0xffffffu) / 16777216.0; }
inline int offset_cells(u32 o) { return int(o >> 24); }

// ------------------------------------------------------------ curl noise
// Signed distance d, its gradient g and Hessian H (d need not be exact).
struct Dist { double d; V3 g; M3 H; };

inline Dist dist_plane(const V3& p, const V3& n, double c) {
  return {n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - c, n, M3{}};
}
inline Dist dist_sphere(const V3& p, const V3& c, double r) {
  V3 q{p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  double s = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  Dist b{s - r, {q[0] / s, q[1] / s, q[2] / s}, M3{}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b.H[i][j] = ((i == j) - b.g[i] * b.g[j]) / s;
  return b;
}
// Rounded box with the C^2 L4 distance of curl_noise.cl: d = ||max(|p-c| - (h-rr), 0)||_4 - rr.
// Derivatives written from e^4 = sum qa_i^4 directly: de/dx_i = s_i qa_i^3 / e^3.
inline Dist dist_box(const V3& p, const V3& c, const V3& h, double rr) {
  V3 q, qa, sg;
  double s4 = 0;
  for (int k = 0; k < 3; ++k) {
    double rel = p[k] - c[k];
    sg[k] = rel < 0 ? -1 : 1;
    q[k] = std::fabs(rel) - (h[k] - rr);
    qa[k] = q[k] > 0 ? q[k] : 0;
    s4 += qa[k] * qa[k] * qa[k] * qa[k];
  }
  Dist b{0, {0, 0, 0}, M3{}};
  if (s4 > 0) {
    double e = std::pow(s4, 0.25), e3 = e * e * e;
    b.d = e - rr;
    for (int k = 0; k < 3; ++k) b.g[k] = sg[k] * qa[k] * qa[k] * qa[k] / e3;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        b.H[i][j] = sg[i] * sg[j] * (3 * qa[i] * qa[i] * (i == j) / e3 -
                                     3 * qa[i] * qa[i] * qa[i] * qa[j] * qa[j] * qa[j] / (e3 * e3 * e));
  } else {
    int m = 0;
    for (int k = 1; k < 3; ++k) if (q[k] > q[m]) m = k;
    b.d = q[m] - rr; b.g[m] = sg[m];
  }
  return b;
}

// Eq. 3 and its derivative.
inline double ramp(double r) {
  if (r <= 0) return 0;
  if (r >= 1) return 1;
  return 15 * r / 8 - 10 * r * r * r / 8 + 3 * r * r * r * r * r / 8;
}
inline double dramp(double r) { return (r <= 0 || r >= 1) ? 0 : 15.0 / 8 - 30 * r * r / 8 + 15 * r * r * r * r / 8; }

// Eq. 2 on a value, n = g / |g|.
inline V3 unit(const V3& g) {
  double l = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  return {g[0] / l, g[1] / l, g[2] / l};
}
inline V3 modulate_value(const Dist& b, double d0, const V3& psi) {
  if (b.d / d0 >= 1) return psi;
  double a = ramp(b.d / d0), phi = 0;
  V3 n = unit(b.g), N;
  for (int k = 0; k < 3; ++k) phi += n[k] * psi[k];
  for (int i = 0; i < 3; ++i) N[i] = a * psi[i] + (1 - a) * phi * n[i];
  return N;
}
// Eq. 2 on (psi, J): d/dx_j of a psi_i + (1 - a) phi n_i, phi = n.psi, n = g/|g|,
// dn_i/dx_j = (H_ij - n_i (H n)_j) / |g|.
inline void modulate(const Dist& b, double d0, V3& psi, M3& J) {
  double r = b.d / d0;
  if (r >= 1) return;
  double a = ramp(r), gl = std::sqrt(b.g[0] * b.g[0] + b.g[1] * b.g[1] + b.g[2] * b.g[2]);
  V3 n = unit(b.g), da, dphi{0, 0, 0}, Hn{0, 0, 0};
  M3 G;
  double phi = 0;
  for (int k = 0; k < 3; ++k) { da[k] = dramp(r) / d0 * b.g[k]; phi += n[k] * psi[k]; }
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) Hn[i] += b.H[i][k] * n[k];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) G[i][j] = (b.H[i][j] - n[i] * Hn[j]) / gl;
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) dphi[j] += psi[k] * G[k][j] + n[k] * J[k][j];
  M3 JN;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      JN[i][j] = da[j] * psi[i] + a * J[i][j]                             // d(a psi_i)
                 - da[j] * phi * n[i] + (1 - a) * dphi[j] * n[i]          // d((1-a) phi) n_i
                 + (1 - a) * phi * G[i][j];                               // (1-a) phi dn_i
  psi = modulate_value(b, d0, psi);
  J = JN;
}

// Packed primitives as in curl_noise.cl (2 float4 each, a.w = type).
struct Prim { std::array<float, 4> a, b; };
enum { PRIM_NONE = 0, PRIM_BOX_INTERIOR = 1, PRIM_SPHERE = 2, PRIM_BOX = 3, PRIM_PLANE = 4 };
inline std::vector<Dist> prim_dists(const Prim& pr, const V3& p) {
  int type = int(pr.a[3]);
  V3 a{pr.a[0], pr.a[1], pr.a[2]}, b{pr.b[0], pr.b[1], pr.b[2]};
  std::vector<Dist> out;
  if (type == PRIM_BOX_INTERIOR)
    for (int ax = 0; ax < 3; ++ax) {
      V3 n{0, 0, 0}; n[ax] = 1;
      out.push_back(dist_plane(p, n, a[ax]));
      out.push_back(dist_plane(p, {-n[0], -n[1], -n[2]}, -b[ax]));
    }
  else if (type == PRIM_SPHERE) out.push_back(dist_sphere(p, a, b[0]));
  else if (type == PRIM_BOX) out.push_back(dist_box(p, a, b, pr.b[3]));
  else if (type == PRIM_PLANE) out.push_back(dist_plane(p, a, b[0]));
  return out;
}

struct CurlParams {
  double scale = 1, gain = 1, d0 = 1, time_scale = 0;  // time_scale 0: static
  std::uint64_t seed = 0;
};

// psi = gain P(x/scale) (3 seeded channels), J = d psi/dx.
inline void potential(const CurlParams& c, const V3& x, double t, bool timed, V3& psi, M3& J) {
  for (u32 k = 0; k < 3; ++k) {
    u4 o = perlin_offset(c.seed, k);
    // the kernel adds the fraction in float; do the same rounding here so that
    // both evaluate the noise at the same point
    double u[4];
    for (int a = 0; a < 3; ++a) u[a] = x[a] / c.scale + offset_frac(o[a]);
    if (timed) {
      u[3] = t / c.time_scale + offset_frac(o[3]);
      int off[4] = {offset_cells(o[0]), offset_cells(o[1]), offset_cells(o[2]), offset_cells(o[3])};
      auto vg = noise4_vg(u, off);
      psi[k] = c.gain * vg[0];
      for (int j = 0; j < 3; ++j) J[k][j] = c.gain / c.scale * vg[1 + j];
    } else {
      int ox = offset_cells(o[0]), oy = offset_cells(o[1]), oz = offset_cells(o[2]);
      psi[k] = c.gain * noise3(u[0], u[1], u[2], ox, oy, oz);
      V3 g = noise3_grad(u[0], u[1], u[2], ox, oy, oz);
      for (int j = 0; j < 3; ++j) J[k][j] = c.gain / c.scale * g[j];
    }
  }
}
inline V3 curl(const M3& J) { return {J[2][1] - J[1][2], J[0][2] - J[2][0], J[1][0] - J[0][1]}; }

// Modulated potential N(x) (value only) and analytic V = scale curl N.
inline V3 potential_modulated(const CurlParams& c, const std::vector<Prim>& prims, const V3& x,
                              double t = 0, bool timed = false) {
  V3 psi; M3 J;
  potential(c, x, t, timed, psi, J);
  for (const Prim& p : prims)
    for (const Dist& b : prim_dists(p, x)) psi = modulate_value(b, c.d0, psi);
  return psi;
}
inline V3 curl_noise(const CurlParams& c, const std::vector<Prim>& prims, const V3& x,
                     double t = 0, bool timed = false) {
  V3 psi; M3 J;
  potential(c, x, t, timed, psi, J);
  for (const Prim& p : prims)
    for (const Dist& b : prim_dists(p, x)) modulate(b, c.d0, psi, J);
  V3 v = curl(J);
  for (double& e : v) e *= c.scale;
  return v;
}
// Central-difference curl of potential_modulated (step h).
inline V3 curl_noise_fd(const CurlParams& c, const std::vector<Prim>& prims, const V3& x, double h,
                        double t = 0, bool timed = false) {
  M3 J;  // J[i][j] = dN_i/dx_j
  for (int j = 0; j < 3; ++j) {
    V3 xp = x, xm = x; xp[j] += h; xm[j] -= h;
    V3 np = potential_modulated(c, prims, xp, t, timed), nm = potential_modulated(c, prims, xm, t, timed);
    for (int i = 0; i < 3; ++i) J[i][j] = (np[i] - nm[i]) / (2 * h);
  }
  V3 v = curl(J);
  for (double& e : v) e *= c.scale;
  return v;
}

}  // namespace swcl_ref

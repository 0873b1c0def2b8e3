// swarmcl — tests/noise_kernels_standalone.cpp
//
// Standalone check of kernels/philox.cl, perlin.cl, curl_noise.cl against
// tests/reference/noise_reference.hpp on the first OpenCL device (PoCL).
// Build (from the repository root):
//   g++ -std=c++17 -O2 -Itests tests/noise_kernels_standalone.cpp -lOpenCL -o /tmp/noise_check
//   /tmp/noise_check [repo_root]
// Each check prints its measured figure and PASS/FAIL; exit status = #failures.
// Each block maps to one future GoogleTest case.
#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "reference/noise_reference.hpp"

namespace {

namespace R = swcl_ref;
int g_failures = 0;

void check(bool ok, const char* what, double measured, double limit) {
  std::printf("%-4s %-62s %.3e (limit %.1e)\n", ok ? "PASS" : "FAIL", what, measured, limit);
  if (!ok) ++g_failures;
}

// Reads `file` from one of `dirs`, expanding #include "x.cl" once each.
std::string load_cl(const std::string& file, const std::vector<std::string>& dirs, std::set<std::string>& seen) {
  if (!seen.insert(file).second) return "";
  for (const auto& d : dirs) {
    std::ifstream in(d + "/" + file);
    if (!in) continue;
    std::stringstream out;
    std::string line;
    while (std::getline(in, line)) {
      auto a = line.find("#include \"");
      if (a != std::string::npos && line.find_first_not_of(" \t") == a) {
        auto b = line.find('"', a + 10);
        out << load_cl(line.substr(a + 10, b - a - 10), dirs, seen) << "\n";
      } else {
        out << line << "\n";
      }
    }
    return out.str();
  }
  throw std::runtime_error("kernel source not found: " + file);
}

struct Cl {
  cl::Context ctx;
  cl::Device dev;
  cl::CommandQueue q;
  cl::Program prog;
};

template <class T>
cl::Buffer to_dev(Cl& cl, const std::vector<T>& v) {
  return cl::Buffer(cl.ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T),
                    const_cast<T*>(v.data()));
}
template <class T>
std::vector<T> from_dev(Cl& cl, const cl::Buffer& b, size_t n) {
  std::vector<T> v(n);
  cl.q.enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(T), v.data());
  return v;
}


// ------------------------------------------------------------------ Philox
void test_philox(Cl& cl) {
  std::vector<cl_uint4> ctr = {{{0, 0, 0, 0}}, {{0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu}},
                               {{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}}};
  std::vector<cl_uint2> key = {{{0, 0}}, {{0xffffffffu, 0xffffffffu}}, {{0xa4093822u, 0x299f31d0u}}};
  const R::u32 kat[3][4] = {{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u},
                            {0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu},
                            {0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}};
  std::mt19937 rng(7);  // 32-bit engine
  auto u32 = [&] { return cl_uint(rng()); };
  for (int i = 0; i < 4096; ++i) {
    ctr.push_back({{u32(), u32(), u32(), u32()}});
    key.push_back({{u32(), u32()}});
  }
  cl::Buffer bo(cl.ctx, CL_MEM_WRITE_ONLY, ctr.size() * sizeof(cl_uint4));
  cl::Kernel k(cl.prog, "t_philox");
  cl::Buffer bc = to_dev(cl, ctr), bk = to_dev(cl, key);  // alive until the read (setArg does not retain)
  k.setArg(0, bc); k.setArg(1, bk); k.setArg(2, bo);
  cl.q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(ctr.size()));
  auto out = from_dev<cl_uint4>(cl, bo, ctr.size());
  int kat_bad_dev = 0, kat_bad_ref = 0, mism = 0;
  for (int i = 0; i < 3; ++i) {
    auto r = R::philox4x32_10({ctr[i].s[0], ctr[i].s[1], ctr[i].s[2], ctr[i].s[3]}, {key[i].s[0], key[i].s[1]});
    for (int j = 0; j < 4; ++j) { kat_bad_dev += out[i].s[j] != kat[i][j]; kat_bad_ref += r[j] != kat[i][j]; }
    std::printf("     KAT %d device %08x %08x %08x %08x\n", i, out[i].s[0], out[i].s[1], out[i].s[2], out[i].s[3]);
  }
  for (size_t i = 0; i < ctr.size(); ++i) {
    auto r = R::philox4x32_10({ctr[i].s[0], ctr[i].s[1], ctr[i].s[2], ctr[i].s[3]}, {key[i].s[0], key[i].s[1]});
    for (int j = 0; j < 4; ++j) mism += out[i].s[j] != r[j];
  }
  check(kat_bad_dev == 0, "philox KAT (Random123) on device: wrong words", kat_bad_dev, 0);
  check(kat_bad_ref == 0, "philox KAT (Random123) in reference: wrong words", kat_bad_ref, 0);
  check(mism == 0, "philox device == reference, 4099 random ctr/key: wrong words", mism, 0);
}

// ----------------------------------------------------- uniform / gaussian
void test_random(Cl& cl) {
  const size_t n = 1 << 20;
  const cl_ulong seed = 0x0123456789abcdefULL;
  cl::Buffer braw(cl.ctx, CL_MEM_WRITE_ONLY, n * sizeof(cl_uint4));
  cl::Buffer buni(cl.ctx, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
  cl::Buffer bg(cl.ctx, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
  cl::Kernel k(cl.prog, "t_random");
  k.setArg(0, seed); k.setArg(1, cl_uint(17)); k.setArg(2, cl_uint(R::STREAM_GAUSSIAN_NOISE));
  k.setArg(3, braw); k.setArg(4, buni); k.setArg(5, bg);
  cl.q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
  auto raw = from_dev<cl_uint4>(cl, braw, n);
  auto uni = from_dev<cl_float4>(cl, buni, n);
  auto g = from_dev<cl_float4>(cl, bg, n);
  int raw_bad = 0;
  double umin = 1, umax = 0, usum = 0, usq = 0, uerr = 0, gerr = 0;
  double gs[5] = {0, 0, 0, 0, 0}, corr = 0;
  std::vector<double> u0;
  for (size_t i = 0; i < n; ++i) {
    auto r = R::rand_u4(seed, R::u32(i), 17, R::STREAM_GAUSSIAN_NOISE, 0);
    auto g0 = R::box_muller(r[0], r[1]), g1 = R::box_muller(r[2], r[3]);
    double gr[4] = {g0[0], g0[1], g1[0], g1[1]};
    for (int j = 0; j < 4; ++j) {
      raw_bad += raw[i].s[j] != r[j];
      double u = uni[i].s[j];
      uerr = std::max(uerr, std::fabs(u - R::u01_co(r[j])));
      umin = std::min(umin, u); umax = std::max(umax, u); usum += u; usq += u * u;
      double x = g[i].s[j];
      gerr = std::max(gerr, std::fabs(x - gr[j]) / (1 + std::fabs(gr[j])));
      double p = 1;
      for (int m = 1; m <= 4; ++m) { p *= x; gs[m] += p; }
    }
    if (i + 1 < n) corr += (uni[i].s[0] - 0.5) * (uni[i + 1].s[0] - 0.5);
    if (i < 100000) u0.push_back(uni[i].s[0]);
  }
  const double m = 4.0 * n;
  double umean = usum / m, uvar = usq / m - umean * umean;
  double gmean = gs[1] / m, gvar = gs[2] / m - gmean * gmean, gskew = gs[3] / m, gkurt = gs[4] / m;
  corr /= (n - 1) / 12.0;
  std::sort(u0.begin(), u0.end());
  double ks = 0;
  for (size_t i = 0; i < u0.size(); ++i)
    ks = std::max({ks, std::fabs(u0[i] - double(i) / u0.size()), std::fabs(u0[i] - double(i + 1) / u0.size())});
  check(raw_bad == 0, "rand_u4(seed, agent, step, stream) == reference: wrong words", raw_bad, 0);
  check(uerr == 0, "uniform [0,1) device == reference (exact)", uerr, 0);
  check(umin >= 0 && umax < 1, "uniform range [0,1): 1 - max", 1 - umax, 0);
  const double se_mean = std::sqrt(1.0 / 12 / m);
  check(std::fabs(umean - 0.5) < 5 * se_mean, "uniform mean - 1/2 (4M draws)", umean - 0.5, 5 * se_mean);
  check(std::fabs(uvar - 1.0 / 12) < 5e-4, "uniform variance - 1/12", uvar - 1.0 / 12, 5e-4);
  check(std::fabs(corr) < 5.0 / std::sqrt(double(n)), "uniform lag-1 correlation across agent ids", corr,
        5.0 / std::sqrt(double(n)));
  check(ks < 1.63 / std::sqrt(double(u0.size())), "uniform KS statistic (1e5 draws, 1% critical)", ks,
        1.63 / std::sqrt(double(u0.size())));
  check(gerr < 2e-6, "gaussian device vs double reference, |d|/(1+|g|)", gerr, 2e-6);
  check(std::fabs(gmean) < 5 / std::sqrt(m), "gaussian mean", gmean, 5 / std::sqrt(m));
  check(std::fabs(gvar - 1) < 5 * std::sqrt(2 / m), "gaussian variance - 1", gvar - 1, 5 * std::sqrt(2 / m));
  check(std::fabs(gskew) < 5 * std::sqrt(15 / m), "gaussian E[x^3]", gskew, 5 * std::sqrt(15 / m));
  check(std::fabs(gkurt - 3) < 5 * std::sqrt(96 / m), "gaussian E[x^4] - 3", gkurt - 3, 5 * std::sqrt(96 / m));
}

// ------------------------------------------------------------------ Perlin
void test_perlin(Cl& cl) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> U(-100.f, 100.f);
  std::vector<cl_float4> p = {{{3.14f, 42.f, 7.f, 0.f}}};
  const size_t nlat = 1000;
  for (size_t i = 0; i < nlat; ++i)  // integer lattice points
    p.push_back({{float(int(U(rng))), float(int(U(rng))), float(int(U(rng))), 0.f}});
  const size_t first_rand = p.size();
  for (int i = 0; i < 20000; ++i) p.push_back({{U(rng), U(rng), U(rng), U(rng) * 0.1f}});
  const size_t n = p.size();
  cl::Buffer bp = to_dev(cl, p);
  cl::Buffer bo(cl.ctx, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
  cl::Buffer bv(cl.ctx, CL_MEM_WRITE_ONLY, n * sizeof(float));
  const R::u4 off = R::perlin_offset(99, 1);
  cl_uint4 o = {{off[0], off[1], off[2], off[3]}};

  for (int seeded = 0; seeded < 2; ++seeded) {
    cl::Kernel k(cl.prog, "t_perlin3");
    k.setArg(0, bp); k.setArg(1, o); k.setArg(2, seeded); k.setArg(3, bo);
    cl.q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
    auto out = from_dev<cl_float4>(cl, bo, n);
    if (!seeded) {
      double v = out[0].s[3];
      std::printf("     noise(3.14, 42, 7): device %.9f, reference %.17g\n", v, R::noise3(3.14, 42, 7));
      check(std::fabs(R::noise3(3.14, 42, 7) - 0.13691995878400012) < 1e-15, "reference noise(3.14,42,7) - 0.136919958784",
            std::fabs(R::noise3(3.14, 42, 7) - 0.13691995878400012), 1e-15);
      check(std::fabs(v - 0.13691995878400012) < 1e-6, "device noise(3.14f,42,7) - 0.136919958784",
            std::fabs(v - 0.13691995878400012), 1e-6);
      double lat = 0;
      for (size_t i = 1; i < first_rand; ++i) lat = std::max(lat, std::fabs(double(out[i].s[3])));
      check(lat == 0, "device |noise| at 1000 integer lattice points", lat, 0);
    }
    double verr = 0, gerr = 0, gfd = 0, vmax = 0;
    for (size_t i = first_rand; i < n; ++i) {
      double x = p[i].s[0], y = p[i].s[1], z = p[i].s[2];
      int ox = 0, oy = 0, oz = 0;
      if (seeded) {  // same float rounding as the kernel: p + frac in float
        x = double(p[i].s[0] + float(R::offset_frac(off[0])));
        y = double(p[i].s[1] + float(R::offset_frac(off[1])));
        z = double(p[i].s[2] + float(R::offset_frac(off[2])));
        ox = R::offset_cells(off[0]); oy = R::offset_cells(off[1]); oz = R::offset_cells(off[2]);
      }
      double rv = R::noise3(x, y, z, ox, oy, oz);
      R::V3 rg = R::noise3_grad(x, y, z, ox, oy, oz);
      vmax = std::max(vmax, std::fabs(rv));
      verr = std::max(verr, std::fabs(out[i].s[3] - rv));
      for (int j = 0; j < 3; ++j) gerr = std::max(gerr, std::fabs(out[i].s[j] - rg[j]));
      if (i < first_rand + 2000) {  // reference gradient vs double central differences
        const double h = 1e-6;
        double xs[3] = {x, y, z};
        for (int j = 0; j < 3; ++j) {
          double a[3] = {xs[0], xs[1], xs[2]}, b[3] = {xs[0], xs[1], xs[2]};
          a[j] += h; b[j] -= h;
          double fd = (R::noise3(a[0], a[1], a[2], ox, oy, oz) - R::noise3(b[0], b[1], b[2], ox, oy, oz)) / (2 * h);
          gfd = std::max(gfd, std::fabs(fd - rg[j]));
        }
      }
    }
    std::string tag = seeded ? "seeded " : "";
    check(verr < 1e-6, (tag + "perlin3 value: max |device - double ref| (20k pts)").c_str(), verr, 1e-6);
    check(gerr < 5e-6, (tag + "perlin3 gradient: max |device - ref| per component").c_str(), gerr, 5e-6);
    check(gfd < 1e-7, (tag + "perlin3 ref gradient vs double central diff").c_str(), gfd, 1e-7);
    std::printf("     %smax |noise| seen: %.4f\n", tag.c_str(), vmax);
  }

  // 4D
  for (int seeded = 0; seeded < 2; ++seeded) {
    cl::Kernel k(cl.prog, "t_perlin4");
    k.setArg(0, bp); k.setArg(1, o); k.setArg(2, seeded); k.setArg(3, bv); k.setArg(4, bo);
    cl.q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n));
    auto val = from_dev<float>(cl, bv, n);
    auto gr = from_dev<cl_float4>(cl, bo, n);
    double verr = 0, gerr = 0, gfd = 0, lat = 0;
    for (size_t i = 1; i < n; ++i) {
      double q[4];
      int oo[4] = {0, 0, 0, 0};
      for (int j = 0; j < 4; ++j) {
        q[j] = seeded ? double(p[i].s[j] + float(R::offset_frac(off[j]))) : p[i].s[j];
        if (seeded) oo[j] = R::offset_cells(off[j]);
      }
      auto r = R::noise4_vg(q, oo);
      if (i < first_rand) { if (!seeded) lat = std::max(lat, std::fabs(double(val[i]))); continue; }
      verr = std::max(verr, std::fabs(val[i] - r[0]));
      for (int j = 0; j < 4; ++j) gerr = std::max(gerr, std::fabs(gr[i].s[j] - r[1 + j]));
      if (i < first_rand + 2000)
        for (int j = 0; j < 4; ++j) {
          double a[4] = {q[0], q[1], q[2], q[3]}, b[4] = {q[0], q[1], q[2], q[3]};
          a[j] += 1e-6; b[j] -= 1e-6;
          gfd = std::max(gfd, std::fabs((R::noise4_vg(a, oo)[0] - R::noise4_vg(b, oo)[0]) / 2e-6 - r[1 + j]));
        }
    }
    std::string tag = seeded ? "seeded " : "";
    if (!seeded) check(lat == 0, "device |noise4| at integer lattice points (w=0)", lat, 0);
    check(verr < 1e-6, (tag + "perlin4 value: max |device - double ref|").c_str(), verr, 1e-6);
    check(gerr < 5e-6, (tag + "perlin4 gradient: max |device - ref|").c_str(), gerr, 5e-6);
    check(gfd < 1e-7, (tag + "perlin4 ref gradient vs double central diff").c_str(), gfd, 1e-7);
  }
}

// -------------------------------------------------------------- curl noise
struct Scene {
  std::vector<R::Prim> prims;
  R::CurlParams c;
};

std::vector<cl_float4> run_curl(Cl& cl, const Scene& s, const std::vector<cl_float4>& x, bool timed, int mode,
                                float h) {
  std::vector<cl_float4> pr;
  for (const auto& p : s.prims) {
    pr.push_back({{p.a[0], p.a[1], p.a[2], p.a[3]}});
    pr.push_back({{p.b[0], p.b[1], p.b[2], p.b[3]}});
  }
  if (pr.empty()) pr.push_back({{0, 0, 0, 0}});
  cl::Buffer bo(cl.ctx, CL_MEM_WRITE_ONLY, x.size() * sizeof(cl_float4));
  cl::Buffer bx = to_dev(cl, x), bpr = to_dev(cl, pr);  // alive until the read
  cl::Kernel k(cl.prog, "t_curl");
  int a = 0;
  k.setArg(a++, bx); k.setArg(a++, float(s.c.scale)); k.setArg(a++, float(s.c.gain));
  k.setArg(a++, float(s.c.d0)); k.setArg(a++, float(s.c.time_scale)); k.setArg(a++, cl_ulong(s.c.seed));
  k.setArg(a++, int(timed)); k.setArg(a++, bpr); k.setArg(a++, cl_uint(s.prims.size()));
  k.setArg(a++, mode); k.setArg(a++, h); k.setArg(a++, bo);
  cl.q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(x.size()));
  return from_dev<cl_float4>(cl, bo, x.size());
}

// Signed distance of the scene (min over parts) for sampling.
double scene_dist(const Scene& s, const R::V3& x) {
  double d = 1e30;
  for (const auto& p : s.prims)
    for (const auto& b : R::prim_dists(p, x)) d = std::min(d, b.d);
  return d;
}

void test_curl_scene(Cl& cl, const char* name, const Scene& s, bool timed, const R::V3& lo, const R::V3& hi) {
  std::printf("---- curl noise, scene '%s'%s (scale %.2f gain %.2f d0 %.2f)\n", name, timed ? ", time-varying" : "",
              s.c.scale, s.c.gain, s.c.d0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  // sample points in free space, oversampling the boundary layer d < d0
  std::vector<cl_float4> x;
  while (x.size() < 4000) {
    R::V3 p{lo[0] + U(rng) * (hi[0] - lo[0]), lo[1] + U(rng) * (hi[1] - lo[1]), lo[2] + U(rng) * (hi[2] - lo[2])};
    double d = scene_dist(s, p);
    if (d < 2e-3 * s.c.scale) continue;                 // keep FD stencils out of the walls
    if (d > s.c.d0 && U(rng) < 0.5) continue;
    x.push_back({{float(p[0]), float(p[1]), float(p[2]), float(U(rng) * 3)}});
  }
  const size_t n = x.size();
  auto va = run_curl(cl, s, x, timed, 0, 0);
  const float hfd = float(1e-2 * s.c.scale);
  auto vf = run_curl(cl, s, x, timed, 1, hfd);

  double rms = 0, err_ref = 0, err_fd = 0, err_ref_fd = 0;
  for (size_t i = 0; i < n; ++i) rms += va[i].s[0] * va[i].s[0] + va[i].s[1] * va[i].s[1] + va[i].s[2] * va[i].s[2];
  rms = std::sqrt(rms / n);
  for (size_t i = 0; i < n; ++i) {
    R::V3 p{x[i].s[0], x[i].s[1], x[i].s[2]};
    R::V3 r = R::curl_noise(s.c, s.prims, p, x[i].s[3], timed);
    const bool stencil_free = scene_dist(s, p) > 1.5 * hfd;  // FD stencil stays in free space
    for (int j = 0; j < 3; ++j) {
      err_ref = std::max(err_ref, std::fabs(va[i].s[j] - r[j]));
      if (stencil_free) err_fd = std::max(err_fd, std::fabs(double(va[i].s[j]) - vf[i].s[j]));
    }
    if (i < 1000) {
      R::V3 rf = R::curl_noise_fd(s.c, s.prims, p, 1e-6 * s.c.scale, x[i].s[3], timed);
      for (int j = 0; j < 3; ++j) err_ref_fd = std::max(err_ref_fd, std::fabs(r[j] - rf[j]));
    }
  }
  std::printf("     rms |V| = %.4f over %zu points\n", rms, n);
  check(err_ref < 1e-4 * rms, "V analytic: max |device - double ref| / rms|V|", err_ref / rms, 1e-4);
  check(err_ref_fd < 1e-6 * rms, "ref: analytic (product rule) vs double FD of Eq.2 potential", err_ref_fd / rms, 1e-6);
  check(err_fd < 1e-2 * rms, "device analytic vs device FD mode (h = 0.01 scale, float)", err_fd / rms, 1e-2);

  // Divergence: central differences of the device's analytic V, 7-point stencil.
  const double hd = 2e-3 * s.c.scale;
  std::vector<cl_float4> st;
  for (size_t i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j)
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        cl_float4 q = x[i];
        q.s[j] = float(q.s[j] + sgn * hd);
        st.push_back(q);
      }
  auto vs = run_curl(cl, s, st, timed, 0, 0);
  double worst = 0, worst_ref = 0, mean_ratio = 0;
  for (size_t i = 0; i < n; ++i) {
    double div = 0, g2 = 0;
    for (int j = 0; j < 3; ++j) {
      const cl_float4& qp = st[6 * i + 2 * j + 1];
      const cl_float4& qm = st[6 * i + 2 * j];
      double step = double(qp.s[j]) - double(qm.s[j]);  // actual float step
      const cl_float4& a = vs[6 * i + 2 * j + 1];
      const cl_float4& b = vs[6 * i + 2 * j];
      for (int c = 0; c < 3; ++c) {
        double dv = (double(a.s[c]) - double(b.s[c])) / step;
        g2 += dv * dv;
        if (c == j) div += dv;
      }
    }
    double ratio = std::fabs(div) / std::sqrt(g2);
    worst = std::max(worst, ratio);
    mean_ratio += ratio / n;
    if (i < 500) {  // the same on the double reference
      double rd = 0, rg2 = 0;
      for (int j = 0; j < 3; ++j) {
        R::V3 p{x[i].s[0], x[i].s[1], x[i].s[2]}, m = p;
        p[j] += 1e-5; m[j] -= 1e-5;
        R::V3 a = R::curl_noise(s.c, s.prims, p, x[i].s[3], timed), b = R::curl_noise(s.c, s.prims, m, x[i].s[3], timed);
        for (int c = 0; c < 3; ++c) {
          double dv = (a[c] - b[c]) / 2e-5;
          rg2 += dv * dv;
          if (c == j) rd += dv;
        }
      }
      worst_ref = std::max(worst_ref, std::fabs(rd) / std::sqrt(rg2));
    }
  }
  std::printf("     device |div V|/|grad V|: mean %.2e\n", mean_ratio);
  check(worst < 1e-3, "device max |div V| / |grad V|_F (FD h = 2e-3 scale)", worst, 1e-3);
  check(worst_ref < 1e-6, "double ref max |div V| / |grad V|_F (FD h = 1e-5)", worst_ref, 1e-6);
}

// Normal velocity at and near the boundaries: V.n / rms|V| at d = 0 and d = eps.
void test_normal(Cl& cl, const char* name, const Scene& s, bool timed,
                 const std::vector<std::pair<R::V3, R::V3>>& surf /* point on surface, unit normal */) {
  const double ds[] = {0.0, 1e-3, 1e-2, 0.1, 0.5};
  double rms = 0;
  std::vector<cl_float4> x;
  for (double d : ds)
    for (const auto& pn : surf)
      x.push_back({{float(pn.first[0] + d * s.c.d0 * pn.second[0]), float(pn.first[1] + d * s.c.d0 * pn.second[1]),
                    float(pn.first[2] + d * s.c.d0 * pn.second[2]), 0.7f}});
  auto v = run_curl(cl, s, x, timed, 0, 0);
  for (size_t i = 0; i < surf.size(); ++i)
    rms += v[i].s[0] * v[i].s[0] + v[i].s[1] * v[i].s[1] + v[i].s[2] * v[i].s[2];
  rms = std::sqrt(rms / surf.size());
  std::printf("     '%s': rms |V| on the boundary %.4f; max |V.n|/rms by d/d0:", name, rms);
  double at0 = 0;
  for (size_t k = 0; k < std::size(ds); ++k) {
    double m = 0;
    for (size_t i = 0; i < surf.size(); ++i) {
      const auto& vv = v[k * surf.size() + i];
      const R::V3& n = surf[i].second;
      m = std::max(m, std::fabs(vv.s[0] * n[0] + vv.s[1] * n[1] + vv.s[2] * n[2]) / rms);
    }
    if (k == 0) at0 = m;
    std::printf(" %g:%.1e", ds[k], m);
  }
  std::printf("\n");
  check(at0 < 1e-4, (std::string("|V.n|/rms|V| on boundary '") + name + "'").c_str(), at0, 1e-4);
}

void test_curl(Cl& cl) {
  Scene free_space;
  free_space.c = {0.8, 0.5, 0.3, 2.0, 42};
  test_curl_scene(cl, "free space", free_space, false, {-5, -5, -5}, {5, 5, 5});
  test_curl_scene(cl, "free space", free_space, true, {-5, -5, -5}, {5, 5, 5});

  Scene sc;  // box interior [0,6]^3 + sphere + rounded box; d0 zones do not overlap
  sc.c = {0.8, 0.5, 0.5, 2.0, 7};
  sc.prims.push_back({{0, 0, 0, float(R::PRIM_BOX_INTERIOR)}, {6, 6, 6, 0}});
  sc.prims.push_back({{2, 2, 2, float(R::PRIM_SPHERE)}, {0.6f, 0, 0, 0}});
  sc.prims.push_back({{4.2f, 4.2f, 3.5f, float(R::PRIM_BOX)}, {0.5f, 0.4f, 0.6f, 0.1f}});
  test_curl_scene(cl, "walls+sphere+box", sc, false, {0, 0, 0}, {6, 6, 6});
  test_curl_scene(cl, "walls+sphere+box", sc, true, {0, 0, 0}, {6, 6, 6});

  std::printf("---- normal velocity at the boundaries (scene 'walls+sphere+box')\n");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<std::pair<R::V3, R::V3>> walls, sphere, box;
  for (int i = 0; i < 600; ++i) {
    int ax = i % 3, side = (i / 3) % 2;
    R::V3 p{U(rng) * 6, U(rng) * 6, U(rng) * 6}, n{0, 0, 0};
    if (i % 10 == 0) { p[(ax + 1) % 3] = U(rng) * 0.5; }  // near edges and corners
    if (i % 20 == 0) { p[(ax + 2) % 3] = 6 - U(rng) * 0.5; }
    p[ax] = side ? 6 : 0; n[ax] = side ? -1 : 1;
    walls.push_back({p, n});
  }
  for (int i = 0; i < 600; ++i) {
    double z = 2 * U(rng) - 1, ph = 6.283185307179586 * U(rng), r = std::sqrt(1 - z * z);
    R::V3 n{r * std::cos(ph), r * std::sin(ph), z};
    sphere.push_back({{2 + 0.6 * n[0], 2 + 0.6 * n[1], 2 + 0.6 * n[2]}, n});
  }
  const R::V3 bc{4.2, 4.2, 3.5}, bh{0.5, 0.4, 0.6};
  const double rr = 0.1;
  for (int i = 0; i < 600; ++i) {  // points of the surface d = 0 of the L4-rounded box
    int nact = 1 + i % 3;            // faces, edges, corners
    R::V3 q, w{0, 0, 0}, sg;
    double w4 = 0;
    for (int k = 0; k < 3; ++k) {
      sg[k] = U(rng) < 0.5 ? -1 : 1;
      if ((k + i) % 3 < nact) { w[k] = 0.05 + U(rng); w4 += std::pow(w[k], 4); }
    }
    R::V3 p, n;
    double gl = 0;
    for (int k = 0; k < 3; ++k) {
      w[k] /= std::pow(w4, 0.25);   // ||w||_4 = 1
      q[k] = w[k] > 0 ? (bh[k] - rr) + rr * w[k] : (2 * U(rng) - 1) * (bh[k] - rr);
      p[k] = bc[k] + sg[k] * q[k];
      n[k] = sg[k] * w[k] * w[k] * w[k]; gl += n[k] * n[k];
    }
    for (int k = 0; k < 3; ++k) n[k] /= std::sqrt(gl);
    box.push_back({p, n});
  }
  for (int timed = 0; timed < 2; ++timed) {
    std::printf("     %s\n", timed ? "time-varying" : "static");
    test_normal(cl, "box interior walls (incl. edges/corners)", sc, timed, walls);
    test_normal(cl, "sphere obstacle", sc, timed, sphere);
    test_normal(cl, "rounded box obstacle", sc, timed, box);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string root = argc > 1 ? argv[1] : ".";
  try {
    Cl cl;
    std::vector<cl::Platform> plats;
    cl::Platform::get(&plats);
    std::vector<cl::Device> devs;
    plats.at(0).getDevices(CL_DEVICE_TYPE_ALL, &devs);
    cl.dev = devs.at(0);
    cl.ctx = cl::Context(cl.dev);
    cl.q = cl::CommandQueue(cl.ctx, cl.dev);
    std::printf("device: %s (%s)\n", cl.dev.getInfo<CL_DEVICE_NAME>().c_str(),
                plats[0].getInfo<CL_PLATFORM_NAME>().c_str());
    std::set<std::string> seen;
    std::string src = load_cl("noise_test_kernels.cl", {root + "/tests", root + "/kernels"}, seen);
    cl.prog = cl::Program(cl.ctx, src);
    try {
      cl.prog.build({cl.dev}, "-cl-std=CL1.2");
    } catch (const cl::Error&) {
      std::fprintf(stderr, "build log:\n%s\n", cl.prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(cl.dev).c_str());
      return 100;
    }
    const std::string log = cl.prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(cl.dev);
    if (log.find("warning") != std::string::npos) std::printf("build log:\n%s\n", log.c_str());
    std::printf("---- philox\n");
    test_philox(cl);
    std::printf("---- uniform / gaussian\n");
    test_random(cl);
    std::printf("---- perlin\n");
    test_perlin(cl);
    test_curl(cl);
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "OpenCL error %d in %s\n", e.err(), e.what());
    return 101;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 102;
  }
  std::printf("%d failure(s)\n", g_failures);
  return g_failures;
}

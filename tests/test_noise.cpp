// Noise: Philox, white/Gaussian, improved Perlin, boundary-aware curl noise
// and baked fields — the device code (kernels/philox.cl, perlin.cl,
// curl_noise.cl through the thin kernels of tests/noise_test_kernels.cl) and
// the C API (swcl_noise_sample) against the double reference
// tests/reference/noise_reference.hpp, plus the properties a user checks:
// statistics, independence, determinism, divergence-free, no flow through
// boundaries, convergence of a baked field, and refused bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/philox.hpp"
#include "device/kernel_sources.hpp"
#include "reference/noise_reference.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

namespace {

namespace R = swcl_ref;
using swarmcl::test::shared_context;

// ------------------------------------------------------------ test harness

swarmcl::Context& ctx() { return *shared_context(); }

// The largest difference between the baked samples vb at pts (xyz packed)
// and the trilinear interpolation, in double, of the procedural values pv at
// every node of the res^3 grid from lo with edge cell (x fastest).
double trilinear_error(const std::vector<float>& pts, const std::vector<float>& vb, const std::vector<float>& pv,
                       float lo, float cell, uint32_t res) {
    double err = 0;
    for (size_t q = 0; q < pts.size() / 3; ++q) {
        int i0[3];
        double w[3];
        for (int a = 0; a < 3; ++a) {
            const double u = std::min(std::max((pts[3 * q + a] - lo) / double(cell), 0.0), double(res - 1));
            i0[a] = std::min(int(std::floor(u)), int(res) - 2);
            w[a] = u - i0[a];
        }
        for (int c = 0; c < 3; ++c) {
            double v = 0;
            for (int corner = 0; corner < 8; ++corner) {
                size_t idx = 0, stride = 1;
                double wt = 1;
                for (int a = 0; a < 3; ++a) {
                    const int bit = (corner >> a) & 1;
                    idx += (i0[a] + bit) * stride;
                    stride *= res;
                    wt *= bit ? w[a] : 1 - w[a];
                }
                v += wt * pv[3 * idx + c];
            }
            err = std::max(err, std::fabs(vb[3 * q + c] - v));
        }
    }
    return err;
}

// tests/noise_test_kernels.cl with its #include "lib/curl_noise.cl" expanded from
// the library's kernel sources, built once per test process.
cl::Program& test_program() {
    static cl::Program prog = [] {
        std::ifstream in(std::string(SWARMCL_SOURCE_DIR) + "/tests/noise_test_kernels.cl");
        if (!in) throw std::runtime_error("tests/noise_test_kernels.cl not found");
        std::stringstream ss;
        ss << in.rdbuf();
        std::string src = ss.str();
        const std::string inc = "#include \"lib/curl_noise.cl\"";
        const size_t at = src.find(inc);
        if (at == std::string::npos) throw std::runtime_error("noise_test_kernels.cl: include line not found");
        src.replace(at, inc.size(), swarmcl::load_kernel_source("lib/curl_noise.cl"));
        cl::Program p(ctx().cl_context(), src);
        try {
            p.build({ctx().device().device}, "-cl-std=CL1.2");
        } catch (const cl::Error&) {
            throw std::runtime_error("noise_test_kernels.cl build failed:\n" +
                                     p.getBuildInfo<CL_PROGRAM_BUILD_LOG>(ctx().device().device));
        }
        return p;
    }();
    return prog;
}

template <class T>
cl::Buffer to_dev(const std::vector<T>& v) {
    return cl::Buffer(ctx().cl_context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T),
                      const_cast<T*>(v.data()));
}
cl::Buffer out_buf(size_t bytes) { return cl::Buffer(ctx().cl_context(), CL_MEM_WRITE_ONLY, bytes); }
template <class T>
std::vector<T> from_dev(const cl::Buffer& b, size_t n) {
    std::vector<T> v(n);
    ctx().queue().enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(T), v.data());
    return v;
}
void run(cl::Kernel& k, size_t n) { ctx().queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n)); }

// One C API context per test process.
swcl_context capi() {
    static swcl_context c{};
    static swcl_status s = [] {
        swcl_context_desc d = swcl_context_desc_default();
        return swcl_context_create(&d, &c);
    }();
    if (s != SWCL_OK) throw std::runtime_error(std::string("swcl_context_create: ") + swcl_last_error());
    return c;
}

std::vector<float> sample(const swcl_noise_desc& d, const std::vector<float>& pts, float t = 0.0f,
                          uint32_t step = 0) {
    std::vector<float> out(pts.size(), std::nanf(""));
    const swcl_status s = swcl_noise_sample(capi(), &d, pts.data(), pts.size() / 3, t, step, out.data());
    EXPECT_EQ(s, SWCL_OK) << swcl_last_error();
    return out;
}

double rms3(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += double(x) * x;
    return std::sqrt(s / (v.size() / 3));
}

// Pearson correlation of a[i] and b[i].
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    const size_t n = a.size();
    double ma = 0, mb = 0;
    for (size_t i = 0; i < n; ++i) { ma += a[i]; mb += b[i]; }
    ma /= n; mb /= n;
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < n; ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

// ================================================================== Philox

// Random123's known-answer vectors for philox4x32-10 (kat_vectors).
const R::u32 kKatCtr[3][4] = {{0, 0, 0, 0},
                              {0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                              {0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}};
const R::u32 kKatKey[3][2] = {{0, 0}, {0xffffffffu, 0xffffffffu}, {0xa4093822u, 0x299f31d0u}};
const R::u32 kKatOut[3][4] = {{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u},
                              {0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu},
                              {0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}};

std::vector<cl_uint4> philox_on_device(const std::vector<cl_uint4>& ctr, const std::vector<cl_uint2>& key) {
    cl::Buffer bc = to_dev(ctr), bk = to_dev(key);  // alive until the read
    cl::Buffer bo = out_buf(ctr.size() * sizeof(cl_uint4));
    cl::Kernel k(test_program(), "t_philox");
    k.setArg(0, bc); k.setArg(1, bk); k.setArg(2, bo);
    run(k, ctr.size());
    return from_dev<cl_uint4>(bo, ctr.size());
}

TEST(Philox, KnownAnswerVectorsOnDeviceReferenceAndHost) {
    std::vector<cl_uint4> ctr;
    std::vector<cl_uint2> key;
    for (int i = 0; i < 3; ++i) {
        ctr.push_back({{kKatCtr[i][0], kKatCtr[i][1], kKatCtr[i][2], kKatCtr[i][3]}});
        key.push_back({{kKatKey[i][0], kKatKey[i][1]}});
    }
    const auto dev = philox_on_device(ctr, key);
    for (int i = 0; i < 3; ++i) {
        const R::u4 c{kKatCtr[i][0], kKatCtr[i][1], kKatCtr[i][2], kKatCtr[i][3]};
        const auto ref = R::philox4x32_10(c, {kKatKey[i][0], kKatKey[i][1]});
        const auto host = swarmcl::philox4x32_10(c, {kKatKey[i][0], kKatKey[i][1]});
        for (int j = 0; j < 4; ++j) {
            EXPECT_EQ(dev[i].s[j], kKatOut[i][j]) << "device, vector " << i << " word " << j;
            EXPECT_EQ(ref[j], kKatOut[i][j]) << "reference, vector " << i << " word " << j;
            EXPECT_EQ(host[j], kKatOut[i][j]) << "host, vector " << i << " word " << j;
        }
    }
}

TEST(Philox, DeviceReferenceAndHostAgreeBitwise) {
    std::mt19937 rng(7);
    std::vector<cl_uint4> ctr;
    std::vector<cl_uint2> key;
    for (int i = 0; i < 4096; ++i) {
        ctr.push_back({{cl_uint(rng()), cl_uint(rng()), cl_uint(rng()), cl_uint(rng())}});
        key.push_back({{cl_uint(rng()), cl_uint(rng())}});
    }
    const auto dev = philox_on_device(ctr, key);
    int bad_ref = 0, bad_host = 0;
    for (size_t i = 0; i < ctr.size(); ++i) {
        const R::u4 c{ctr[i].s[0], ctr[i].s[1], ctr[i].s[2], ctr[i].s[3]};
        const auto ref = R::philox4x32_10(c, {key[i].s[0], key[i].s[1]});
        const auto host = swarmcl::philox4x32_10(c, {key[i].s[0], key[i].s[1]});
        for (int j = 0; j < 4; ++j) {
            bad_ref += dev[i].s[j] != ref[j];
            bad_host += dev[i].s[j] != host[j];
        }
    }
    EXPECT_EQ(bad_ref, 0) << "words where device != reference";
    EXPECT_EQ(bad_host, 0) << "words where device != host swarmcl::philox4x32_10";
    // The host helper keyed like the device: counter (agent, step, stream, 0), key = seed.
    const uint64_t seed = 0x0123456789abcdefULL;
    const auto a = swarmcl::philox_for(seed, 5, 9, 1);
    const auto b = R::rand_u4(seed, 5, 9, 1, 0);
    for (int j = 0; j < 4; ++j) EXPECT_EQ(a[j], b[j]);
}

// Device uniforms and Gaussians (philox.cl) against the reference formulas.
TEST(Philox, DeviceUniformAndGaussianMatchReference) {
    const size_t n = 1 << 18;
    const cl_ulong seed = 0x0123456789abcdefULL;
    const cl_uint step = 17;
    cl::Buffer braw = out_buf(n * sizeof(cl_uint4)), buni = out_buf(n * sizeof(cl_float4)),
               bg = out_buf(n * sizeof(cl_float4));
    cl::Kernel k(test_program(), "t_random");
    k.setArg(0, seed); k.setArg(1, step); k.setArg(2, cl_uint(R::STREAM_GAUSSIAN_NOISE));
    k.setArg(3, braw); k.setArg(4, buni); k.setArg(5, bg);
    run(k, n);
    const auto raw = from_dev<cl_uint4>(braw, n);
    const auto uni = from_dev<cl_float4>(buni, n);
    const auto g = from_dev<cl_float4>(bg, n);
    int raw_bad = 0;
    double uerr = 0, gerr = 0, umin = 1, umax = 0;
    double gs[5] = {0, 0, 0, 0, 0}, usum = 0, usq = 0, ucorr = 0;
    std::vector<double> u0;
    for (size_t i = 0; i < n; ++i) {
        const auto r = R::rand_u4(seed, R::u32(i), step, R::STREAM_GAUSSIAN_NOISE, 0);
        const auto g0 = R::box_muller(r[0], r[1]), g1 = R::box_muller(r[2], r[3]);
        const double gr[4] = {g0[0], g0[1], g1[0], g1[1]};
        for (int j = 0; j < 4; ++j) {
            raw_bad += raw[i].s[j] != r[j];
            uerr = std::max(uerr, std::fabs(uni[i].s[j] - R::u01_co(r[j])));
            umin = std::min(umin, double(uni[i].s[j]));
            umax = std::max(umax, double(uni[i].s[j]));
            gerr = std::max(gerr, std::fabs(g[i].s[j] - gr[j]) / (1 + std::fabs(gr[j])));
            double p = 1;
            for (int k = 1; k <= 4; ++k) gs[k] += (p *= g[i].s[j]);
            usum += uni[i].s[j];
            usq += double(uni[i].s[j]) * uni[i].s[j];
        }
        if (i + 1 < n) ucorr += (uni[i].s[0] - 0.5) * (uni[i + 1].s[0] - 0.5);
        if (i < 100000) u0.push_back(uni[i].s[0]);
    }
    EXPECT_EQ(raw_bad, 0) << "swcl_rand_u4 words != reference";
    EXPECT_EQ(uerr, 0.0) << "uniforms are k 2^-24 exactly";
    EXPECT_GE(umin, 0.0);
    EXPECT_LT(umax, 1.0);
    EXPECT_LT(gerr, 2e-6) << "Box-Muller in float vs double";
    // Kolmogorov-Smirnov on 1e5 uniforms (1% critical value) and the first
    // four moments of 4n Gaussians (5 standard errors).
    std::sort(u0.begin(), u0.end());
    double ks = 0;
    for (size_t i = 0; i < u0.size(); ++i)
        ks = std::max({ks, std::fabs(u0[i] - double(i) / u0.size()), std::fabs(u0[i] - double(i + 1) / u0.size())});
    EXPECT_LT(ks, 1.63 / std::sqrt(double(u0.size()))) << "KS statistic of the uniforms";
    const double m = 4.0 * n;
    const double umean = usum / m, uvar = usq / m - umean * umean;
    EXPECT_LT(std::fabs(umean - 0.5), 5 * std::sqrt(1.0 / 12 / m)) << "uniform mean";
    EXPECT_LT(std::fabs(uvar - 1.0 / 12), 5 * std::sqrt(1.0 / 180 / m)) << "uniform variance";
    EXPECT_LT(std::fabs(ucorr / ((n - 1) / 12.0)), 5 / std::sqrt(double(n))) << "lag-1 correlation across agent ids";
    EXPECT_LT(std::fabs(gs[1] / m), 5 / std::sqrt(m)) << "Gaussian mean";
    EXPECT_LT(std::fabs(gs[2] / m - 1), 5 * std::sqrt(2 / m)) << "Gaussian E[x^2] - 1";
    EXPECT_LT(std::fabs(gs[3] / m), 5 * std::sqrt(15 / m)) << "Gaussian E[x^3]";
    EXPECT_LT(std::fabs(gs[4] / m - 3), 5 * std::sqrt(96 / m)) << "Gaussian E[x^4] - 3";
}

// ========================================================= white / Gaussian

struct Moments {
    double mean[3] = {0, 0, 0}, var[3] = {0, 0, 0};
};
Moments moments(const std::vector<float>& v) {
    Moments m;
    const size_t n = v.size() / 3;
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) m.mean[a] += v[3 * i + a];
    for (int a = 0; a < 3; ++a) m.mean[a] /= n;
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) m.var[a] += (v[3 * i + a] - m.mean[a]) * (v[3 * i + a] - m.mean[a]);
    for (int a = 0; a < 3; ++a) m.var[a] /= n - 1;
    return m;
}

// Statistics of one random noise type: mean 0, variance var_unit g^2 (with
// var4_unit = Var(x^2)/g^4 for the standard error of the variance), no
// correlation between neighbouring points, between components, or between a
// point's draws at consecutive steps.
void check_random_noise(swcl_noise_type type, double var_unit, double var4_unit) {
    const size_t n = 100000;
    const float g = 0.7f;
    swcl_noise_desc d = swcl_noise_desc_default();
    d.type = type;
    d.gain = g;
    d.seed = 1234;
    const auto pts = swarmcl::test::random_points(n, -3, 3, 1);
    const auto s5 = sample(d, pts, 0.0f, 5), s6 = sample(d, pts, 0.0f, 6);
    const Moments m = moments(s5);
    const double var = var_unit * g * g;
    const double se_mean = std::sqrt(var / n), se_var = std::sqrt(var4_unit / n) * g * g;
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(std::fabs(m.mean[a]), 5 * se_mean) << "axis " << a;
        EXPECT_LT(std::fabs(m.var[a] - var), 5 * se_var) << "axis " << a << ": variance " << m.var[a] << " vs " << var;
    }
    const double lim = 5.0 / std::sqrt(double(n));
    for (int a = 0; a < 3; ++a) {
        std::vector<double> x0, x1, y, st5, st6;
        for (size_t i = 0; i + 1 < n; ++i) {
            x0.push_back(s5[3 * i + a]);
            x1.push_back(s5[3 * (i + 1) + a]);
            y.push_back(s5[3 * i + (a + 1) % 3]);
            st5.push_back(s5[3 * i + a]);
            st6.push_back(s6[3 * i + a]);
        }
        EXPECT_LT(std::fabs(correlation(x0, x1)), lim) << "neighbouring points, axis " << a;
        EXPECT_LT(std::fabs(correlation(x0, y)), lim) << "components " << a << " and " << (a + 1) % 3;
        EXPECT_LT(std::fabs(correlation(st5, st6)), lim) << "same point at steps 5 and 6, axis " << a;
    }
    // The same (seed, step) gives bitwise the same output; another seed or
    // step gives other values (positions do not matter).
    const auto again = sample(d, swarmcl::test::random_points(n, -3, 3, 2), 3.0f, 5);
    EXPECT_EQ(std::memcmp(again.data(), s5.data(), s5.size() * sizeof(float)), 0);
    swcl_noise_desc d2 = d;
    d2.seed = 1235;
    const auto other = sample(d2, pts, 0.0f, 5);
    size_t same_seed = 0, same_step = 0;
    for (size_t i = 0; i < s5.size(); ++i) {
        same_seed += other[i] == s5[i];
        same_step += s6[i] == s5[i];
    }
    EXPECT_LT(same_seed, s5.size() / 1000) << "values equal under another seed";
    EXPECT_LT(same_step, s5.size() / 1000) << "values equal at another step";
}

TEST(WhiteNoise, ZeroMeanVarianceGainSquaredOverThreeIndependent) {
    // U(-g, g): Var = g^2/3, Var(x^2) = g^4/5 - g^4/9.
    check_random_noise(SWCL_NOISE_WHITE, 1.0 / 3, 1.0 / 5 - 1.0 / 9);
}

TEST(GaussianNoise, ZeroMeanVarianceGainSquaredIndependent) {
    // N(0, g^2): Var(x^2) = 2 g^4.
    check_random_noise(SWCL_NOISE_GAUSSIAN, 1.0, 2.0);
}

TEST(WhiteNoise, MatchesPhiloxFormulaPerAgentAndStep) {
    // V = gain (2u - 1), u from (seed, agent = point index, step, stream 0);
    // Gaussian = gain * Box-Muller of the words of stream 1.
    const size_t n = 5000;
    const float g = 0.3f;
    // Both halves of the seed set: the noise block carries it as two 32-bit
    // slots (lib/noise_field.cl), and a dropped half would change every draw.
    const uint64_t seed = (uint64_t(5) << 32) | 99u;
    const uint32_t step = 41;
    swcl_noise_desc d = swcl_noise_desc_default();
    d.type = SWCL_NOISE_WHITE;
    d.gain = g;
    d.seed = seed;
    const auto pts = swarmcl::test::random_points(n, 0, 1, 3);
    const auto w = sample(d, pts, 0.0f, step);
    d.type = SWCL_NOISE_GAUSSIAN;
    const auto gs = sample(d, pts, 0.0f, step);
    double werr = 0, gerr = 0;
    for (size_t i = 0; i < n; ++i) {
        const auto r = swarmcl::philox_for(seed, uint32_t(i), step, R::STREAM_WHITE_NOISE);
        const auto q = R::rand_u4(seed, uint32_t(i), step, R::STREAM_GAUSSIAN_NOISE, 0);
        const auto b0 = R::box_muller(q[0], q[1]), b1 = R::box_muller(q[2], q[3]);
        const double gr[3] = {b0[0], b0[1], b1[0]};
        for (int a = 0; a < 3; ++a) {
            werr = std::max(werr, double(std::fabs(w[3 * i + a] - g * (2.0f * swarmcl::uniform01(r[a]) - 1.0f))));
            gerr = std::max(gerr, std::fabs(gs[3 * i + a] - g * gr[a]) / (g * (1 + std::fabs(gr[a]))));
        }
    }
    EXPECT_LE(werr, 1e-7 * g);
    EXPECT_LT(gerr, 2e-6);
}

// ================================================================== Perlin

// Points for Perlin checks: p[0] = (3.14, 42, 7); then integer lattice
// points; then random points (x, y, z, t).
struct PerlinPoints {
    std::vector<cl_float4> p;
    size_t first_rand = 0;
};
PerlinPoints perlin_points() {
    PerlinPoints pp;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(-100.f, 100.f);
    pp.p.push_back({{3.14f, 42.f, 7.f, 0.f}});
    for (int i = 0; i < 1000; ++i)
        pp.p.push_back({{float(int(U(rng))), float(int(U(rng))), float(int(U(rng))), 0.f}});
    pp.first_rand = pp.p.size();
    for (int i = 0; i < 20000; ++i) pp.p.push_back({{U(rng), U(rng), U(rng), U(rng) * 0.1f}});
    return pp;
}

std::vector<cl_float4> perlin3_on_device(const std::vector<cl_float4>& p, const R::u4& off, bool seeded) {
    cl::Buffer bp = to_dev(p), bo = out_buf(p.size() * sizeof(cl_float4));
    cl::Kernel k(test_program(), "t_perlin3");
    k.setArg(0, bp); k.setArg(1, cl_uint4{{off[0], off[1], off[2], off[3]}}); k.setArg(2, cl_int(seeded));
    k.setArg(3, bo);
    run(k, p.size());
    return from_dev<cl_float4>(bo, p.size());
}

TEST(Perlin, KnownValueAndZeroOnLattice) {
    EXPECT_NEAR(R::noise3(3.14, 42, 7), 0.13691995878400012, 1e-15);
    const auto pp = perlin_points();
    const auto out = perlin3_on_device(pp.p, {0, 0, 0, 0}, false);
    EXPECT_NEAR(out[0].s[3], 0.13691995878400012, 1e-6) << "noise(3.14, 42, 7) on the device";
    double lat = 0;
    for (size_t i = 1; i < pp.first_rand; ++i) lat = std::max(lat, std::fabs(double(out[i].s[3])));
    EXPECT_EQ(lat, 0.0) << "|noise| at integer lattice points (3D)";

    // 4D (time-varying) noise is zero on the 4D lattice too.
    cl::Buffer bp = to_dev(pp.p), bv = out_buf(pp.p.size() * sizeof(float)),
               bg = out_buf(pp.p.size() * sizeof(cl_float4));
    cl::Kernel k(test_program(), "t_perlin4");
    k.setArg(0, bp); k.setArg(1, cl_uint4{{0, 0, 0, 0}}); k.setArg(2, cl_int(0)); k.setArg(3, bv); k.setArg(4, bg);
    run(k, pp.p.size());
    const auto val = from_dev<float>(bv, pp.p.size());
    double lat4 = 0;
    for (size_t i = 1; i < pp.first_rand; ++i) lat4 = std::max(lat4, std::fabs(double(val[i])));
    EXPECT_EQ(lat4, 0.0) << "|noise4| at integer lattice points (w = 0)";
}

class PerlinSeeded : public ::testing::TestWithParam<bool> {};

TEST_P(PerlinSeeded, ValueAndGradientMatchReference3D) {
    const bool seeded = GetParam();
    const auto pp = perlin_points();
    const R::u4 off = R::perlin_offset(99, 1);
    const auto out = perlin3_on_device(pp.p, off, seeded);
    double verr = 0, gerr = 0, gfd = 0;
    for (size_t i = pp.first_rand; i < pp.p.size(); ++i) {
        double x[3];
        int o[3] = {0, 0, 0};
        for (int j = 0; j < 3; ++j) {
            // the kernel adds the offset fraction in float
            x[j] = seeded ? double(pp.p[i].s[j] + float(R::offset_frac(off[j]))) : pp.p[i].s[j];
            if (seeded) o[j] = R::offset_cells(off[j]);
        }
        const double rv = R::noise3(x[0], x[1], x[2], o[0], o[1], o[2]);
        const R::V3 rg = R::noise3_grad(x[0], x[1], x[2], o[0], o[1], o[2]);
        verr = std::max(verr, std::fabs(out[i].s[3] - rv));
        for (int j = 0; j < 3; ++j) gerr = std::max(gerr, std::fabs(out[i].s[j] - rg[j]));
        if (i < pp.first_rand + 2000)  // the reference gradient is the derivative of the reference value
            for (int j = 0; j < 3; ++j) {
                double a[3] = {x[0], x[1], x[2]}, b[3] = {x[0], x[1], x[2]};
                a[j] += 1e-6; b[j] -= 1e-6;
                const double fd = (R::noise3(a[0], a[1], a[2], o[0], o[1], o[2]) -
                                   R::noise3(b[0], b[1], b[2], o[0], o[1], o[2])) / 2e-6;
                gfd = std::max(gfd, std::fabs(fd - rg[j]));
            }
    }
    EXPECT_LT(verr, 1e-6) << "value: max |device - double reference|";
    EXPECT_LT(gerr, 5e-6) << "gradient: max |device - reference| per component";
    EXPECT_LT(gfd, 1e-7) << "reference gradient vs double central differences";
}

TEST_P(PerlinSeeded, ValueAndGradientMatchReference4D) {
    const bool seeded = GetParam();
    const auto pp = perlin_points();
    const R::u4 off = R::perlin_offset(99, 1);
    const size_t n = pp.p.size();
    cl::Buffer bp = to_dev(pp.p), bv = out_buf(n * sizeof(float)), bg = out_buf(n * sizeof(cl_float4));
    cl::Kernel k(test_program(), "t_perlin4");
    k.setArg(0, bp); k.setArg(1, cl_uint4{{off[0], off[1], off[2], off[3]}}); k.setArg(2, cl_int(seeded));
    k.setArg(3, bv); k.setArg(4, bg);
    run(k, n);
    const auto val = from_dev<float>(bv, n);
    const auto gr = from_dev<cl_float4>(bg, n);
    double verr = 0, gerr = 0, gfd = 0;
    for (size_t i = pp.first_rand; i < n; ++i) {
        double q[4];
        int oo[4] = {0, 0, 0, 0};
        for (int j = 0; j < 4; ++j) {
            q[j] = seeded ? double(pp.p[i].s[j] + float(R::offset_frac(off[j]))) : pp.p[i].s[j];
            if (seeded) oo[j] = R::offset_cells(off[j]);
        }
        const auto r = R::noise4_vg(q, oo);
        verr = std::max(verr, std::fabs(val[i] - r[0]));
        for (int j = 0; j < 4; ++j) gerr = std::max(gerr, std::fabs(gr[i].s[j] - r[1 + j]));
        if (i < pp.first_rand + 2000)
            for (int j = 0; j < 4; ++j) {
                double a[4] = {q[0], q[1], q[2], q[3]}, b[4] = {q[0], q[1], q[2], q[3]};
                a[j] += 1e-6; b[j] -= 1e-6;
                gfd = std::max(gfd, std::fabs((R::noise4_vg(a, oo)[0] - R::noise4_vg(b, oo)[0]) / 2e-6 - r[1 + j]));
            }
    }
    EXPECT_LT(verr, 1e-6);
    EXPECT_LT(gerr, 5e-6);
    EXPECT_LT(gfd, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Perlin, PerlinSeeded, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) { return i.param ? "Seeded" : "Unseeded"; });

TEST(Perlin, VectorNoiseMatchesReferenceAndSeededChannelsAreIndependent) {
    // swcl_noise_sample PERLIN: V = gain (P1, P2, P3)(x / scale), one seeded
    // channel per component.
    swcl_noise_desc d = swcl_noise_desc_default();
    d.type = SWCL_NOISE_PERLIN;
    d.scale = 0.5f;
    d.gain = 2.0f;
    d.seed = 31;
    const size_t n = 20000;
    const auto pts = swarmcl::test::random_points(n, -40, 40, 5);  // ~160 cells per axis
    const auto v = sample(d, pts);
    R::CurlParams c;
    c.scale = d.scale; c.gain = d.gain; c.seed = d.seed;
    double err = 0;
    std::vector<double> ch[3];
    for (size_t i = 0; i < n; ++i) {
        R::V3 psi;
        R::M3 J;
        R::potential(c, {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]}, 0, false, psi, J);
        for (int a = 0; a < 3; ++a) {
            err = std::max(err, std::fabs(v[3 * i + a] - psi[a]));
            ch[a].push_back(v[3 * i + a]);
        }
    }
    EXPECT_LT(err, 1e-4 * d.gain) << "PERLIN vs gain * reference noise with the seeded offsets";
    // The three channels are different functions: uncorrelated over many cells.
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(std::fabs(correlation(ch[a], ch[(a + 1) % 3])), 0.05) << "channels " << a << ", " << (a + 1) % 3;
        size_t equal = 0;
        for (size_t i = 0; i < n; ++i) equal += ch[a][i] == ch[(a + 1) % 3][i];
        EXPECT_LT(equal, n / 100);
    }
    // Another seed gives another field.
    d.seed = 32;
    const auto w = sample(d, pts);
    std::vector<double> x0, x1;
    for (size_t i = 0; i < n; ++i) { x0.push_back(v[3 * i]); x1.push_back(w[3 * i]); }
    EXPECT_LT(std::fabs(correlation(x0, x1)), 0.05) << "seed 31 vs seed 32";
}

// ============================================================== curl noise

// A scene: noise parameters and boundaries for the C API, the same for the
// reference, and the box to sample points in.
struct Scene {
    std::string name;
    swcl_noise_desc desc = swcl_noise_desc_default();
    std::vector<swcl_obstacle> bounds;
    std::vector<R::Prim> prims;
    R::CurlParams c;
    R::V3 lo{-3, -3, -3}, hi{3, 3, 3};

    swcl_noise_desc get(bool timed) const {
        swcl_noise_desc d = desc;
        d.boundaries = bounds.empty() ? nullptr : bounds.data();
        d.boundary_count = uint32_t(bounds.size());
        d.time_scale = timed ? float(c.time_scale) : 0.0f;
        return d;
    }
    double dist(const R::V3& x) const {
        double d = 1e30;
        for (const auto& p : prims)
            for (const auto& b : R::prim_dists(p, x)) d = std::min(d, b.d);
        return d;
    }
};

Scene base_scene(const std::string& name) {
    Scene s;
    s.name = name;
    s.c.scale = 0.8; s.c.gain = 0.5; s.c.d0 = 0.5; s.c.time_scale = 2.0; s.c.seed = 7;
    s.desc.type = SWCL_NOISE_CURL;
    s.desc.scale = float(s.c.scale);
    s.desc.gain = float(s.c.gain);
    s.desc.boundary_distance = float(s.c.d0);
    s.desc.seed = s.c.seed;
    return s;
}
void add_walls(Scene& s, float lo, float hi) {
    s.desc.domain_walls = 1;
    for (int a = 0; a < 3; ++a) { s.desc.region_min[a] = lo; s.desc.region_max[a] = hi; }
    s.prims.push_back({{lo, lo, lo, float(R::PRIM_BOX_INTERIOR)}, {hi, hi, hi, 0}});
    s.lo = {lo, lo, lo};
    s.hi = {hi, hi, hi};
}
void add_sphere(Scene& s, R::V3 c, float r) {
    swcl_obstacle b{};
    b.type = SWCL_OBSTACLE_SPHERE;
    for (int a = 0; a < 3; ++a) b.center[a] = float(c[a]);
    b.radius = r;
    s.bounds.push_back(b);
    s.prims.push_back({{float(c[0]), float(c[1]), float(c[2]), float(R::PRIM_SPHERE)}, {r, 0, 0, 0}});
}
void add_box(Scene& s, R::V3 c, R::V3 h, float rr) {
    swcl_obstacle b{};
    b.type = SWCL_OBSTACLE_BOX;
    for (int a = 0; a < 3; ++a) { b.center[a] = float(c[a]); b.half_extents[a] = float(h[a]); }
    b.radius = rr;
    s.bounds.push_back(b);
    s.prims.push_back({{float(c[0]), float(c[1]), float(c[2]), float(R::PRIM_BOX)},
                       {float(h[0]), float(h[1]), float(h[2]), rr}});
}

Scene scene(const std::string& name) {
    Scene s = base_scene(name);
    if (name == "walls") add_walls(s, 0, 4);
    if (name == "sphere") add_sphere(s, {0.1, -0.2, 0.3}, 0.8f);
    if (name == "box") add_box(s, {0.1, -0.2, 0.3}, {0.6, 0.5, 0.7}, 0.1f);
    if (name == "all") {  // d0 bands do not overlap
        add_walls(s, 0, 6);
        add_sphere(s, {2, 2, 2}, 0.6f);
        add_box(s, {4.2, 4.2, 3.5}, {0.5, 0.4, 0.6}, 0.1f);
    }
    return s;
}

// Points in the scene's box and free space, oversampling the d0 band.
std::vector<float> scene_points(const Scene& s, size_t n, double min_dist, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<float> x;
    while (x.size() < 3 * n) {
        R::V3 p;
        for (int a = 0; a < 3; ++a) p[a] = s.lo[a] + U(rng) * (s.hi[a] - s.lo[a]);
        const double d = s.dist(p);
        if (d < min_dist) continue;
        if (d > s.c.d0 && U(rng) < 0.5) continue;
        for (int a = 0; a < 3; ++a) x.push_back(float(p[a]));
    }
    return x;
}

class CurlScene : public ::testing::TestWithParam<std::string> {};

// Device (through t_curl, analytic and finite-difference) against the double
// reference, for the scene's primitives, static and time-varying.
TEST_P(CurlScene, DeviceKernelMatchesReference) {
    const Scene s = scene(GetParam());
    std::vector<cl_float4> pr;
    for (const auto& p : s.prims) {
        pr.push_back({{p.a[0], p.a[1], p.a[2], p.a[3]}});
        pr.push_back({{p.b[0], p.b[1], p.b[2], p.b[3]}});
    }
    if (pr.empty()) pr.push_back({{0, 0, 0, 0}});
    const auto xs = scene_points(s, 2000, 2e-3 * s.c.scale, 5);
    std::vector<cl_float4> x;
    std::mt19937 rng(9);
    for (size_t i = 0; i < xs.size() / 3; ++i)
        x.push_back({{xs[3 * i], xs[3 * i + 1], xs[3 * i + 2], float(std::uniform_real_distribution<>(0, 3)(rng))}});
    const float hfd = float(1e-2 * s.c.scale);
    for (int timed = 0; timed < 2; ++timed) {
        SCOPED_TRACE(timed ? "time-varying" : "static");
        auto run_curl = [&](int mode) {
            cl::Buffer bx = to_dev(x), bp = to_dev(pr), bo = out_buf(x.size() * sizeof(cl_float4));
            cl::Kernel k(test_program(), "t_curl");
            cl_uint a = 0;
            k.setArg(a++, bx); k.setArg(a++, float(s.c.scale)); k.setArg(a++, float(s.c.gain));
            k.setArg(a++, float(s.c.d0)); k.setArg(a++, float(s.c.time_scale)); k.setArg(a++, cl_ulong(s.c.seed));
            k.setArg(a++, cl_int(timed)); k.setArg(a++, bp); k.setArg(a++, cl_uint(s.prims.size()));
            k.setArg(a++, cl_int(mode)); k.setArg(a++, hfd); k.setArg(a++, bo);
            run(k, x.size());
            return from_dev<cl_float4>(bo, x.size());
        };
        const auto va = run_curl(0), vf = run_curl(1);
        double rms = 0;
        for (const auto& v : va) rms += v.s[0] * v.s[0] + v.s[1] * v.s[1] + v.s[2] * v.s[2];
        rms = std::sqrt(rms / va.size());
        ASSERT_GT(rms, 0.1 * s.c.gain);
        double err_ref = 0, err_fd = 0, err_ref_fd = 0, ref_div = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            const R::V3 p{x[i].s[0], x[i].s[1], x[i].s[2]};
            const R::V3 r = R::curl_noise(s.c, s.prims, p, x[i].s[3], timed);
            const bool stencil_free = s.dist(p) > 1.5 * hfd;
            for (int j = 0; j < 3; ++j) {
                err_ref = std::max(err_ref, std::fabs(va[i].s[j] - r[j]));
                if (stencil_free) err_fd = std::max(err_fd, std::fabs(double(va[i].s[j]) - vf[i].s[j]));
            }
            if (i < 500) {
                const R::V3 rf = R::curl_noise_fd(s.c, s.prims, p, 1e-6 * s.c.scale, x[i].s[3], timed);
                for (int j = 0; j < 3; ++j) err_ref_fd = std::max(err_ref_fd, std::fabs(r[j] - rf[j]));
                // the reference itself is divergence-free (double central differences)
                double div = 0, g2 = 0;
                for (int j = 0; j < 3; ++j) {
                    R::V3 pp = p, pm = p;
                    pp[j] += 1e-5; pm[j] -= 1e-5;
                    const R::V3 a = R::curl_noise(s.c, s.prims, pp, x[i].s[3], timed),
                                b = R::curl_noise(s.c, s.prims, pm, x[i].s[3], timed);
                    for (int c = 0; c < 3; ++c) {
                        const double dv = (a[c] - b[c]) / 2e-5;
                        g2 += dv * dv;
                        if (c == j) div += dv;
                    }
                }
                ref_div = std::max(ref_div, std::fabs(div) / std::sqrt(g2));
            }
        }
        EXPECT_LT(err_ref / rms, 1e-4) << "analytic V: max |device - double reference| / rms|V|";
        EXPECT_LT(err_ref_fd / rms, 1e-6) << "reference: analytic derivative of Eq. 2 vs its double FD curl";
        EXPECT_LT(err_fd / rms, 1e-2) << "device analytic vs device FD mode (h = scale/100, float)";
        EXPECT_LT(ref_div, 1e-6) << "reference max |div V| / |grad V|_F";
    }
}

// Through the C API: swcl_noise_sample agrees with the reference; its
// finite-difference mode agrees with the analytic curl; V is divergence-free
// (central differences of swcl_noise_sample output); a time-varying field
// changes with time, a static one does not.
TEST_P(CurlScene, SampledFieldMatchesReferenceAndIsDivergenceFree) {
    const Scene s = scene(GetParam());
    const size_t n = 1500;
    const auto x = scene_points(s, n, 2e-3 * s.c.scale, 6);
    for (int timed = 0; timed < 2; ++timed) {
        SCOPED_TRACE(timed ? "time-varying" : "static");
        const swcl_noise_desc d = s.get(timed);
        const float t = 1.3f;
        const auto v = sample(d, x, t);
        const double rms = rms3(v);
        ASSERT_GT(rms, 0.1 * s.c.gain);

        double err_ref = 0;
        for (size_t i = 0; i < n; ++i) {
            const R::V3 r = R::curl_noise(s.c, s.prims, {x[3 * i], x[3 * i + 1], x[3 * i + 2]}, t, timed);
            for (int j = 0; j < 3; ++j) err_ref = std::max(err_ref, std::fabs(v[3 * i + j] - r[j]));
        }
        EXPECT_LT(err_ref / rms, 1e-4) << "swcl_noise_sample vs double reference";

        swcl_noise_desc dfd = d;
        dfd.finite_difference = 1;  // fd_step 0: scale / 100
        const auto vf = sample(dfd, x, t);
        const double hfd = s.c.scale / 100;
        double err_fd = 0;
        for (size_t i = 0; i < n; ++i) {
            if (s.dist({x[3 * i], x[3 * i + 1], x[3 * i + 2]}) <= 1.5 * hfd) continue;
            for (int j = 0; j < 3; ++j) err_fd = std::max(err_fd, std::fabs(double(v[3 * i + j]) - vf[3 * i + j]));
        }
        EXPECT_LT(err_fd / rms, 1e-2) << "finite_difference = 1 vs analytic";

        // Divergence by a 7-point stencil, step h = 2e-3 scale (actual float steps).
        const double h = 2e-3 * s.c.scale;
        std::vector<float> st;
        for (size_t i = 0; i < n; ++i)
            for (int j = 0; j < 3; ++j)
                for (int sg = -1; sg <= 1; sg += 2)
                    for (int a = 0; a < 3; ++a) st.push_back(float(x[3 * i + a] + (a == j ? sg * h : 0.0)));
        const auto vs = sample(d, st, t);
        double worst = 0;
        for (size_t i = 0; i < n; ++i) {
            double div = 0, g2 = 0;
            for (int j = 0; j < 3; ++j) {
                const size_t m = 6 * i + 2 * j, p = m + 1;
                const double step = double(st[3 * p + j]) - double(st[3 * m + j]);
                for (int c = 0; c < 3; ++c) {
                    const double dv = (double(vs[3 * p + c]) - double(vs[3 * m + c])) / step;
                    g2 += dv * dv;
                    if (c == j) div += dv;
                }
            }
            worst = std::max(worst, std::fabs(div) / std::sqrt(g2));
        }
        EXPECT_LT(worst, 1e-3) << "max |div V| / |grad V|_F";

        // Time: the static field is the same at any time; the time-varying one changes.
        const auto later = sample(d, x, t + float(s.c.time_scale));
        if (!timed) {
            EXPECT_EQ(std::memcmp(later.data(), v.data(), v.size() * sizeof(float)), 0);
        } else {
            std::vector<float> diff(v.size());
            for (size_t i = 0; i < v.size(); ++i) diff[i] = later[i] - v[i];
            EXPECT_GT(rms3(diff), 0.3 * rms) << "time-varying field after one time_scale";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Curl, CurlScene, ::testing::Values("free", "walls", "sphere", "box", "all"),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// ============================================================== boundaries

using SurfacePoints = std::vector<std::pair<R::V3, R::V3>>;  // point on the surface, unit normal into free space

// |V.n| at the boundary is tiny compared with rms |V| there, and grows off it.
void check_normal_velocity(const Scene& s, bool timed, const SurfacePoints& surf, const char* what) {
    SCOPED_TRACE(std::string(what) + (timed ? ", time-varying" : ", static"));
    std::vector<float> x, xin;
    for (const auto& pn : surf)
        for (int a = 0; a < 3; ++a) {
            x.push_back(float(pn.first[a]));
            xin.push_back(float(pn.first[a] + 0.1 * s.c.d0 * pn.second[a]));
        }
    const auto v = sample(s.get(timed), x, 0.7f), vin = sample(s.get(timed), xin, 0.7f);
    const double rms = rms3(v);
    ASSERT_GT(rms, 0.1 * s.c.gain) << "the tangential flow along the boundary is not zero";
    double at0 = 0, off = 0;
    for (size_t i = 0; i < surf.size(); ++i) {
        double vn = 0, vn_in = 0;
        for (int a = 0; a < 3; ++a) {
            vn += v[3 * i + a] * surf[i].second[a];
            vn_in += vin[3 * i + a] * surf[i].second[a];
        }
        at0 = std::max(at0, std::fabs(vn) / rms);
        off = std::max(off, std::fabs(vn_in) / rms);
    }
    EXPECT_LT(at0, 1e-4) << "max |V.n| / rms|V| on the boundary";
    EXPECT_GT(off, 1e-2) << "the normal flow 0.1 d0 away from the boundary is not suppressed";
}

TEST(CurlBoundaries, NoNormalFlowOnWallsSphereAndRoundedBox) {
    const Scene s = scene("all");
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0, 1);
    SurfacePoints walls, sphere, box;
    for (int i = 0; i < 600; ++i) {
        const int ax = i % 3, side = (i / 3) % 2;
        R::V3 p{U(rng) * 6, U(rng) * 6, U(rng) * 6}, n{0, 0, 0};
        if (i % 10 == 0) p[(ax + 1) % 3] = U(rng) * 0.5;  // near edges and corners
        if (i % 20 == 0) p[(ax + 2) % 3] = 6 - U(rng) * 0.5;
        p[ax] = side ? 6 : 0;
        n[ax] = side ? -1 : 1;
        walls.push_back({p, n});
    }
    for (int i = 0; i < 600; ++i) {
        const double z = 2 * U(rng) - 1, ph = 6.283185307179586 * U(rng), r = std::sqrt(1 - z * z);
        const R::V3 n{r * std::cos(ph), r * std::sin(ph), z};
        sphere.push_back({{2 + 0.6 * n[0], 2 + 0.6 * n[1], 2 + 0.6 * n[2]}, n});
    }
    const R::V3 bc{4.2, 4.2, 3.5}, bh{0.5, 0.4, 0.6};
    const double rr = 0.1;
    for (int i = 0; i < 600; ++i) {  // the surface d = 0 of the L4-rounded box: faces, edges, corners
        const int nact = 1 + i % 3;
        R::V3 q, w{0, 0, 0}, sg, p, n;
        double w4 = 0, gl = 0;
        for (int k = 0; k < 3; ++k) {
            sg[k] = U(rng) < 0.5 ? -1 : 1;
            if ((k + i) % 3 < nact) { w[k] = 0.05 + U(rng); w4 += std::pow(w[k], 4); }
        }
        for (int k = 0; k < 3; ++k) {
            w[k] /= std::pow(w4, 0.25);  // ||w||_4 = 1
            q[k] = w[k] > 0 ? (bh[k] - rr) + rr * w[k] : (2 * U(rng) - 1) * (bh[k] - rr);
            p[k] = bc[k] + sg[k] * q[k];
            n[k] = sg[k] * w[k] * w[k] * w[k];
            gl += n[k] * n[k];
        }
        for (int k = 0; k < 3; ++k) n[k] /= std::sqrt(gl);
        box.push_back({p, n});
    }
    for (int timed = 0; timed < 2; ++timed) {
        check_normal_velocity(s, timed, walls, "domain walls (edges and corners included)");
        check_normal_velocity(s, timed, sphere, "sphere obstacle");
        check_normal_velocity(s, timed, box, "rounded box obstacle");
    }
}

TEST(CurlBoundaries, AdvectedInsectsStayInsideWallsAndOutOfObstacles) {
    // Explicit Euler through the sampled field, as the field model moves
    // insects: V.n vanishes linearly at a wall, so d_new >= d (1 - |grad V| dt)
    // stays positive while |grad V| dt < 1.
    Scene s = base_scene("advect");
    s.c.scale = 0.4; s.c.gain = 0.5; s.c.d0 = 0.4; s.c.time_scale = 1.0;
    s.desc.scale = 0.4f; s.desc.gain = 0.5f; s.desc.boundary_distance = 0.4f;
    add_walls(s, 0, 2);
    const R::V3 sc{1.0, 1.0, 1.0};
    const float sr = 0.3f;
    add_sphere(s, sc, sr);
    const size_t n = 400;
    auto x = scene_points(s, n, 0.02, 8);
    const float dt = 0.02f;
    for (int timed = 0; timed < 2; ++timed) {
        SCOPED_TRACE(timed ? "time-varying" : "static");
        const swcl_noise_desc d = s.get(timed);
        auto p = x;
        double travelled = 0, min_wall = 1e9, min_sphere = 1e9;
        for (int step = 0; step < 250; ++step) {
            const auto v = sample(d, p, step * dt, step);
            for (size_t i = 0; i < 3 * n; ++i) {
                p[i] += v[i] * dt;
                travelled += std::fabs(v[i] * dt);
            }
            for (size_t i = 0; i < n; ++i) {
                double r2 = 0;
                for (int a = 0; a < 3; ++a) {
                    min_wall = std::min({min_wall, double(p[3 * i + a]), 2.0 - p[3 * i + a]});
                    r2 += (p[3 * i + a] - sc[a]) * (p[3 * i + a] - sc[a]);
                }
                min_sphere = std::min(min_sphere, std::sqrt(r2) - sr);
            }
        }
        EXPECT_GT(travelled / n, 1.0) << "insects moved (mean path length in m, summed over axes)";
        EXPECT_GE(min_wall, 0.0) << "closest approach to the domain walls";
        EXPECT_GE(min_sphere, 0.0) << "closest approach to the sphere obstacle";
    }
}

// =================================================================== baked

TEST(BakedNoise, AgreesWithProceduralAtNodesAndWithinTrilinearErrorBetween) {
    swcl_noise_desc proc = swcl_noise_desc_default();
    proc.type = SWCL_NOISE_CURL;
    proc.scale = 0.4f;
    proc.gain = 0.3f;
    proc.seed = 17;
    for (int a = 0; a < 3; ++a) { proc.region_min[a] = 0.0f; proc.region_max[a] = 2.0f; }
    const float lo = 0.0f, hi = 2.0f;

    // Random points in the region; the procedural field there.
    const size_t n = 3000;
    const auto pts = swarmcl::test::random_points(n, lo, hi, 21);
    const auto vp = sample(proc, pts);
    const double rms = rms3(vp);
    ASSERT_GT(rms, 0.05);

    // Largest second derivatives |d2V_c/dx_k^2| over dense samples (central
    // differences of the procedural field, step e = 0.01).
    const double e = 0.01;
    std::vector<float> st;
    const auto dense = swarmcl::test::random_points(4000, lo, hi, 22);
    for (size_t i = 0; i < 4000; ++i)
        for (int k = 0; k < 3; ++k)
            for (int sg = -1; sg <= 1; sg += 2)
                for (int a = 0; a < 3; ++a) st.push_back(dense[3 * i + a] + (a == k ? float(sg * e) : 0.0f));
    const auto vst = sample(proc, st), vd = sample(proc, dense);
    std::array<double, 3> m2{0, 0, 0};  // per axis k: max over points and components
    for (size_t i = 0; i < 4000; ++i)
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) {
                const double d2 = (vst[3 * (6 * i + 2 * k + 1) + c] - 2.0 * vd[3 * i + c] + vst[3 * (6 * i + 2 * k) + c]) / (e * e);
                m2[k] = std::max(m2[k], std::fabs(d2));
            }

    double rms_err[2] = {0, 0};
    const uint32_t res[2] = {17, 33};
    for (int r = 0; r < 2; ++r) {
        SCOPED_TRACE("bake_resolution " + std::to_string(res[r]));
        swcl_noise_desc baked = proc;
        baked.baked = 1;
        for (int a = 0; a < 3; ++a) baked.bake_resolution[a] = res[r];
        const float cell = (hi - lo) / float(res[r] - 1);

        // At the grid nodes (placed as the bake kernel places them).
        std::vector<float> nodes;
        for (uint32_t k = 0; k < res[r]; k += 3)
            for (uint32_t j = 0; j < res[r]; j += 2)
                for (uint32_t i = 0; i < res[r]; ++i) {
                    nodes.push_back(lo + cell * float(i));
                    nodes.push_back(lo + cell * float(j));
                    nodes.push_back(lo + cell * float(k));
                }
        const auto bn = sample(baked, nodes), pn = sample(proc, nodes);
        double node_err = 0;
        for (size_t i = 0; i < bn.size(); ++i) node_err = std::max(node_err, double(std::fabs(bn[i] - pn[i])));
        EXPECT_LT(node_err, 1e-5 * rms) << "baked vs procedural at grid nodes (float rounding of the node weights only)";

        // Between nodes the baked field is the trilinear interpolation of the
        // procedural field at the 8 surrounding nodes (host interpolation in double).
        std::vector<float> all_nodes;
        for (uint32_t k = 0; k < res[r]; ++k)
            for (uint32_t j = 0; j < res[r]; ++j)
                for (uint32_t i = 0; i < res[r]; ++i)
                    for (uint32_t c : {i, j, k}) all_nodes.push_back(lo + cell * float(c));
        const auto pv = sample(proc, all_nodes);
        const auto vb = sample(baked, pts);
        const double interp_err = trilinear_error(pts, vb, pv, lo, cell, res[r]);
        EXPECT_LT(interp_err, 2e-5 * rms) << "baked vs host trilinear interpolation of the procedural nodes";

        // Baked vs procedural between nodes: the trilinear interpolation error per component is at
        // most (h^2 / 8) sum_k max |d2V/dx_k^2|; 1.5x for maxima between samples.
        const double bound = 1.5 * cell * cell / 8.0 * (m2[0] + m2[1] + m2[2]);
        double worst = 0, s2 = 0;
        for (size_t i = 0; i < vb.size(); ++i) {
            const double d = std::fabs(double(vb[i]) - vp[i]);
            worst = std::max(worst, d);
            s2 += d * d;
        }
        rms_err[r] = std::sqrt(s2 / vb.size());
        EXPECT_LT(worst, bound) << "max |baked - procedural| between nodes";

        // Outside the region the field is clamped: the value at the nearest
        // point of the region.
        std::vector<float> out_pts, clamped;
        for (size_t i = 0; i < 300; ++i) {
            for (int a = 0; a < 3; ++a) {
                float q = pts[3 * i + a];
                if ((i + a) % 3 == 0) q = (i % 2) ? hi + 0.5f + 0.01f * float(i % 7) : lo - 0.7f;
                out_pts.push_back(q);
                clamped.push_back(std::min(std::max(q, lo), hi));
            }
        }
        const auto vo = sample(baked, out_pts), vc = sample(baked, clamped);
        EXPECT_EQ(std::memcmp(vo.data(), vc.data(), vo.size() * sizeof(float)), 0)
            << "outside the region = the border value";
    }
    // Second-order convergence: halving h divides the error by ~4.
    // (measured: 0.076 and 0.022, ratio 0.29, rms |V| 0.52)
    EXPECT_LT(rms_err[1], 0.35 * rms_err[0]) << "rms error at 33 vs 17 nodes: " << rms_err[1] << " vs " << rms_err[0];
    // At h = scale / 6.4 the baked field is a usable stand-in.
    EXPECT_LT(rms_err[1], 0.1 * rms) << "rms |baked - procedural| at 33 nodes per axis";
}

// The bake at a small size (what scripts/oclgrind_check.py runs under
// Oclgrind, where the test above takes minutes): at the nodes the baked
// field is the procedural one, between them the host's trilinear
// interpolation of the procedural nodes, outside the region the border value.
TEST(BakedNoise, SmallBakeIsTheProceduralFieldAtNodesAndItsInterpolationBetween) {
    swcl_noise_desc proc = swcl_noise_desc_default();
    proc.type = SWCL_NOISE_CURL;
    proc.scale = 0.4f;
    proc.gain = 0.3f;
    proc.seed = 17;
    const float lo = 0.0f, hi = 2.0f;
    const uint32_t res = 5;
    for (int a = 0; a < 3; ++a) { proc.region_min[a] = lo; proc.region_max[a] = hi; }
    swcl_noise_desc baked = proc;
    baked.baked = 1;
    for (int a = 0; a < 3; ++a) baked.bake_resolution[a] = res;
    const float cell = (hi - lo) / float(res - 1);
    std::vector<float> nodes;  // every node, x fastest (placed as the bake kernel places them)
    for (uint32_t k = 0; k < res; ++k)
        for (uint32_t j = 0; j < res; ++j)
            for (uint32_t i = 0; i < res; ++i)
                for (uint32_t c : {i, j, k}) nodes.push_back(lo + cell * float(c));
    const auto pn = sample(proc, nodes), bn = sample(baked, nodes);
    const double rms = rms3(pn);
    ASSERT_GT(rms, 0.05);
    double node_err = 0;
    for (size_t i = 0; i < bn.size(); ++i) node_err = std::max(node_err, double(std::fabs(bn[i] - pn[i])));
    EXPECT_LT(node_err, 1e-5 * rms) << "baked vs procedural at the nodes";
    const size_t n = 40;
    const auto pts = swarmcl::test::random_points(n, lo, hi, 23);
    const auto vb = sample(baked, pts);
    const double interp_err = trilinear_error(pts, vb, pn, lo, cell, res);
    EXPECT_LT(interp_err, 2e-5 * rms) << "baked vs host trilinear interpolation of the procedural nodes";
    std::vector<float> out_pts, clamped;
    for (size_t i = 0; i < 20; ++i)
        for (int a = 0; a < 3; ++a) {
            float q = pts[3 * i + a];
            if ((i + a) % 3 == 0) q = (i % 2) ? hi + 0.5f : lo - 0.7f;
            out_pts.push_back(q);
            clamped.push_back(std::min(std::max(q, lo), hi));
        }
    const auto vo = sample(baked, out_pts), vc = sample(baked, clamped);
    EXPECT_EQ(std::memcmp(vo.data(), vc.data(), vo.size() * sizeof(float)), 0) << "outside the region = the border";
}

// ================================================================ bad input

class NoiseBadInput : public ::testing::Test {
protected:
    // Expects INVALID_ARGUMENT, a message containing `name`, and `out` untouched.
    void expect_refused(const swcl_noise_desc& d, const char* name, const std::vector<float>& pts,
                        bool null_out = false) {
        std::vector<float> out(pts.size(), kSentinel);
        const swcl_status s =
            swcl_noise_sample(capi(), &d, pts.data(), pts.size() / 3, 0.5f, 3, null_out ? nullptr : out.data());
        EXPECT_EQ(s, SWCL_ERROR_INVALID_ARGUMENT) << name;
        const std::string msg = swcl_last_error();
        EXPECT_NE(msg.find(name), std::string::npos) << "message '" << msg << "' does not name '" << name << "'";
        for (float v : out) ASSERT_EQ(v, kSentinel) << name << ": output written on failure";
    }
    void expect_refused(const swcl_noise_desc& d, const char* name) { expect_refused(d, name, pts_); }
    void TearDown() override {  // the context still works after every refusal
        const auto v = sample(swcl_noise_desc_default(), pts_);
        for (float x : v) ASSERT_TRUE(std::isfinite(x));
    }
    static constexpr float kSentinel = 12345.0f;
    std::vector<float> pts_ = swarmcl::test::random_points(16, -1, 1, 4);
    swcl_noise_desc d_ = swcl_noise_desc_default();
};

TEST_F(NoiseBadInput, ScaleGainTimeScale) {
    for (float bad : {0.0f, -1.0f, std::nanf(""), INFINITY}) {
        swcl_noise_desc d = d_;
        d.scale = bad;
        expect_refused(d, "scale");
    }
    swcl_noise_desc d = d_;
    d.gain = std::nanf("");
    expect_refused(d, "gain");
    d = d_;
    d.time_scale = std::nanf("");
    expect_refused(d, "time_scale");
    d = d_;
    d.time_scale = -1.0f;
    expect_refused(d, "time_scale");
}

TEST_F(NoiseBadInput, Boundaries) {
    swcl_noise_desc d = d_;
    d.boundary_count = 2;
    d.boundaries = nullptr;
    expect_refused(d, "boundaries");

    swcl_obstacle b{};
    d = d_;
    d.boundaries = &b;
    d.boundary_count = 1;
    b.type = SWCL_OBSTACLE_BOX;  // empty box
    expect_refused(d, "half_extents");
    b.half_extents[0] = b.half_extents[1] = 0.5f;  // one zero extent
    expect_refused(d, "half_extents");
    b = swcl_obstacle{};
    b.type = SWCL_OBSTACLE_SPHERE;  // zero radius
    expect_refused(d, "radius");
    b.radius = std::nanf("");
    expect_refused(d, "radius");
    b = swcl_obstacle{};
    b.type = SWCL_OBSTACLE_PLANE;  // zero normal
    expect_refused(d, "normal");
    b = swcl_obstacle{};
    b.type = SWCL_OBSTACLE_CYLINDER;  // the one obstacle type, but not an analytic boundary
    b.radius = b.height = 0.5f;
    expect_refused(d, "boundaries[0]: type 4 is not one of SPHERE, BOX, PLANE");
}

TEST_F(NoiseBadInput, Baking) {
    swcl_noise_desc d = d_;
    for (int a = 0; a < 3; ++a) { d.region_min[a] = -1; d.region_max[a] = 1; }
    d.baked = 1;
    swcl_noise_desc w = d;
    w.type = SWCL_NOISE_WHITE;
    expect_refused(w, "WHITE");
    w.type = SWCL_NOISE_GAUSSIAN;
    expect_refused(w, "GAUSSIAN");
    swcl_noise_desc t = d;
    t.time_scale = 1.0f;
    expect_refused(t, "time_scale");
    swcl_noise_desc r = d;
    r.bake_resolution[1] = 1;
    expect_refused(r, "bake_resolution");
    swcl_noise_desc nr = d_;  // baking with no region
    nr.baked = 1;
    expect_refused(nr, "region");
}

TEST_F(NoiseBadInput, DomainWallsWithoutRegion) {
    swcl_noise_desc d = d_;
    d.domain_walls = 1;
    expect_refused(d, "domain_walls");
}

TEST_F(NoiseBadInput, PointsAndOutput) {
    auto pts = pts_;
    pts[3 * 5 + 1] = std::nanf("");
    expect_refused(d_, "point", pts);
    pts[3 * 5 + 1] = INFINITY;
    expect_refused(d_, "point", pts);
    expect_refused(d_, "out", pts_, /*null_out=*/true);
    // the same for the random types, which do not read positions
    swcl_noise_desc w = d_;
    w.type = SWCL_NOISE_WHITE;
    pts[3 * 5 + 1] = std::nanf("");
    expect_refused(w, "point", pts);
    EXPECT_EQ(swcl_noise_sample(capi(), nullptr, pts_.data(), 16, 0, 0, pts.data()), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("desc"), std::string::npos);
}

}  // namespace

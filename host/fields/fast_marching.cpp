#include "fields/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>

#include "core/error.hpp"
#include "core/helper_thread.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace swarmcl {
namespace {

// The march on a padded copy of the grid: a border of kPad cells on every
// side that is impassable and never known, so neighbour indices (up to two
// cells away for the second-order stencil) need no bounds checks.
constexpr int64_t kPad = 2;

constexpr size_t kHugePage = size_t(2) << 20;

// The per-neighbour steps are lambdas called six times per accepted cell;
// GCC would otherwise call them.
#if defined(__GNUC__)
#define SWARMCL_INLINE __attribute__((always_inline))
#else
#define SWARMCL_INLINE
#endif

// a < b ? a : b and a > b ? a : b without a branch: which neighbour is
// smaller is a coin toss the processor cannot predict, and compilers turn
// std::min into a branch in the big inlined loop.  The __m128d overloads do
// the same for two cells at once, lane by lane, so that the first-order
// solve below gives every cell the same bits whichever way it is solved.
inline double min_nb(double a, double b) {
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a < b ? a : b;
#endif
}
inline double max_nb(double a, double b) {
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a > b ? a : b;
#endif
}
// a > b ? x : y, likewise.
inline double select_gt(double a, double b, double x, double y) {
#if defined(__SSE2__)
    const __m128d m = _mm_cmpgt_sd(_mm_set_sd(a), _mm_set_sd(b));
    return _mm_cvtsd_f64(_mm_or_pd(_mm_and_pd(m, _mm_set_sd(x)), _mm_andnot_pd(m, _mm_set_sd(y))));
#else
    return a > b ? x : y;
#endif
}
inline double sqrt_nb(double a) { return std::sqrt(a); }
template <class V>
V splat(double a);
template <>
inline double splat<double>(double a) {
    return a;
}
#if defined(__SSE2__)
inline __m128d min_nb(__m128d a, __m128d b) { return _mm_min_pd(a, b); }
inline __m128d max_nb(__m128d a, __m128d b) { return _mm_max_pd(a, b); }
inline __m128d select_gt(__m128d a, __m128d b, __m128d x, __m128d y) {
    const __m128d m = _mm_cmpgt_pd(a, b);
    return _mm_or_pd(_mm_and_pd(m, x), _mm_andnot_pd(m, y));
}
inline __m128d sqrt_nb(__m128d a) { return _mm_sqrt_pd(a); }
template <>
inline __m128d splat<__m128d>(double a) {
    return _mm_set1_pd(a);
}
#endif

// The first-order upwind solution from the smaller known neighbour along
// each axis, b0, b1, b2 (+inf: none), and f h: the axes are added in
// increasing order of their value while the solution stays above them.
// Sorted by min/max and each stage computed and selected without a branch,
// as the processor cannot predict the order nor how many axes the solution
// uses.  V: double, or __m128d for two cells.
template <class V>
inline V first_order(V b0, V b1, V b2, V fh) {
    const V lo01 = min_nb(b0, b1), hi01 = max_nb(b0, b1);
    const V s0 = min_nb(lo01, b2), s2 = max_nb(hi01, b2);
    const V s1 = max_nb(lo01, min_nb(hi01, b2));
    const V zero = splat<V>(0.0);
    const V r1 = s0 + fh;
    const V s01 = s0 + s1, sq01 = s0 * s0 + s1 * s1;
    const V r2 = (s01 + sqrt_nb(max_nb(s01 * s01 - splat<V>(2.0) * (sq01 - fh * fh), zero))) * splat<V>(0.5);
    const V s012 = s01 + s2, sq012 = sq01 + s2 * s2;
    const V r3 = (s012 + sqrt_nb(max_nb(s012 * s012 - splat<V>(3.0) * (sq012 - fh * fh), zero))) / splat<V>(3.0);
    return select_gt(r1, s1, select_gt(r2, s2, r3, r2), r1);
}

// One cell of the padded copy: its value (known or tentative; +inf: far or
// blocked) beside its slowness, whose sign tells the state: > 0 open (far or
// trial), < 0 known or blocked (impassable or border: -inf, with u = +inf).
// Together, as the stencil of a cell reads both for its neighbours.
struct Cell {
    double u;
    double f;
};

// The padded grid's cells, on transparent huge pages where Linux offers
// them (madvise; Debian's default is "madvise").  A cell's stencil reaches one
// z-slice either way (279 KB apart at 128^3), so on 4 KB pages nearly every
// neighbour is another page and a TLB miss (docs/benchmarks.md, "Fast
// marching on huge pages").  Small grids (under one 2 MB page) take plain
// memory.
class CellArray {
public:
    explicit CellArray(size_t n) {
        const size_t bytes = n * sizeof(Cell);
        void* p = nullptr;
        if (bytes >= kHugePage) {
            const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;  // aligned_alloc wants a multiple
            p = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
            if (p) madvise(p, rounded, MADV_HUGEPAGE);  // a hint: refused, the pages stay small
#endif
        } else {
            p = std::malloc(std::max<size_t>(bytes, 1));
        }
        if (!p) fail(Status::OutOfMemory, "fast marching: out of memory for " + std::to_string(n) + " cells");
        cells_.reset(static_cast<Cell*>(p));  // uninitialised: fast_march writes every cell
    }
    Cell* data() { return cells_.get(); }
    Cell& operator[](size_t i) { return cells_.get()[i]; }

private:
    struct Free {
        void operator()(Cell* p) const { std::free(p); }
    };
    std::unique_ptr<Cell, Free> cells_;
};

template <bool kSecond>
void march(Cell* cell, size_t np, const int64_t stride[3], double h, double delta, HelperThread* helper) {
    // The value of cell q for the stencil, +inf unless known: u + 0 or
    // u + inf by the sign bit of f (exact; u is never -inf or NaN), not a
    // branch, as the processor could not predict which neighbours are known.
    const double add[2] = {kInf, 0.0};
    auto known = [&](size_t q) {
        uint64_t bits;
        std::memcpy(&bits, &cell[q].f, sizeof bits);
        return cell[q].u + add[bits >> 63];
    };
    // Dial's buckets (see fast_march): bucket b holds the cells whose value
    // lies in [b delta, (b + 1) delta).
    std::vector<std::vector<uint32_t>> buckets(64), spare;  // spare: drained buckets' storage, for reuse
    size_t current = 0;
    auto enqueue = [&](uint32_t p, size_t b) {
        b = std::max(b, current);  // never below the bucket being drained (a bucket drained is not visited again)
        if (b >= buckets.size()) buckets.resize(std::max(b + 1, 2 * buckets.size()));
        std::vector<uint32_t>& q = buckets[b];
        if (q.capacity() == 0 && !spare.empty()) {
            q.swap(spare.back());
            spare.pop_back();
        }
        q.push_back(p);
    };

    // Solves the upwind quadratic at cell p of slowness fp from its known
    // neighbours (+inf when it has none).
    auto solve = [&](size_t p, double fp) SWARMCL_INLINE -> double {
        const double fh = fp * h;
        double b1[3], b2[3] = {kInf, kInf, kInf};  // per axis: the smaller known neighbour, and the known cell beyond it
        for (int a = 0; a < 3; ++a) {
            const double lo = known(p - stride[a]), hi = known(p + stride[a]);
            b1[a] = min_nb(hi, lo);  // a tie takes the lower side
            if (kSecond) {
                const double beyond = known(hi < lo ? p + 2 * stride[a] : p - 2 * stride[a]);
                if (beyond <= b1[a] && b1[a] < kInf) b2[a] = beyond;
            }
        }
        double result = first_order(b1[0], b1[1], b1[2], fh);
        if (kSecond) {
            // sum_a c_a (u - b_a)^2 = f^2 over the axes the first-order
            // solution uses, with c = 9/(4h^2), b = (4 b1 - b2)/3 where the
            // cell beyond is known (one-sided second-order difference), else
            // c = 1/h^2, b = b1.  Kept only when it is a consistent upwind
            // value (between the smallest neighbour and the first-order one).
            double A = 0, B = 0, C = -fp * fp;
            bool any2 = false;
            for (int a = 0; a < 3; ++a) {
                if (!(b1[a] < result)) continue;
                const bool two = b2[a] < kInf;
                const double ca = two ? 9.0 / (4.0 * h * h) : 1.0 / (h * h);
                const double ba = two ? (4.0 * b1[a] - b2[a]) / 3.0 : b1[a];
                any2 |= two;
                A += ca;
                B -= 2.0 * ca * ba;
                C += ca * ba * ba;
            }
            const double disc = B * B - 4 * A * C;
            if (any2 && disc >= 0) {
                const double r2 = (-B + std::sqrt(disc)) / (2 * A);
                const double s0 = min_nb(min_nb(b1[0], b1[1]), b1[2]);
                if (r2 >= s0 && r2 <= result) result = r2;
            }
        }
        return result;
    };

    // Bucket indices by a product, not a division (not on the march's
    // critical path, but 2 divisions a visit: 0.357-0.379 -> 0.351-0.352 s
    // at 128^3).  An index can differ from floor(v / delta) by one at a
    // bucket's edge, which the untidy queue's bound allows (the errors at
    // 128^3 stay 1.79 and 0.14 cells, fmm_bench).
    const double inv_delta = 1.0 / delta;
    // Cell q's value becomes v where that is lower.  A queued cell whose
    // value stays in its bucket keeps its place (it is accepted with the
    // value it has then).
    // Writes v where it is below t (cell q's value) and returns the bucket q
    // must join, kNoQueue where none (a queued cell whose value stays in its
    // bucket keeps its place).
    constexpr size_t kNoQueue = 0xFFFFFFFFu;
    auto lower_cell = [&](size_t q, double v, double t) SWARMCL_INLINE -> size_t {
        if (!(v < t)) return kNoQueue;
        cell[q].u = v;
        const size_t b = size_t(v * inv_delta);
        return !(t < kInf) || b != size_t(t * inv_delta) ? std::min<size_t>(b, kNoQueue - 1) : kNoQueue;
    };
    auto lower_to = [&](size_t q, double v, double t) SWARMCL_INLINE {  // t: cell[q].u
        const size_t b = lower_cell(q, v, t);
        if (b != kNoQueue) enqueue(uint32_t(q), b);
    };
    auto visit = [&](size_t nb) SWARMCL_INLINE {
        if (!(cell[nb].f > 0.0)) return;  // known or blocked
        lower_to(nb, solve(nb, cell[nb].f), cell[nb].u);
    };
    auto push_neighbours = [&](size_t p) {
        visit(p - stride[0]);
        visit(p + stride[0]);
        visit(p - stride[1]);
        visit(p + stride[1]);
        visit(p - stride[2]);
        visit(p + stride[2]);
    };

    // The cells accepting p reads: its neighbours and their stencils, two
    // cells out along the axes, one along the diagonals.  A bucket is a
    // list in no spatial order, so each of these is a cache miss unless
    // fetched while earlier cells are accepted (about 30% of the march at
    // 128^3).
    auto prefetch_stencil = [&](size_t q) SWARMCL_INLINE {  // (GCC drops a prefetch-only function it does not inline)
#if defined(__GNUC__)
        const int64_t sy = stride[1], sz = stride[2];
        for (const int64_t o : {-2 * sz, -sz - sy, -sz + sy, -2 * sy, sy - sz, sy + sz, 2 * sy, 2 * sz})
            __builtin_prefetch(&cell[q + o]);
        for (const int64_t o : {-sz, -sy, int64_t(0), sy, sz}) {  // with the cells beside them along x
            __builtin_prefetch(&cell[q + o - 1]);
            __builtin_prefetch(&cell[q + o]);
            __builtin_prefetch(&cell[q + o + 1]);
        }
        __builtin_prefetch(&cell[q - 2]);
        __builtin_prefetch(&cell[q + 2]);
#else
        (void)q;
#endif
    };
    constexpr size_t kChunk = 256;  // candidates a thread takes at a time
    constexpr size_t kAhead = 4;  // entries ahead: enough to hide the latency, not so many the lines are evicted again

    for (size_t p = 0; p < np; ++p)
        if (cell[p].f < 0.0 && cell[p].u < kInf) push_neighbours(p);
    // A bucket is drained in batches (docs/benchmarks.md, "Fast marching in
    // batches"): its open cells are accepted together, then each open
    // neighbour of the batch is solved once, from all of them; one at a time
    // a cell was solved once for each accepted neighbour (3.4 solves per
    // cell against 1.6 at 128^3).  A cell of the batch beside a lower one of
    // the same batch, which it has not seen, is solved again first (as the
    // later of the two was, one at a time; without it the error at 128^3
    // grows from 1.79 to 4.2 cells).  Values that fall into the bucket being
    // drained make its next batch.
    //
    // Each stage but the sort and the queueing runs on two threads where
    // there is a helper, with results that do not depend on it (the same
    // bits on one thread): the solves write only their own cells; the batch
    // is split in two halves of cell indices, and the cells within a z-slice
    // of the split (the only ones whose stencils reach into the other half)
    // are solved again after both halves, in order.
    std::vector<uint32_t> batch, sorted, bins, candidates, queue_at;
    std::vector<double> values, olds;  // a candidate's new and old value
    // in_batch: the number of the batch a cell was accepted in; listed: of
    // the batch it was listed a candidate in (mod 255: both cleared when the
    // number wraps, so no pass clears a batch's marks).
    std::vector<uint8_t> in_batch(np, 0), listed(np, 0);
    uint8_t batch_id = 0;
    struct alignas(64) Half {  // a cache line of its own: each thread writes its half's
        size_t begin = 0, end = 0;  // its accepted cells, sorted[begin, end)
        std::vector<uint32_t> found, near;
    } halves[2];
    // A batch sorted by blocks of 256 cells (a counting sort), so that
    // neighbouring cells are visited together: a bucket is in no spatial
    // order (0.255 -> 0.232 s at 128^3).
    constexpr int kBlockShift = 8;
    bins.resize((np >> kBlockShift) + 2);
    const int64_t axes[6] = {-stride[0], stride[0], -stride[1], stride[1], -stride[2], stride[2]};
    const size_t slice = size_t(stride[2]);
    size_t split = 0, edge = 0;  // the batch's halves: sorted[0, split), [split, size); cells < edge in the first

    // A cell of the batch beside a lower one of the same batch is solved again.
    auto resolve_if_lower = [&](size_t p) SWARMCL_INLINE {
        bool lower = false;
        for (const int64_t o : axes) lower |= in_batch[p + o] == batch_id && cell[p + o].u < cell[p].u;
        if (lower) cell[p].u = min_nb(cell[p].u, solve(p, -cell[p].f));
    };
    // Half k of the batch accepted: its open cells (a cell queued twice is
    // in one block, so in one half) marked known and kept in order.
    auto accept_half = [&](size_t k, size_t) {
        Half& half = halves[k];
        half.begin = half.end = k ? split : 0;
        for (size_t i = half.begin, end = k ? sorted.size() : split; i < end; ++i) {
            const uint32_t p = sorted[i];
            if (!(cell[p].f > 0.0)) continue;  // accepted already: queued again when its value dropped a bucket
            cell[p].f = -cell[p].f;
            in_batch[p] = batch_id;
            sorted[half.end++] = p;
        }
    };
    // Half k of the batch: its cells solved again where they are beside a
    // lower one (in order), and its open neighbours listed, each once.  A
    // neighbour beside both halves is the first half's; cells within a slice
    // of the edge are left for after both halves.
    auto gather_half = [&](size_t k, size_t) {
        std::vector<uint32_t>& found = halves[k].found;
        std::vector<uint32_t>& near = halves[k].near;
        found.clear();
        near.clear();
        for (size_t i = halves[k].begin; i < halves[k].end; ++i) {
            const size_t p = sorted[i];
            bool lower = false;  // beside a lower cell of the batch
            for (const int64_t o : axes) {
                const size_t q = p + o;
                lower |= in_batch[q] == batch_id && cell[q].u < cell[p].u;
                if (!(cell[q].f > 0.0)) continue;
                if (k == 1 && q < edge + slice) {  // beside the first half too? (before listed[q]: the other thread's)
                    bool first = false;
                    for (const int64_t r : axes) first |= in_batch[q + r] == batch_id && q + r < edge;
                    if (first) continue;
                }
                if (listed[q] == batch_id) continue;
                listed[q] = batch_id;
                found.push_back(uint32_t(q));
            }
            if (k == 0 ? p + slice >= edge : p < edge + slice) near.push_back(uint32_t(p));
            else if (lower) cell[p].u = min_nb(cell[p].u, solve(p, -cell[p].f));
        }
    };
    // The candidates' new values and their old ones, the candidates [begin,
    // end): each writes only its own.
    auto solve_candidates = [&](size_t begin, size_t end) {
        size_t i = begin;
#if defined(__SSE2__)
        // First order: two cells at a time, the same bits as one at a time
        // (0.225 -> 0.195 s at 128^3).
        if (!kSecond)
            for (; i + 2 <= end; i += 2) {
                if (i + kAhead < end) prefetch_stencil(candidates[i + kAhead]);
                if (i + kAhead + 1 < end) prefetch_stencil(candidates[i + kAhead + 1]);
                const size_t p = candidates[i], q = candidates[i + 1];
                __m128d b[3];
                for (int a = 0; a < 3; ++a)
                    b[a] = min_nb(_mm_set_pd(known(q + stride[a]), known(p + stride[a])),
                                  _mm_set_pd(known(q - stride[a]), known(p - stride[a])));
                const __m128d fh = _mm_mul_pd(_mm_set_pd(cell[q].f, cell[p].f), _mm_set1_pd(h));
                olds[i] = cell[p].u;
                olds[i + 1] = cell[q].u;
                _mm_storeu_pd(&values[i], first_order(b[0], b[1], b[2], fh));
            }
#endif
        for (; i < end; ++i) {
            if (i + kAhead < end) prefetch_stencil(candidates[i + kAhead]);
            values[i] = solve(candidates[i], cell[candidates[i]].f);
            olds[i] = cell[candidates[i]].u;
        }
    };
    // The candidates' lower values written, and the bucket each must join
    // (kNoQueue: none; a queued cell whose value stays in its bucket keeps
    // its place, and is accepted with the value it has then).
    auto lower_candidates = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            queue_at[i] = uint32_t(lower_cell(candidates[i], values[i], olds[i]));
        }
    };
    auto on_both = [&](size_t n, size_t chunk, auto& body) {
        if (helper && n > chunk) helper->for_chunks(n, chunk, body);
        else body(0, n);
    };

    for (current = 0; current < buckets.size(); ++current) {
        while (!buckets[current].empty()) {
            batch.clear();
            batch.swap(buckets[current]);
            if (++batch_id == 0) {
                std::fill(in_batch.begin(), in_batch.end(), uint8_t(0));
                std::fill(listed.begin(), listed.end(), uint8_t(0));
                batch_id = 1;
            }
            std::fill(bins.begin(), bins.end(), 0u);
            for (const uint32_t p : batch) ++bins[(p >> kBlockShift) + 1];
            for (size_t k = 1; k < bins.size(); ++k) bins[k] += bins[k - 1];
            const size_t n = batch.size();
            sorted.resize(n);
            for (const uint32_t p : batch) sorted[bins[p >> kBlockShift]++] = p;

            // The halves split at a block's start near the middle; a batch
            // too small to share stays whole (the same with a helper or not).
            split = n;
            if (n >= 2 * kChunk) {
                split = n / 2;
                while (split < n && sorted[split] >> kBlockShift == sorted[split - 1] >> kBlockShift) ++split;
            }
            edge = split < n ? size_t(sorted[split] >> kBlockShift) << kBlockShift : np;
            for (size_t k = 0; k < 2; ++k) {  // room for every push of the halves (6 neighbours a cell)
                const size_t cells = k ? n - split : split;
                halves[k].found.reserve(6 * cells);
                halves[k].near.reserve(cells);
            }
            if (helper && split < n) {
                helper->for_chunks(2, 1, accept_half);
                helper->for_chunks(2, 1, gather_half);
            } else {
                accept_half(0, 0);
                accept_half(1, 0);
                gather_half(0, 0);
                gather_half(1, 0);
            }
            for (const Half& half : halves)
                for (const uint32_t p : half.near) resolve_if_lower(p);

            candidates.assign(halves[0].found.begin(), halves[0].found.end());
            candidates.insert(candidates.end(), halves[1].found.begin(), halves[1].found.end());
            const size_t nc = candidates.size();
            values.resize(nc);
            olds.resize(nc);
            queue_at.resize(nc);
            on_both(nc, kChunk, solve_candidates);
            on_both(nc, 4 * kChunk, lower_candidates);
            for (size_t i = 0; i < nc; ++i)
                if (queue_at[i] != kNoQueue) enqueue(candidates[i], queue_at[i]);
        }
        if (buckets[current].capacity()) spare.push_back(std::move(buckets[current]));
    }
}

}  // namespace

void fast_march(const Grid3& g, const std::vector<double>& slowness, std::vector<double>& u,
                const FastMarchingOptions& options) {
    const size_t n = g.count();
    require(slowness.size() == n && u.size() == n, "fast marching: arrays do not match the grid");
    const int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const int64_t px = nx + 2 * kPad, py = ny + 2 * kPad, pz = nz + 2 * kPad;
    const size_t np = size_t(px * py * pz);
    require(np < 0xFFFFFFFFu, "fast marching: too many cells");
    const int64_t stride[3] = {1, px, px * py};
    auto padded = [&](int64_t y, int64_t z) { return size_t(kPad + stride[1] * (y + kPad) + stride[2] * (z + kPad)); };

    // The padded copy, a z-plane at a time on both threads where there is
    // a helper (see march): the border impassable and never known, each
    // plane's least slowness and whether every slowness is > 0 kept apart.
    std::unique_ptr<HelperThread> helper;
    if (options.threads != 1 && np * sizeof(Cell) >= kHugePage) helper = std::make_unique<HelperThread>();
    CellArray cell(np);
    std::vector<double> plane_min(size_t(pz), kInf);
    std::vector<uint8_t> plane_positive(size_t(pz), 1);
    auto copy_in = [&](size_t begin, size_t end) {
        const Cell border{kInf, -kInf};
        for (size_t zp = begin; zp < end; ++zp) {
            Cell* plane = cell.data() + zp * size_t(stride[2]);
            const int64_t z = int64_t(zp) - kPad;
            if (z < 0 || z >= nz) {
                std::fill(plane, plane + stride[2], border);
                continue;
            }
            std::fill(plane, plane + kPad * stride[1], border);
            std::fill(plane + (kPad + ny) * stride[1], plane + stride[2], border);
            double f_min = kInf;
            bool positive = true;
            for (int64_t y = 0; y < ny; ++y) {
                const size_t c0 = size_t(nx * (y + ny * z)), p0 = padded(y, z);
                std::fill(&cell[p0 - kPad], &cell[p0], border);
                std::fill(&cell[p0 + nx], &cell[p0 + nx + kPad], border);
                for (int64_t x = 0; x < nx; ++x) {
                    const double s = slowness[c0 + x], v = u[c0 + x];
                    positive &= s > 0.0;
                    f_min = std::min(f_min, s);
                    const bool known = std::isfinite(v);
                    cell[p0 + x] = known ? Cell{v, -s} : Cell{kInf, std::isfinite(s) ? s : -kInf};
                }
            }
            plane_min[zp] = f_min;
            plane_positive[zp] = positive;
        }
    };
    if (helper) helper->for_chunks(size_t(pz), 4, copy_in);
    else copy_in(0, size_t(pz));
    const double f_min = *std::min_element(plane_min.begin(), plane_min.end());
    const bool positive = std::all_of(plane_positive.begin(), plane_positive.end(), [](uint8_t p) { return p != 0; });
    require(positive, "fast marching: slowness must be > 0 (+inf: impassable)");
    if (!std::isfinite(f_min)) return;  // every cell impassable

    // An untidy priority queue (Yatziv, Bartesaghi & Sapiro 2006; Dial's
    // buckets): trial cells sit in buckets of width delta by value and are
    // accepted bucket by bucket, first in first out.  An update adds at least
    // f h / sqrt(3) to the smallest known neighbour, so with delta <= f_min h
    // / sqrt(3) a cell cannot change the value of a cell of its own bucket
    // through its smallest neighbour; the result stays within first-order
    // accuracy of the heap-ordered method, in O(N) instead of O(N log N)
    // (3.6x faster at 128^3).  Second order can add less; its buckets are
    // half as wide, and a value that still falls below the bucket being
    // drained (the second-order stencil keeps it only above the smallest
    // neighbour) joins that bucket.
    const double delta = g.h * f_min / std::sqrt(3.0) * (options.second_order ? 0.5 : 1.0);
    if (options.second_order) march<true>(cell.data(), np, stride, g.h, delta, helper.get());
    else march<false>(cell.data(), np, stride, g.h, delta, helper.get());

    auto copy_out = [&](size_t begin, size_t end) {
        for (int64_t z = int64_t(begin); z < int64_t(end); ++z)
            for (int64_t y = 0; y < ny; ++y) {
                const size_t c0 = size_t(nx * (y + ny * z)), p0 = padded(y, z);
                for (int64_t x = 0; x < nx; ++x) u[c0 + x] = cell[p0 + x].u;
            }
    };
    if (helper) helper->for_chunks(size_t(nz), 4, copy_out);
    else copy_out(0, size_t(nz));
}

}  // namespace swarmcl

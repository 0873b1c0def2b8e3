// The nearest other point of every point of a frame of up to kSweepMax
// points (the metrics' d and η, eval/metrics.cpp), by a sweep along one axis:
// the points sorted on it, each scans outwards from itself until the axis gap
// alone exceeds the best squared distance found.  Exact, and the lowest index
// wins ties (as the brute force and the device's metrics).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace swarmcl {

// The scan grows as g^(2/3) a point, so larger frames use a kd-tree.
constexpr size_t kSweepMax = 2048;

class NearestSweep {
public:
    using Vec3 = std::array<double, 3>;

    // wide: eight candidates at a time where the CPU has AVX2, filtered in
    // float and confirmed in double (the same answers; false: one at a
    // time in double, the path of other CPUs).
    explicit NearestSweep(bool wide = true) : wide_(wide) {}

    // nn[i]: the nearest other point of p[i] (finite coordinates, at least
    // two points); hint (or null): a candidate per point, any index other
    // than the point's own.  Frames of one recording follow each other: the
    // last frame's order is re-sorted by insertion (nearly sorted already),
    // and a point's last neighbour (the hint) gives its scan a first bound.
    void find(const std::vector<Vec3>& p, const std::vector<uint32_t>* hint, std::vector<uint32_t>& nn);

private:
    static constexpr size_t kAxisEvery = 32;  // frames between choices of the axis
    static constexpr size_t kPad = 8;         // NaN entries past either end of the arrays

    // A point's coordinate on the axis and its index: what the sort moves.
    struct Entry {
        double key;
        uint32_t index;
    };

    static bool before(const Entry& a, const Entry& b) {
        return a.key < b.key || (a.key == b.key && a.index < b.index);
    }
    // The sorted arrays past their front pads, and the point count.
    struct Sorted {
        const double *x, *y, *z, *axis;
        const float *xf, *yf, *zf;
        const uint32_t* index;
        long count;
    };
    Sorted sorted() const;
    // Sorted point r's first bound: its hint's squared distance and index
    // (best infinite where it has none).
    static void first_bound(const Sorted& s, long r, const std::vector<Vec3>& p, const std::vector<uint32_t>* hint,
                            double& best, uint32_t& who);
    size_t widest_axis(const std::vector<Vec3>& p);
    void scan(const std::vector<Vec3>& p, const std::vector<uint32_t>* hint, std::vector<uint32_t>& nn) const;
#if defined(__x86_64__) && defined(__GNUC__)
    // extent: the frame's largest |coordinate|, which bounds float's rounding.
    void scan_avx2(const std::vector<Vec3>& p, const std::vector<uint32_t>* hint, double extent,
                   std::vector<uint32_t>& nn) const;
#endif

    std::vector<Entry> order_;
    // The points in axis order as coordinate arrays and indices, kPad
    // entries past either end (NaN coordinates: never nearer).
    std::array<std::vector<double>, 3> xyz_;
    // The same in float (the wide scan's filter, as xyz_).
    std::array<std::vector<float>, 3> xyz_f_;
    std::vector<uint32_t> index_;
    std::vector<double> coords_;
    size_t axis_ = 0;
    size_t frames_since_axis_ = 0;
    bool wide_ = true;
};

}  // namespace swarmcl

// The reference dataset D of FASTSWARM (§3, §4, §5.2.1): samples d = [v, a]
// from real tracks, subsampled to k, sorted by speed and divided into speed
// groups for the reduced search; saved in a small binary format
// (docs/energy-model.md, "Dataset files").
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "data/tracks.hpp"

namespace swarmcl {

struct DatasetOptions {
    uint32_t k = 300;       // samples kept (§5.2.1: "k = 300 is enough")
    uint32_t groups = 10;   // speed groups (equal counts, by increasing speed)
    uint64_t seed = 0;      // the subsampling draw
};

struct Dataset {
    std::vector<std::array<float, 3>> v;  // m/s, sorted by |v| (ties keep the draw order)
    std::vector<std::array<float, 3>> a;  // m/s^2, the same sample's acceleration
    std::vector<uint32_t> group_start;    // groups + 1 entries: group g is [start[g], start[g+1])
    double frame_time = 0.0;              // s, of the source data (0: unknown)

    uint32_t size() const { return uint32_t(v.size()); }
    uint32_t groups() const { return uint32_t(group_start.size()) - 1; }
    // Checks sizes, finiteness, speed order and the group table (Error(Parse)
    // with `what` in front: loaded files go through it).
    void validate(const std::string& what) const;
};

// Subsamples k of the samples (all when fewer: a seeded Fisher-Yates draw, so
// the joint distribution of v and a is kept), sorts by speed, splits into
// groups.  Error(InvalidArgument) for an empty input, k = 0, groups = 0 or
// groups > k, non-finite samples.
Dataset build_dataset(const Kinematics& samples, const DatasetOptions& options, double frame_time);

// Binary file (little-endian): "SWCLDSET", u32 version (1), u32 k, u32 groups,
// u32 0, f64 frame_time, k x (f32 vx vy vz ax ay az), (groups + 1) x u32 group
// starts, u64 FNV-1a of all bytes before it.  Written atomically.
void save_dataset(const Dataset& d, const std::string& path);
Dataset load_dataset(const std::string& path);
std::string dataset_to_bytes(const Dataset& d);
// Error(Parse) for anything that is not a valid file (wrong magic, version,
// sizes, checksum, values).
Dataset dataset_from_bytes(const std::string& bytes);

// A dataset from synthetic_tracks (tests, examples without data).
Dataset synthetic_dataset(const DatasetOptions& options, double frame_time = 0.01, float mean_speed = 0.5f);

}  // namespace swarmcl

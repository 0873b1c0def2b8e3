#include "data/dataset.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace swarmcl {
namespace {

constexpr char kMagic[8] = {'S', 'W', 'C', 'L', 'D', 'S', 'E', 'T'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kMaxSamples = 1u << 24;
constexpr size_t kHeaderBytes = 8 + 4 * 4 + 8;

uint64_t fnv1a(const char* data, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; ++i) {
        h ^= uint8_t(data[i]);
        h *= 1099511628211ull;
    }
    return h;
}

// Little-endian writers/readers (the format does not depend on the host).
template <typename T>
void put(std::string& out, T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if constexpr (sizeof(T) > 1) {
        const uint16_t probe = 1;
        if (*reinterpret_cast<const uint8_t*>(&probe) == 0) std::reverse(b, b + sizeof(T));
    }
    out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

template <typename T>
T get(const std::string& in, size_t& pos) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, in.data() + pos, sizeof(T));
    const uint16_t probe = 1;
    if (*reinterpret_cast<const uint8_t*>(&probe) == 0) std::reverse(b, b + sizeof(T));
    pos += sizeof(T);
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

float speed(const std::array<float, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

void Dataset::validate(const std::string& what) const {
    auto bad = [&](const std::string& m) { fail(Status::Parse, what + ": " + m); };
    if (v.empty()) bad("the dataset is empty");
    if (v.size() > kMaxSamples) bad("more than 2^24 samples");
    if (a.size() != v.size()) bad("velocity and acceleration counts differ");
    if (group_start.size() < 2 || group_start.size() - 1 > v.size()) bad("bad number of speed groups");
    if (group_start.front() != 0 || group_start.back() != v.size()) bad("the groups do not cover the samples");
    for (size_t g = 1; g < group_start.size(); ++g)
        if (group_start[g] <= group_start[g - 1]) bad("speed group " + std::to_string(g - 1) + " is empty");
    if (!std::isfinite(frame_time) || frame_time < 0.0) bad("bad frame time");
    for (size_t i = 0; i < v.size(); ++i) {
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[i][c]) || !std::isfinite(a[i][c]))
                bad("sample " + std::to_string(i) + " is not finite");
        if (i > 0 && speed(v[i]) < speed(v[i - 1])) bad("samples are not sorted by speed");
    }
}

Dataset build_dataset(const Kinematics& s, const DatasetOptions& o, double frame_time) {
    require(o.k > 0, "dataset: k must be > 0");
    require(o.k <= kMaxSamples, "dataset: k above 2^24");
    require(o.groups > 0, "dataset: groups must be > 0");
    require(!s.v.empty(), "dataset: no samples (the tracks gave no (v, a) pair)");
    require(s.v.size() == s.a.size(), "dataset: velocity and acceleration counts differ");
    for (size_t i = 0; i < s.v.size(); ++i)
        for (int c = 0; c < 3; ++c)
            require(std::isfinite(s.v[i][c]) && std::isfinite(s.a[i][c]),
                    "dataset: sample " + std::to_string(i) + " is not finite");
    const size_t n = s.v.size();
    const size_t k = std::min<size_t>(o.k, n);
    require(o.groups <= k, "dataset: " + std::to_string(o.groups) + " speed groups for " + std::to_string(k) +
                               " samples (groups must be <= samples)");
    // Seeded partial Fisher-Yates draw of k indices (mt19937_64's sequence is
    // fixed by the standard; the modulo bias is far below anything visible).
    std::vector<size_t> idx(n);
    std::iota(idx.begin(), idx.end(), size_t(0));
    std::mt19937_64 rng(o.seed);
    if (k < n)
        for (size_t i = 0; i < k; ++i) std::swap(idx[i], idx[i + size_t(rng() % (n - i))]);
    idx.resize(k);
    std::stable_sort(idx.begin(), idx.end(), [&](size_t x, size_t y) { return speed(s.v[x]) < speed(s.v[y]); });
    Dataset d;
    d.frame_time = frame_time;
    for (size_t i : idx) {
        d.v.push_back(s.v[i]);
        d.a.push_back(s.a[i]);
    }
    // Equal-count groups (§5.2.1 "divide the dataset into several groups").
    for (uint32_t g = 0; g <= o.groups; ++g) d.group_start.push_back(uint32_t(uint64_t(g) * k / o.groups));
    d.validate("dataset");
    return d;
}

std::string dataset_to_bytes(const Dataset& d) {
    d.validate("dataset");
    std::string out(kMagic, 8);
    put<uint32_t>(out, kVersion);
    put<uint32_t>(out, d.size());
    put<uint32_t>(out, d.groups());
    put<uint32_t>(out, 0);
    put<double>(out, d.frame_time);
    for (uint32_t i = 0; i < d.size(); ++i) {
        for (int c = 0; c < 3; ++c) put<float>(out, d.v[i][c]);
        for (int c = 0; c < 3; ++c) put<float>(out, d.a[i][c]);
    }
    for (uint32_t g : d.group_start) put<uint32_t>(out, g);
    put<uint64_t>(out, fnv1a(out.data(), out.size()));
    return out;
}

Dataset dataset_from_bytes(const std::string& in) {
    const std::string what = "dataset file";
    auto bad = [&](const std::string& m) { fail(Status::Parse, what + ": " + m); };
    if (in.size() < kHeaderBytes + 8 || std::memcmp(in.data(), kMagic, 8) != 0)
        bad("not a swarmcl dataset (no SWCLDSET header)");
    size_t pos = 8;
    const uint32_t version = get<uint32_t>(in, pos);
    if (version != kVersion) bad("version " + std::to_string(version) + " (this build reads version 1)");
    const uint32_t k = get<uint32_t>(in, pos), groups = get<uint32_t>(in, pos), reserved = get<uint32_t>(in, pos);
    if (k == 0 || k > kMaxSamples) bad("bad sample count " + std::to_string(k));
    if (groups == 0 || groups > k) bad("bad group count " + std::to_string(groups));
    if (reserved != 0) bad("reserved field is not 0");
    const uint64_t expected = kHeaderBytes + uint64_t(k) * 24 + (uint64_t(groups) + 1) * 4 + 8;
    if (in.size() != expected)
        bad("size " + std::to_string(in.size()) + " bytes, expected " + std::to_string(expected));
    size_t end = in.size() - 8;
    const uint64_t sum = get<uint64_t>(in, end);
    if (sum != fnv1a(in.data(), in.size() - 8)) bad("checksum mismatch (the file is damaged)");
    Dataset d;
    d.frame_time = get<double>(in, pos);
    d.v.resize(k);
    d.a.resize(k);
    for (uint32_t i = 0; i < k; ++i) {
        for (int c = 0; c < 3; ++c) d.v[i][c] = get<float>(in, pos);
        for (int c = 0; c < 3; ++c) d.a[i][c] = get<float>(in, pos);
    }
    d.group_start.resize(size_t(groups) + 1);
    for (auto& g : d.group_start) g = get<uint32_t>(in, pos);
    d.validate(what);
    return d;
}

void save_dataset(const Dataset& d, const std::string& path) {
    const std::string bytes = dataset_to_bytes(d);
    AtomicFile f(path);
    f.write(bytes);
    f.commit();
}

Dataset load_dataset(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(Status::Io, "dataset: cannot open \"" + path + "\"");
    std::ostringstream s;
    s << f.rdbuf();
    if (f.bad()) fail(Status::Io, "dataset: cannot read \"" + path + "\"");
    try {
        return dataset_from_bytes(s.str());
    } catch (const Error& e) {
        fail(e.status(), path + ": " + e.what());
    }
}

Dataset synthetic_dataset(const DatasetOptions& options, double frame_time, float mean_speed) {
    const uint32_t per_track = 64;
    const uint32_t tracks = std::max<uint32_t>(4, (options.k + per_track - 3) / (per_track - 2) * 2);
    const TrackSet set = synthetic_tracks(tracks, per_track, frame_time, mean_speed, options.seed);
    return build_dataset(track_kinematics(set), options, frame_time);
}

}  // namespace swarmcl

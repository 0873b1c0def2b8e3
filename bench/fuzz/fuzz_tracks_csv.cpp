// Track CSV files (host/data/tracks.cpp), then what the loader's caller does
// with them: forward differences.  The first byte picks the load options, so
// every time format, delimiter and the smoothing are reached; the second the
// unit and gap factor.
#include <cmath>
#include <cstdlib>

#include "data/tracks.hpp"
#include "fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 2) return 0;
    const uint8_t mode = data[0], scale = data[1];
    swarmcl::TrackLoadOptions o;
    static const swarmcl::TimeFormat formats[4] = {swarmcl::TimeFormat::Auto, swarmcl::TimeFormat::Seconds,
                                                   swarmcl::TimeFormat::Frame, swarmcl::TimeFormat::DateTime};
    o.time_format = formats[mode & 3];
    o.frame_time = (mode & 4) ? 0.01 : (o.time_format == swarmcl::TimeFormat::Frame ? 0.02 : 0.0);
    static const char delimiters[4] = {',', ';', '\t', ' '};
    o.delimiter = delimiters[(mode >> 3) & 3];
    o.smoothing = (mode >> 5) & 3;
    if (mode & 0x80) o.columns = {"0", "1", "2", "3", "4"};  // by index instead of by header name
    // The second byte: the unit and the gap factor.
    static const double units[4] = {1.0, 0.01, 1000.0, 1e300};
    static const double gaps[4] = {1.5, 1.0, 3.0, 1e300};
    o.unit_scale = units[scale & 3];
    o.gap_factor = gaps[(scale >> 2) & 3];
    return swarmcl::fuzz::expect_error_or_value([&] {
        const swarmcl::TrackSet set = swarmcl::parse_tracks_csv(swarmcl::fuzz::bytes_of(data + 2, size - 2), o);
        // What a returned set promises (tracks.hpp): segments of >= 3 finite
        // samples at increasing times, a frame time > 0.
        if (set.tracks.empty() || !(set.frame_time > 0.0)) std::abort();
        for (const swarmcl::Track& t : set.tracks) {
            if (t.t.size() < 3 || t.p.size() != t.t.size()) std::abort();
            for (size_t k = 0; k < t.t.size(); ++k) {
                if (!std::isfinite(t.t[k]) || (k > 0 && !(t.t[k] > t.t[k - 1]))) std::abort();
                for (double v : t.p[k])
                    if (!std::isfinite(v)) std::abort();
            }
        }
        swarmcl::track_kinematics(set);
    });
}

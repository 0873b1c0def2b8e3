// Real 3D insect tracks (FASTSWARM §3, data processing stage): a CSV loader
// with configurable columns, splitting where frames are missing, optional
// smoothing, and velocity / acceleration by forward differencing.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace swarmcl {

// Which column holds what: a header name, or a 0-based index written in
// digits ("3") when no header column has that name.
struct TrackColumns {
    std::string id = "id";
    std::string time = "time";
    std::string x = "x", y = "y", z = "z";
};

enum class TimeFormat {
    Auto,      // a number: seconds; otherwise "YYYY-MM-DD HH:MM:SS[.ffffff]"
    Seconds,   // a number of seconds
    Frame,     // an integer frame number; seconds = frame * frame_time
    DateTime,  // "YYYY-MM-DD HH:MM:SS[.ffffff]" (or 'T' between date and time)
};

struct TrackLoadOptions {
    TrackColumns columns;
    TimeFormat time_format = TimeFormat::Auto;
    double frame_time = 0.0;   // s; 0: the median step of the data (required > 0 for Frame)
    double unit_scale = 1.0;   // position unit in metres (0.01 for centimetres)
    double gap_factor = 1.5;   // a step above gap_factor * frame_time splits the track
    uint32_t smoothing = 0;    // half-width of a centred moving average of positions; 0: none
    char delimiter = ',';
};

// One gap-free segment of a track: times (s) and positions (m).
struct Track {
    std::string id;  // the source track id (segments of one track share it)
    std::vector<double> t;
    std::vector<std::array<double, 3>> p;
};

struct TrackSet {
    std::vector<Track> tracks;  // segments of >= 3 samples
    double frame_time = 0.0;    // s
    uint64_t rows = 0;          // data rows read
    uint64_t dropped_segments = 0;  // segments shorter than 3 samples after splitting
};

// Forward differences (§3): v_k = (p_{k+1} - p_k) / (t_{k+1} - t_k),
// a_k = (v_{k+1} - v_k) / (t_{k+1} - t_k), in m/s and m/s^2; a segment of n
// samples gives n - 2 (v, a) pairs.
struct Kinematics {
    std::vector<std::array<float, 3>> v, a;
};

// Parses CSV text (the first line is the header).  Error(Parse) names the
// line and column of a bad value (a NaN or non-number position, a bad time,
// a missing field), Error(InvalidArgument) an unknown column or bad option;
// no segment of 3 samples or more: Error(InvalidArgument).
TrackSet parse_tracks_csv(const std::string& text, const TrackLoadOptions& options);
TrackSet load_tracks_csv(const std::string& path, const TrackLoadOptions& options);

// Tracks given as arrays: track k has counts[k] samples, times t (s) and
// packed xyz positions (in units of unit_scale); samples are consecutive over
// the tracks.  Each track must have >= 3 finite samples with increasing
// times; it is then split and smoothed as a CSV track would be.
TrackSet tracks_from_arrays(const uint32_t* counts, size_t track_count, const double* t, const float* xyz,
                            const TrackLoadOptions& options);

// Forward differences over every segment (smoothing is applied on loading).
Kinematics track_kinematics(const TrackSet& tracks);

// Centred moving average of positions with half-width h (shrinking at the
// ends of the segment).
void smooth_track(Track& track, uint32_t h);

// Deterministic synthetic tracks for tests: `count` tracks of `samples`
// samples at frame_time, velocity an Ornstein-Uhlenbeck process (speed about
// mean_speed m/s, relaxing over 0.2 s) pulled towards the origin.
TrackSet synthetic_tracks(uint32_t count, uint32_t samples, double frame_time, float mean_speed, uint64_t seed);

// CSV text of a track set (header id,time,x,y,z; positions in metres).
std::string tracks_to_csv(const TrackSet& tracks);

}  // namespace swarmcl

#include "data/tracks.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>

#include "core/error.hpp"
#include "core/philox.hpp"

namespace swarmcl {
namespace {

[[noreturn]] void bad_cell(uint64_t line, size_t column, const std::string& name, const std::string& what) {
    fail(Status::Parse, "line " + std::to_string(line) + ", column " + std::to_string(column + 1) + " (" + name +
                            "): " + what);
}

std::vector<std::string> split(const std::string& line, char delimiter) {
    std::vector<std::string> out;
    std::string cell;
    for (char c : line) {
        if (c == delimiter) {
            out.push_back(cell);
            cell.clear();
        } else {
            cell.push_back(c);
        }
    }
    out.push_back(cell);
    for (auto& s : out) {  // trim blanks
        const auto b = s.find_first_not_of(" \t");
        const auto e = s.find_last_not_of(" \t");
        s = b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
    }
    return out;
}

size_t column_index(const std::vector<std::string>& header, const std::string& spec, const char* role) {
    for (size_t i = 0; i < header.size(); ++i)
        if (header[i] == spec) return i;
    const bool digits = !spec.empty() && spec.size() < 9 &&
                        std::all_of(spec.begin(), spec.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) {
        const size_t i = std::stoul(spec);
        if (i < header.size()) return i;
    }
    std::string names;
    for (const auto& h : header) names += (names.empty() ? "" : ", ") + h;
    fail(Status::InvalidArgument, std::string("tracks: unknown ") + role + " column \"" + spec +
                                      "\" (the header has: " + names + "; or give a 0-based index)");
}

bool parse_number(const std::string& s, double& out) {
    if (s.empty()) return false;
    errno = 0;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && errno != ERANGE;
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's algorithm).
int64_t days_from_civil(int64_t y, unsigned m, unsigned d) {
    y -= m <= 2;
    const int64_t era = (y >= 0 ? y : y - 399) / 400;
    const unsigned yoe = unsigned(y - era * 400);
    const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + int64_t(doe) - 719468;
}

// "YYYY-MM-DD HH:MM:SS[.fff...]" -> seconds since 1970 (UTC, no zone).
bool parse_datetime(const std::string& s, double& out) {
    auto num = [&](size_t pos, size_t len, int& v) {
        if (pos + len > s.size()) return false;
        v = 0;
        for (size_t i = pos; i < pos + len; ++i) {
            if (s[i] < '0' || s[i] > '9') return false;
            v = v * 10 + (s[i] - '0');
        }
        return true;
    };
    int Y, M, D, h, m, sec;
    if (s.size() < 19 || !num(0, 4, Y) || s[4] != '-' || !num(5, 2, M) || s[7] != '-' || !num(8, 2, D) ||
        (s[10] != ' ' && s[10] != 'T') || !num(11, 2, h) || s[13] != ':' || !num(14, 2, m) || s[16] != ':' ||
        !num(17, 2, sec))
        return false;
    if (M < 1 || M > 12 || D < 1 || D > 31 || h > 23 || m > 59 || sec > 60) return false;
    double frac = 0.0;
    if (s.size() > 19) {
        if (s[19] != '.' || s.size() == 20 || s.size() > 32) return false;
        double scale = 0.1;
        for (size_t i = 20; i < s.size(); ++i, scale *= 0.1) {
            if (s[i] < '0' || s[i] > '9') return false;
            frac += (s[i] - '0') * scale;
        }
    }
    out = double(days_from_civil(Y, unsigned(M), unsigned(D))) * 86400.0 + h * 3600.0 + m * 60.0 + sec + frac;
    return true;
}

void check_options(const TrackLoadOptions& o) {
    require(std::isfinite(o.unit_scale) && o.unit_scale > 0.0, "tracks: unit_scale must be a finite number > 0");
    require(std::isfinite(o.frame_time) && o.frame_time >= 0.0, "tracks: frame_time must be >= 0 (0: estimate)");
    require(o.time_format != TimeFormat::Frame || o.frame_time > 0.0,
            "tracks: time format \"frame\" needs frame_time > 0");
    require(std::isfinite(o.gap_factor) && o.gap_factor >= 1.0, "tracks: gap_factor must be >= 1");
    require(o.smoothing <= 1000, "tracks: smoothing half-width above 1000");
    require(o.delimiter != '\n' && o.delimiter != '\r' && o.delimiter != '\0', "tracks: bad delimiter");
}

// Raw samples of one source track, in input order.
struct RawTrack {
    std::string id;
    std::vector<double> t;
    std::vector<std::array<double, 3>> p;
};

double median_step(const std::vector<RawTrack>& raw) {
    std::vector<double> steps;
    for (const auto& r : raw)
        for (size_t k = 1; k < r.t.size(); ++k)
            if (r.t[k] > r.t[k - 1]) steps.push_back(r.t[k] - r.t[k - 1]);
    if (steps.empty()) return 0.0;
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    return steps[steps.size() / 2];
}

// Sorts each track by time (stable), splits at gaps and repeated times,
// smooths, keeps segments of >= 3 samples.
TrackSet segment(std::vector<RawTrack> raw, const TrackLoadOptions& o, uint64_t rows) {
    TrackSet out;
    out.rows = rows;
    out.frame_time = o.frame_time > 0.0 ? o.frame_time : median_step(raw);
    require(out.frame_time > 0.0, "tracks: cannot estimate the frame time (no track has two samples at "
                                  "increasing times); give frame_time");
    const double gap = o.gap_factor * out.frame_time * (1.0 + 1e-9);
    for (auto& r : raw) {
        std::vector<size_t> order(r.t.size());
        std::iota(order.begin(), order.end(), size_t(0));
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return r.t[a] < r.t[b]; });
        Track cur;
        auto flush = [&] {
            if (cur.t.size() >= 3) {
                smooth_track(cur, o.smoothing);
                out.tracks.push_back(std::move(cur));
            } else if (!cur.t.empty()) {
                ++out.dropped_segments;
            }
            cur = Track();
            cur.id = r.id;
        };
        cur.id = r.id;
        for (size_t k : order) {
            if (!cur.t.empty()) {
                const double dt = r.t[k] - cur.t.back();
                if (!(dt > 0.0) || dt > gap) flush();  // a missing frame or a repeated time
            }
            cur.t.push_back(r.t[k]);
            cur.p.push_back(r.p[k]);
        }
        flush();
    }
    if (out.tracks.empty())
        fail(Status::InvalidArgument, "tracks: no gap-free segment of 3 samples or more (" +
                                          std::to_string(out.dropped_segments) + " shorter segments)");
    return out;
}

}  // namespace

void smooth_track(Track& track, uint32_t h) {
    if (h == 0) return;
    const auto src = track.p;
    const int64_t n = int64_t(src.size());
    for (int64_t k = 0; k < n; ++k) {
        // Symmetric window that shrinks at the ends so the end points stay put
        // (no bias towards the inside of the segment).
        const int64_t w = std::min<int64_t>({int64_t(h), k, n - 1 - k});
        std::array<double, 3> s{0, 0, 0};
        for (int64_t j = k - w; j <= k + w; ++j)
            for (int a = 0; a < 3; ++a) s[a] += src[size_t(j)][a];
        for (int a = 0; a < 3; ++a) {
            double mean = s[a] / double(2 * w + 1);
            if (!std::isfinite(mean)) {
                // The sum overflowed (finite positions near 1e308; fuzzing
                // finding): sum the samples scaled by 2^-11 (exact), and keep
                // the mean inside the window's range, where a mean lies.
                double scaled = 0.0, lo = src[size_t(k)][a], hi = lo;
                for (int64_t j = k - w; j <= k + w; ++j) {
                    scaled += std::ldexp(src[size_t(j)][a], -11);
                    lo = std::min(lo, src[size_t(j)][a]);
                    hi = std::max(hi, src[size_t(j)][a]);
                }
                mean = std::ldexp(scaled / double(2 * w + 1), 11);
                mean = std::isnan(mean) ? lo : std::clamp(mean, lo, hi);
            }
            track.p[size_t(k)][a] = mean;
        }
    }
}

TrackSet parse_tracks_csv(const std::string& text, const TrackLoadOptions& o) {
    check_options(o);
    std::istringstream in(text);
    std::string line;
    uint64_t line_no = 0;
    std::vector<std::string> header;
    while (header.empty() && std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") != std::string::npos) header = split(line, o.delimiter);
    }
    if (header.empty()) fail(Status::Parse, "tracks: no header line");
    const size_t ci = column_index(header, o.columns.id, "track id");
    const size_t ct = column_index(header, o.columns.time, "time");
    const size_t cx = column_index(header, o.columns.x, "x");
    const size_t cy = column_index(header, o.columns.y, "y");
    const size_t cz = column_index(header, o.columns.z, "z");
    const size_t needed = std::max({ci, ct, cx, cy, cz}) + 1;

    std::vector<RawTrack> raw;
    std::map<std::string, size_t> index_of;
    uint64_t rows = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos) continue;
        const auto cells = split(line, o.delimiter);
        if (cells.size() < needed)
            fail(Status::Parse, "line " + std::to_string(line_no) + ": " + std::to_string(cells.size()) +
                                    " fields, the columns need " + std::to_string(needed));
        const std::string& id = cells[ci];
        if (id.empty()) bad_cell(line_no, ci, header[ci], "empty track id");
        double t = 0.0;
        const std::string& ts = cells[ct];
        bool ok = false;
        switch (o.time_format) {
            case TimeFormat::Seconds: ok = parse_number(ts, t); break;
            case TimeFormat::Frame:
                ok = parse_number(ts, t) && t == std::floor(t) && std::fabs(t) < 9e15;
                t *= o.frame_time;
                break;
            case TimeFormat::DateTime: ok = parse_datetime(ts, t); break;
            case TimeFormat::Auto: ok = parse_number(ts, t) || parse_datetime(ts, t); break;
        }
        if (!ok || !std::isfinite(t)) bad_cell(line_no, ct, header[ct], "bad time \"" + ts.substr(0, 40) + "\"");
        std::array<double, 3> p{};
        const size_t cols[3] = {cx, cy, cz};
        for (int a = 0; a < 3; ++a) {
            double v;
            if (!parse_number(cells[cols[a]], v) || !std::isfinite(v))
                bad_cell(line_no, cols[a], header[cols[a]],
                         "expected a finite number, got \"" + cells[cols[a]].substr(0, 40) + "\"");
            p[a] = v * o.unit_scale;
            if (!std::isfinite(p[a]))  // a finite number times unit_scale (fuzzing finding)
                bad_cell(line_no, cols[a], header[cols[a]],
                         "\"" + cells[cols[a]].substr(0, 40) + "\" times unit_scale is not a finite number");
        }
        auto [it, added] = index_of.emplace(id, raw.size());
        if (added) raw.push_back(RawTrack{id, {}, {}});
        raw[it->second].t.push_back(t);
        raw[it->second].p.push_back(p);
        ++rows;
    }
    if (rows == 0) fail(Status::InvalidArgument, "tracks: no data rows");
    return segment(std::move(raw), o, rows);
}

TrackSet load_tracks_csv(const std::string& path, const TrackLoadOptions& options) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(Status::Io, "tracks: cannot open \"" + path + "\"");
    std::ostringstream s;
    s << f.rdbuf();
    if (f.bad()) fail(Status::Io, "tracks: cannot read \"" + path + "\"");
    try {
        return parse_tracks_csv(s.str(), options);
    } catch (const Error& e) {
        fail(e.status(), path + ": " + e.what());
    }
}

TrackSet tracks_from_arrays(const uint32_t* counts, size_t track_count, const double* t, const float* xyz,
                            const TrackLoadOptions& o) {
    check_options(o);
    require(track_count > 0, "tracks: no tracks given (track_count is 0)");
    require(counts != nullptr, "tracks: counts is NULL");
    uint64_t total = 0;
    for (size_t k = 0; k < track_count; ++k) {
        if (counts[k] < 3)
            fail(Status::InvalidArgument, "tracks: track " + std::to_string(k) + " has " +
                                              std::to_string(counts[k]) + " samples (3 or more needed)");
        total += counts[k];
    }
    require(total <= (uint64_t(1) << 32), "tracks: more than 2^32 samples");
    require(t != nullptr && xyz != nullptr, "tracks: times or positions are NULL");
    std::vector<RawTrack> raw(track_count);
    uint64_t s = 0;
    for (size_t k = 0; k < track_count; ++k) {
        raw[k].id = std::to_string(k);
        for (uint32_t i = 0; i < counts[k]; ++i, ++s) {
            const std::string where = "tracks: track " + std::to_string(k) + ", sample " + std::to_string(i);
            if (!std::isfinite(t[s])) fail(Status::InvalidArgument, where + ": time is not finite");
            if (i > 0 && !(t[s] > t[s - 1])) fail(Status::InvalidArgument, where + ": times must increase");
            std::array<double, 3> p{};
            for (int a = 0; a < 3; ++a) {
                if (!std::isfinite(xyz[3 * s + a]))
                    fail(Status::InvalidArgument, where + ": position is not finite (NaN or Inf)");
                p[a] = double(xyz[3 * s + a]) * o.unit_scale;
                if (!std::isfinite(p[a]))
                    fail(Status::InvalidArgument, where + ": position times unit_scale is not finite");
            }
            raw[k].t.push_back(t[s]);
            raw[k].p.push_back(p);
        }
    }
    return segment(std::move(raw), o, total);
}

Kinematics track_kinematics(const TrackSet& tracks) {
    Kinematics out;
    for (const Track& tr : tracks.tracks) {
        const size_t n = tr.t.size();
        if (n < 3) continue;
        std::vector<std::array<double, 3>> v(n - 1);
        for (size_t k = 0; k + 1 < n; ++k)
            for (int a = 0; a < 3; ++a) v[k][a] = (tr.p[k + 1][a] - tr.p[k][a]) / (tr.t[k + 1] - tr.t[k]);
        for (size_t k = 0; k + 2 < n; ++k) {
            std::array<float, 3> vf, af;
            for (int a = 0; a < 3; ++a) {
                vf[a] = float(v[k][a]);
                af[a] = float((v[k + 1][a] - v[k][a]) / (tr.t[k + 1] - tr.t[k]));
            }
            out.v.push_back(vf);
            out.a.push_back(af);
        }
    }
    return out;
}

TrackSet synthetic_tracks(uint32_t count, uint32_t samples, double frame_time, float mean_speed, uint64_t seed) {
    require(count > 0 && samples >= 3, "synthetic tracks: need count > 0 and samples >= 3");
    require(frame_time > 0.0 && std::isfinite(frame_time), "synthetic tracks: frame_time must be > 0");
    require(mean_speed > 0.0f && std::isfinite(mean_speed), "synthetic tracks: mean_speed must be > 0");
    TrackSet set;
    set.frame_time = frame_time;
    const double tau = 0.2;                      // velocity relaxation time, s
    const double sigma = mean_speed * 0.8;       // velocity fluctuation, m/s
    auto gauss = [&](uint32_t track, uint32_t k, uint32_t stream) {
        const auto r = philox_for(seed, track, k, stream);
        // Box-Muller on two uniforms in (0, 1].
        const double u1 = (double(r[0] >> 8) + 1.0) / 16777216.0, u2 = double(r[1] >> 8) / 16777216.0;
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
    };
    for (uint32_t i = 0; i < count; ++i) {
        Track tr;
        tr.id = "s" + std::to_string(i);
        std::array<double, 3> p{0.2 * gauss(i, 0, 0), 0.2 * gauss(i, 0, 1), 0.2 * gauss(i, 0, 2)};
        std::array<double, 3> v{mean_speed * gauss(i, 0, 3), mean_speed * gauss(i, 0, 4), 0.3 * gauss(i, 0, 5)};
        for (uint32_t k = 0; k < samples; ++k) {
            tr.t.push_back(k * frame_time);
            tr.p.push_back(p);
            for (int a = 0; a < 3; ++a) {
                // Ornstein-Uhlenbeck velocity plus a weak pull to the origin.
                v[a] += (-v[a] / tau - 2.0 * p[a]) * frame_time +
                        sigma * std::sqrt(2.0 * frame_time / tau) * gauss(i, k + 1, uint32_t(a));
                p[a] += v[a] * frame_time;
            }
        }
        set.tracks.push_back(std::move(tr));
        set.rows += samples;
    }
    return set;
}

std::string tracks_to_csv(const TrackSet& tracks) {
    std::ostringstream out;
    out.precision(17);
    out << "id,time,x,y,z\n";
    for (const Track& tr : tracks.tracks)
        for (size_t k = 0; k < tr.t.size(); ++k)
            out << tr.id << ',' << tr.t[k] << ',' << tr.p[k][0] << ',' << tr.p[k][1] << ',' << tr.p[k][2] << '\n';
    return out.str();
}

}  // namespace swarmcl

// Helpers the benchmarks share: robust summaries of repeated timings, the
// machine's load (to tell a noisy machine from a slow one) and JSON output.
#pragma once
#include <algorithm>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace swarmcl::bench {

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline double minimum(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

// The 1-minute load average (Linux); -1 when unknown.
inline double load_average() {
    std::ifstream f("/proc/loadavg");
    double l = -1;
    if (f) f >> l;
    return l;
}

inline std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

inline std::string json_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '"' || c == '\\') o += '\\';
        if (static_cast<unsigned char>(c) < 0x20) continue;
        o += c;
    }
    return o;
}

inline std::string json_array(const std::vector<double>& v, double scale) {
    std::ostringstream s;
    s.precision(6);
    s << '[';
    for (size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i] * scale;
    s << ']';
    return s.str();
}

}  // namespace swarmcl::bench

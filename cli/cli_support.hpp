// What the swarmcl program's commands share: their two kinds of failure,
// handles owned by a scope, and small file and argument helpers.
#pragma once
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <swarmcl/swarmcl.h>

// The library's atomic file writer, compiled into this program (CMakeLists.txt):
// the C API has no call for writing a text file.
#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace swarmcl_cli {

// A failed C call: message on stderr, exit status 1.
struct Failure {
    std::string message;
};
// A malformed command line: message and usage on stderr, exit status 2.
struct Usage {
    std::string message;
};

// Destroys a handle when the scope ends, also when a Failure unwinds it: a
// recorder destroyed unfinished removes what it wrote.
template <typename H, swcl_status (*Destroy)(H)>
struct Owned {
    H handle{};
    ~Owned() {
        if (handle.id) Destroy(handle);
    }
};

inline void check(swcl_status status, const char* what) {
    if (status != SWCL_OK)
        throw Failure{std::string(what) + ": " + swcl_status_string(status) + ": " + swcl_last_error()};
}

// A C call's swcl_last_error() without the function name it begins with
// ("swcl_export_formats_parse: unknown ..." -> "unknown ...").
inline std::string without_function_name(const std::string& error) {
    const size_t colon = error.find(": ");
    return error.rfind("swcl_", 0) == 0 && colon != std::string::npos ? error.substr(colon + 2) : error;
}

inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline uint32_t parse_count(const char* flag, const char* text, uint32_t min) {
    char* end = nullptr;
    errno = 0;
    const unsigned long v = std::strtoul(text, &end, 10);
    if (!*text || *end || errno || v < min || v > 0xFFFFFFFFul || text[0] == '-')
        throw Usage{std::string(flag) + ": expected an integer >= " + std::to_string(min) + ", got '" + text + "'"};
    return uint32_t(v);
}

// The names of a mask's export formats as the library's table gives them
// (swcl_export_format_name), lowest bit first; Failure for a bit no format has.
inline std::vector<std::string> export_format_names(uint32_t mask) {
    std::vector<std::string> names;
    for (uint32_t bit = 1; bit != 0; bit <<= 1) {
        if (!(mask & bit)) continue;
        const char* name = swcl_export_format_name(bit);
        if (!name) throw Failure{"export formats: no format has the bit " + std::to_string(bit)};
        names.emplace_back(name);
    }
    return names;
}

// Writes text to path through a temporary file and a rename (host/io/atomic_file).
inline void write_atomically(const std::string& path, const std::string& text) {
    try {
        swarmcl::AtomicFile file(path);
        file.write(text);
        file.commit();
    } catch (const swarmcl::Error&) {
        throw Failure{"cannot write '" + path + "'"};
    }
}

// A progress bar on stderr (only when `show`: stderr is a terminal).
inline void progress(bool show, uint32_t done, uint32_t total, double seconds) {
    if (!show) return;
    const int width = 30;
    const int filled = total ? int(double(done) / total * width) : width;
    std::fprintf(stderr, "\r[%.*s%.*s] %3d%% %u/%u steps  %.1f steps/s", filled, "##############################",
                 width - filled, "..............................", total ? int(100.0 * done / total) : 100, done, total,
                 seconds > 0 ? done / seconds : 0.0);
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace swarmcl_cli

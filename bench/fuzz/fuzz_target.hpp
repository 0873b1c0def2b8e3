// What every fuzz target shares (bench/fuzz/README in docs/reliability.md,
// "Fuzzing").  A target hands the input to one parser of outside bytes; the
// parser's contract is to return or throw swarmcl::Error (a status and a
// message), so Error is caught and anything else (another exception, a
// crash, a sanitizer report) is a finding.  The same sources are linked into
// the replay test (bench/fuzz/replay_main.cpp) of the normal build.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"

namespace swarmcl::fuzz {

inline std::string bytes_of(const uint8_t* data, size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `parse`, swallowing the one exception type a bad file may raise.
template <typename F>
int expect_error_or_value(F&& parse) {
    try {
        parse();
    } catch (const swarmcl::Error&) {
    }
    return 0;
}

}  // namespace swarmcl::fuzz

// Linked into every test executable.  Some tests switch a kernel variant with
// setenv (SWARMCL_NOISE_WIDTH, SWARMCL_POLICY_LANES, SWARMCL_DEVICE*) while
// PoCL's worker threads, from earlier launches, call getenv.  Adding a
// variable that was not there reallocates glibc's environment array under
// those readers (a crash seen once under ASan); replacing the value of one
// that exists only swaps a pointer.  So every such variable exists from
// before main, empty when the caller had not set it (the library reads an
// empty value as unset), and tests "unset" one by setting it to "".
#include <cstdlib>
#include <initializer_list>

namespace {
struct EnvPrelude {
    EnvPrelude() {
        for (const char* name : {"SWARMCL_NOISE_WIDTH", "SWARMCL_POLICY_LANES", "SWARMCL_DEVICE",
                                 "SWARMCL_DEVICE_PROFILE"})
            if (!std::getenv(name)) setenv(name, "", 1);
    }
} const prelude;
}  // namespace

// The reference dataset's binary file (host/data/dataset.cpp).  The file ends
// in an FNV-1a checksum of everything before it; when the first input byte is
// odd the target rewrites that checksum to match, so mutations of the body
// reach the field checks instead of all stopping at the checksum.
#include <cstdlib>
#include <cstring>

#include "data/dataset.hpp"
#include "fuzz_target.hpp"

namespace {
// 64-bit FNV-1a, as the dataset file uses (docs/energy-model.md, "Dataset files").
uint64_t fnv1a(const char* p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ uint8_t(p[i])) * 1099511628211ull;
    return h;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    std::string bytes = swarmcl::fuzz::bytes_of(data + 1, size - 1);
    if ((data[0] & 1) && bytes.size() >= 8) {
        const uint64_t h = fnv1a(bytes.data(), bytes.size() - 8);
        for (int i = 0; i < 8; ++i) bytes[bytes.size() - 8 + i] = char(uint8_t(h >> (8 * i)));
    }
    return swarmcl::fuzz::expect_error_or_value([&] {
        const swarmcl::Dataset d = swarmcl::dataset_from_bytes(bytes);
        // A file that loads is exactly what the writer makes of its dataset.
        if (swarmcl::dataset_to_bytes(d) != bytes) std::abort();
    });
}

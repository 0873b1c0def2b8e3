// Swarm checkpoints (swcl_swarm_load): the container (host/io/checkpoint.cpp)
// and the decode of its sections, model descriptors and datasets included
// (host/models/swarm_checkpoint.cpp, model_checkpoint.cpp).  What needs a
// device (building the swarm, the model's state section) is not reached.
// The first input byte: odd verifies the CRC-32 as a real load does; even
// skips it so that mutations reach the section parsers.  A container that
// parses must also write back to the same bytes.
#include <cstdlib>

#include "fuzz_target.hpp"
#include "io/checkpoint.hpp"
#include "models/swarm_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const bool verify = data[0] & 1;
    const std::string bytes = swarmcl::fuzz::bytes_of(data + 1, size - 1);
    swarmcl::fuzz::expect_error_or_value([&] {
        // A container that parses is what the writer makes of its sections
        // (up to the CRC-32 when it is not verified).
        const std::string again = swarmcl::checkpoint_to_bytes(swarmcl::parse_checkpoint(bytes, verify));
        if (again.size() != bytes.size() || again.compare(0, again.size() - 4, bytes, 0, bytes.size() - 4) != 0 ||
            (verify && again != bytes))
            std::abort();
    });
    return swarmcl::fuzz::expect_error_or_value([&] { swarmcl::decode_swarm_checkpoint(bytes, verify); });
}

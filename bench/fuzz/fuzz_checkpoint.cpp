// Swarm checkpoints (swcl_swarm_load): the container (host/io/checkpoint.cpp)
// and the decode of its sections, model descriptors and datasets included
// (host/models/swarm_checkpoint.cpp, model_checkpoint.cpp).  What needs a
// device (building the swarm, the model's state section) is not reached.
// The first input byte: odd verifies the CRC-32 as a real load does; even
// skips it so that mutations reach the section parsers.
#include "fuzz_target.hpp"
#include "models/swarm_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const bool verify = data[0] & 1;
    return swarmcl::fuzz::expect_error_or_value(
        [&] { swarmcl::decode_swarm_checkpoint(swarmcl::fuzz::bytes_of(data + 1, size - 1), verify); });
}

// The CLI's run checkpoints (cli/run_checkpoint.cpp, read by `swarmcl
// resume`): checkpoint.json and the frames file.  First input byte: 0..127
// the JSON; otherwise the frames file, its CRC-32 verified when odd.
#include "../../cli/run_checkpoint.hpp"
#include "fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string bytes = swarmcl::fuzz::bytes_of(data + 1, size - 1);
    return swarmcl::fuzz::expect_error_or_value([&] {
        if (data[0] < 128) {
            swarmcl::cli::parse_run_checkpoint(bytes, "checkpoint.json");
        } else {
            uint32_t agents = 0;
            swarmcl::cli::frames_from_bytes(bytes, "fuzz.frames", agents, data[0] & 1);
        }
    });
}

// Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as 1, 2, 3",
// SC 2011) on the host, bit-identical to kernels/philox.cl, so host-side
// random choices (initial placement) are keyed like the device's:
// counter = (agent id, step, stream, 0), key = seed.
#pragma once
#include <array>
#include <cstdint>

namespace swarmcl {

inline std::array<uint32_t, 4> philox4x32_10(std::array<uint32_t, 4> ctr, std::array<uint32_t, 2> key) {
    constexpr uint32_t kM0 = 0xD2511F53u, kM1 = 0xCD9E8D57u;
    constexpr uint32_t kW0 = 0x9E3779B9u, kW1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const uint64_t p0 = uint64_t(kM0) * ctr[0];
        const uint64_t p1 = uint64_t(kM1) * ctr[2];
        ctr = {uint32_t(p1 >> 32) ^ ctr[1] ^ key[0], uint32_t(p1), uint32_t(p0 >> 32) ^ ctr[3] ^ key[1],
               uint32_t(p0)};
        key = {key[0] + kW0, key[1] + kW1};
    }
    return ctr;
}

// Uniform float in [0, 1) from the top 24 bits.
inline float uniform01(uint32_t bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

inline std::array<uint32_t, 4> philox_for(uint64_t seed, uint32_t agent, uint32_t step, uint32_t stream) {
    return philox4x32_10({agent, step, stream, 0u}, {uint32_t(seed), uint32_t(seed >> 32)});
}

}  // namespace swarmcl

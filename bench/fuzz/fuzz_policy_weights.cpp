// Policy weights (safetensors, host/rl/policy_weights.cpp): the 8-byte header
// length, the JSON header, the tensors' dtypes, shapes and offsets, the
// swarmcl.* metadata.  A file that parses must keep the contract the policy
// kernel relies on (docs/rl-swarm.md, "Policy model"): 1..8 chained layers
// from obs_dim to 4 actions, widths <= 512, every value finite, obs_std > 0.
#include <cmath>
#include <cstdlib>

#include "fuzz_target.hpp"
#include "rl/policy_weights.hpp"

namespace {
bool finite(const std::vector<float>& v) {
    for (float x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

void check_contract(const swarmcl::PolicyWeights& w) {
    using namespace swarmcl;
    if (w.obs_dim != (w.efs ? 54u : 51u)) std::abort();
    if (w.layers.empty() || w.layers.size() > kPolicyMaxLayers) std::abort();
    uint32_t in = w.obs_dim;
    for (const PolicyLayer& L : w.layers) {
        if (L.in != in || L.out == 0 || L.out > kPolicyMaxWidth) std::abort();
        if (L.weight.size() != size_t(L.in) * L.out || L.bias.size() != L.out) std::abort();
        if (!finite(L.weight) || !finite(L.bias)) std::abort();
        in = L.out;
    }
    if (in != kPolicyActions) std::abort();
    if (w.obs_mean.size() != w.obs_std.size()) std::abort();
    if (!w.obs_mean.empty() && w.obs_mean.size() != w.obs_dim) std::abort();
    if (!finite(w.obs_mean)) std::abort();
    for (float s : w.obs_std)
        if (!(s > 0.0f) || !std::isfinite(s)) std::abort();
    for (float s : w.action_scale)
        if (!std::isfinite(s)) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return swarmcl::fuzz::expect_error_or_value(
        [&] { check_contract(swarmcl::parse_policy_weights(data, size)); });
}

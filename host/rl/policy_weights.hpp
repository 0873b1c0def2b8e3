// A trained policy (actor MLP) in the safetensors file of the policy weights
// contract (docs/rl-swarm.md, "Policy model"; paper §IV-A, Fig. 6): tensors
// layers.{i}.weight [out, in] / layers.{i}.bias [out] (F32), optional
// obs_mean / obs_std [obs_dim], and __metadata__ with swarmcl.format
// "policy-mlp/1", swarmcl.activations, swarmcl.action_scale, swarmcl.efs.
//
// The reader checks every length, offset and shape before it allocates or
// copies anything, and names the problem (Error(Parse)); it is pure host code
// over bytes, so it can be fuzzed (parse_policy_weights).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace swarmcl {

enum class PolicyActivation : uint32_t { Relu = 0, Linear = 1, Tanh = 2 };

struct PolicyLayer {
    uint32_t in = 0, out = 0;
    PolicyActivation activation = PolicyActivation::Linear;
    std::vector<float> weight;  // out x in, row-major
    std::vector<float> bias;    // out
};

struct PolicyWeights {
    bool efs = true;
    uint32_t obs_dim = 54;  // 54 with EFS, 51 without (Eq. 11-13)
    std::vector<PolicyLayer> layers;
    std::vector<float> obs_mean, obs_std;  // both empty or both obs_dim long
    std::array<float, 4> action_scale{{1.0f, 1.0f, 1.0f, 1.0f}};
    std::string env_json, trained_by;  // provenance, as given (may be empty)
};

// Limits of the contract: 1 <= L <= 8 layers, widths <= 512, 4 actions.
constexpr uint32_t kPolicyMaxLayers = 8;
constexpr uint32_t kPolicyMaxWidth = 512;
constexpr uint32_t kPolicyActions = 4;
// A header longer than this is refused before it is read (ours are < 4 KiB).
constexpr uint64_t kPolicyMaxHeader = 1u << 20;

// Parses a whole file's bytes.  Error(Parse) naming the problem: truncated
// file, header length beyond the file, header not JSON, a tensor with a dtype
// other than F32 or offsets outside the data, wrong layer shapes,
// non-contiguous layers, missing or bad metadata, non-finite values.
PolicyWeights parse_policy_weights(const uint8_t* data, size_t size);
// Reads `path` (Error(Io) when it cannot be read) and parses it; messages
// start with the path.
PolicyWeights load_policy_weights(const std::string& path);
// The file's bytes (Error(Io)); kept by the policy model for checkpoints.
std::string read_policy_file(const std::string& path);

const char* activation_name(PolicyActivation a);

}  // namespace swarmcl

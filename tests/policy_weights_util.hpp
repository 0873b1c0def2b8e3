// Writing policy weight files in the tests (the contract of
// docs/rl-swarm.md, "Policy model"): a safetensors file built by hand, so
// each test can break one thing.
#pragma once
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace swarmcl::test {

struct TensorSpec {
    std::string dtype = "F32";
    std::vector<uint64_t> shape;
    std::vector<float> data;
};

inline std::string safetensors_bytes(const std::map<std::string, TensorSpec>& tensors,
                                     const std::map<std::string, std::string>& meta) {
    nlohmann::json h = nlohmann::json::object();
    std::string body;
    for (const auto& [name, t] : tensors) {
        const uint64_t begin = body.size();
        body.append(reinterpret_cast<const char*>(t.data.data()), t.data.size() * 4);
        h[name] = {{"dtype", t.dtype}, {"shape", t.shape}, {"data_offsets", {begin, uint64_t(body.size())}}};
    }
    if (!meta.empty()) h["__metadata__"] = meta;
    std::string head = h.dump();
    std::string out(8, '\0');
    for (int i = 0; i < 8; ++i) out[size_t(i)] = char((uint64_t(head.size()) >> (8 * i)) & 0xFF);
    return out + head + body;
}

// A random MLP obs_dim -> widths... -> 4 with the contract's metadata.
struct MlpFile {
    std::map<std::string, TensorSpec> tensors;
    std::map<std::string, std::string> meta;
    std::string bytes() const { return safetensors_bytes(tensors, meta); }
};

inline MlpFile random_mlp(std::vector<uint64_t> widths, const std::string& activations, uint32_t seed,
                          bool efs = true, bool norm = false) {
    MlpFile f;
    std::mt19937 rng(seed);
    uint64_t in = efs ? 54 : 51;
    for (size_t i = 0; i < widths.size(); ++i) {
        std::normal_distribution<float> g(0.0f, 1.0f / std::sqrt(float(in)));
        TensorSpec w{"F32", {widths[i], in}, {}}, b{"F32", {widths[i]}, {}};
        for (uint64_t k = 0; k < widths[i] * in; ++k) w.data.push_back(g(rng));
        for (uint64_t k = 0; k < widths[i]; ++k) b.data.push_back(0.1f * g(rng));
        f.tensors["layers." + std::to_string(i) + ".weight"] = w;
        f.tensors["layers." + std::to_string(i) + ".bias"] = b;
        in = widths[i];
    }
    if (norm) {
        const uint64_t d = efs ? 54 : 51;
        TensorSpec m{"F32", {d}, {}}, s{"F32", {d}, {}};
        std::uniform_real_distribution<float> u(0.5f, 3.0f);
        for (uint64_t k = 0; k < d; ++k) {
            m.data.push_back(u(rng) - 1.5f);
            s.data.push_back(u(rng));
        }
        f.tensors["obs_mean"] = m;
        f.tensors["obs_std"] = s;
    }
    f.meta = {{"swarmcl.format", "policy-mlp/1"},
              {"swarmcl.activations", activations},
              {"swarmcl.action_scale", "0.1,0.0699,0.0699,0.0699"},
              {"swarmcl.efs", efs ? "1" : "0"}};
    return f;
}

// The paper's actor shape (§IV-A, Fig. 6): 54 -> 128 -> 256 -> 64 -> 4.
inline MlpFile paper_mlp(uint32_t seed, bool norm = true) {
    return random_mlp({128, 256, 64, 4}, "relu,relu,linear,tanh", seed, true, norm);
}

}  // namespace swarmcl::test

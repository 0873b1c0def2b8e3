#include "rl/policy_weights.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

[[noreturn]] void bad(const std::string& what) { fail(Status::Parse, "policy weights: " + what); }

uint64_t read_u64le(const uint8_t* p) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

// A tensor entry as checked against the data: shape and where its bytes are.
struct Tensor {
    std::vector<uint64_t> shape;
    uint64_t begin = 0, end = 0;
};

std::string shape_text(const std::vector<uint64_t>& s) {
    std::string t = "[";
    for (size_t i = 0; i < s.size(); ++i) t += (i ? ", " : "") + std::to_string(s[i]);
    return t + "]";
}

// One entry of the header: dtype F32, a shape of at most 2 dims each at most
// kPolicyMaxWidth (no tensor of the contract is larger), offsets inside the
// data whose length is 4 * the element count.
Tensor read_entry(const std::string& name, const json& e, uint64_t data_size) {
    if (!e.is_object()) bad("tensor '" + name + "': header entry is not an object");
    for (const char* k : {"dtype", "shape", "data_offsets"})
        if (!e.contains(k)) bad("tensor '" + name + "': header entry has no \"" + k + "\"");
    const json& dt = e["dtype"];
    if (!dt.is_string()) bad("tensor '" + name + "': dtype is not a string");
    if (dt.get<std::string>() != "F32")
        bad("tensor '" + name + "': dtype " + dt.get<std::string>() + ", expected F32 (float32)");
    const json& sh = e["shape"];
    if (!sh.is_array() || sh.size() > 2) bad("tensor '" + name + "': shape must be an array of 1 or 2 sizes");
    Tensor t;
    uint64_t count = 1;
    for (const json& d : sh) {
        if (!d.is_number_unsigned()) bad("tensor '" + name + "': shape entries must be non-negative integers");
        const uint64_t v = d.get<uint64_t>();
        if (v > kPolicyMaxWidth)
            bad("tensor '" + name + "': dimension " + std::to_string(v) + " exceeds the largest width " +
                std::to_string(kPolicyMaxWidth));
        t.shape.push_back(v);
        count *= v;  // <= 512^2: no overflow
    }
    const json& off = e["data_offsets"];
    if (!off.is_array() || off.size() != 2 || !off[0].is_number_unsigned() || !off[1].is_number_unsigned())
        bad("tensor '" + name + "': data_offsets must be [begin, end] (non-negative integers)");
    t.begin = off[0].get<uint64_t>();
    t.end = off[1].get<uint64_t>();
    if (t.begin > t.end) bad("tensor '" + name + "': data_offsets begin > end");
    if (t.end > data_size)
        bad("tensor '" + name + "': data_offsets end " + std::to_string(t.end) + " is beyond the " +
            std::to_string(data_size) + " data bytes (file truncated?)");
    if (t.end - t.begin != 4 * count)
        bad("tensor '" + name + "': " + std::to_string(t.end - t.begin) + " bytes for shape " + shape_text(t.shape) +
            " (expected " + std::to_string(4 * count) + ")");
    return t;
}

std::vector<float> floats(const std::string& name, const Tensor& t, const uint8_t* data) {
    std::vector<float> v(size_t((t.end - t.begin) / 4));
    for (size_t i = 0; i < v.size(); ++i) {
        const uint8_t* p = data + t.begin + 4 * i;
        const uint32_t bits = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
        std::memcpy(&v[i], &bits, 4);
        if (!std::isfinite(v[i])) bad("tensor '" + name + "': element " + std::to_string(i) + " is not finite");
    }
    return v;
}

const std::string& meta(const std::map<std::string, std::string>& m, const char* key) {
    auto it = m.find(key);
    if (it == m.end()) bad(std::string("__metadata__ has no \"") + key + "\"");
    return it->second;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else if (c != ' ') {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

// "layers.{i}.weight" / "layers.{i}.bias": i (decimal, no sign or leading
// zeros) and which; false for any other name.
bool layer_name(const std::string& name, uint32_t* index, bool* weight) {
    const std::string pre = "layers.";
    if (name.compare(0, pre.size(), pre) != 0) return false;
    size_t p = pre.size(), q = p;
    while (q < name.size() && name[q] >= '0' && name[q] <= '9') ++q;
    if (q == p || q - p > 3 || (name[p] == '0' && q - p > 1)) return false;
    const std::string rest = name.substr(q);
    if (rest != ".weight" && rest != ".bias") return false;
    *index = uint32_t(std::stoul(name.substr(p, q - p)));
    *weight = rest == ".weight";
    return true;
}

}  // namespace

const char* activation_name(PolicyActivation a) {
    switch (a) {
        case PolicyActivation::Relu: return "relu";
        case PolicyActivation::Linear: return "linear";
        case PolicyActivation::Tanh: return "tanh";
    }
    return "?";
}

PolicyWeights parse_policy_weights(const uint8_t* data, size_t size) {
    if (size < 8) bad("file truncated: " + std::to_string(size) + " bytes, shorter than the 8-byte header length");
    const uint64_t n = read_u64le(data);
    if (n > kPolicyMaxHeader)
        bad("header length " + std::to_string(n) + " exceeds the limit of " + std::to_string(kPolicyMaxHeader) +
            " bytes (corrupt header?)");
    if (n > size - 8)
        bad("header length " + std::to_string(n) + " is beyond the end of the file (" + std::to_string(size) +
            " bytes; truncated?)");
    json h;
    try {
        h = json::parse(data + 8, data + 8 + n);
    } catch (const json::exception& e) {
        bad(std::string("header is not valid JSON: ") + e.what());
    }
    if (!h.is_object()) bad("header is not a JSON object");
    const uint8_t* body = data + 8 + n;
    const uint64_t body_size = size - 8 - n;

    std::map<std::string, std::string> md;
    std::map<uint32_t, std::pair<const json*, const json*>> layers;  // index -> (weight, bias)
    const json* mean = nullptr;
    const json* stdev = nullptr;
    for (auto it = h.begin(); it != h.end(); ++it) {
        const std::string& key = it.key();
        if (key == "__metadata__") {
            if (!it->is_object()) bad("__metadata__ is not an object");
            for (auto m = it->begin(); m != it->end(); ++m) {
                if (!m->is_string()) bad("__metadata__ value of \"" + m.key() + "\" is not a string");
                md[m.key()] = m->get<std::string>();
            }
            continue;
        }
        uint32_t i = 0;
        bool weight = false;
        if (layer_name(key, &i, &weight)) {
            if (i >= kPolicyMaxLayers)
                bad("tensor '" + key + "': at most " + std::to_string(kPolicyMaxLayers) + " layers");
            (weight ? layers[i].first : layers[i].second) = &*it;
        } else if (key == "obs_mean") {
            mean = &*it;
        } else if (key == "obs_std") {
            stdev = &*it;
        } else {
            bad("unexpected tensor '" + key + "' (expected layers.{i}.weight/bias, obs_mean, obs_std)");
        }
    }

    PolicyWeights w;
    const std::string& format = meta(md, "swarmcl.format");
    if (format != "policy-mlp/1") bad("swarmcl.format is \"" + format + "\", expected \"policy-mlp/1\"");
    const std::string& efs = meta(md, "swarmcl.efs");
    if (efs != "1" && efs != "0") bad("swarmcl.efs is \"" + efs + "\", expected \"1\" or \"0\"");
    w.efs = efs == "1";
    w.obs_dim = w.efs ? 54u : 51u;
    if (md.count("swarmcl.env")) w.env_json = md["swarmcl.env"];
    if (md.count("swarmcl.trained_by")) w.trained_by = md["swarmcl.trained_by"];

    const std::vector<std::string> scale = split(meta(md, "swarmcl.action_scale"));
    if (scale.size() != kPolicyActions) bad("swarmcl.action_scale must hold 4 comma-separated numbers");
    for (size_t k = 0; k < 4; ++k) {
        std::istringstream in(scale[k]);
        in.imbue(std::locale::classic());
        float v = 0.0f;
        if (!(in >> v) || !in.eof() || !std::isfinite(v))
            bad("swarmcl.action_scale entry " + std::to_string(k) + " (\"" + scale[k] + "\") is not a finite number");
        w.action_scale[k] = v;
    }

    if (layers.empty()) bad("no layers.0.weight / layers.0.bias tensors");
    const uint32_t count = uint32_t(layers.size());
    if (layers.rbegin()->first + 1 != count)
        bad("layers are not contiguous: layers.0 .. layers." + std::to_string(layers.rbegin()->first) + " with " +
            std::to_string(count) + " present");
    const std::vector<std::string> acts = split(meta(md, "swarmcl.activations"));
    if (acts.size() != count)
        bad("swarmcl.activations names " + std::to_string(acts.size()) + " activations for " +
            std::to_string(count) + " layers");
    uint32_t in = w.obs_dim;
    for (uint32_t i = 0; i < count; ++i) {
        const std::string wn = "layers." + std::to_string(i) + ".weight", bn = "layers." + std::to_string(i) + ".bias";
        if (!layers[i].first) bad("tensor '" + wn + "' is missing");
        if (!layers[i].second) bad("tensor '" + bn + "' is missing");
        const Tensor tw = read_entry(wn, *layers[i].first, body_size);
        const Tensor tb = read_entry(bn, *layers[i].second, body_size);
        if (tw.shape.size() != 2 || tw.shape[1] != in || tw.shape[0] == 0)
            bad("tensor '" + wn + "' has shape " + shape_text(tw.shape) + ", expected [out, " + std::to_string(in) +
                "]" +
                (i == 0 ? std::string(" (the first layer takes the observation: ") + std::to_string(in) +
                              " entries, as swarmcl.efs is \"" + efs + "\"; 54 with EFS, 51 without)"
                        : std::string(" (in = the previous layer's out)")));
        const uint64_t out = tw.shape[0];
        if (i + 1 == count && out != kPolicyActions)
            bad("tensor '" + wn + "' has shape " + shape_text(tw.shape) + ", expected [" +
                std::to_string(kPolicyActions) + ", " + std::to_string(in) + "]: the last layer must have " +
                std::to_string(kPolicyActions) + " outputs (the actions), it has " + std::to_string(out));
        if (tb.shape.size() != 1 || tb.shape[0] != out)
            bad("tensor '" + bn + "' has shape " + shape_text(tb.shape) + ", expected [" + std::to_string(out) + "]");
        PolicyLayer L;
        L.in = in;
        L.out = uint32_t(out);
        const std::string& a = acts[i];
        if (a == "relu") L.activation = PolicyActivation::Relu;
        else if (a == "linear") L.activation = PolicyActivation::Linear;
        else if (a == "tanh") L.activation = PolicyActivation::Tanh;
        else bad("swarmcl.activations entry " + std::to_string(i) + " is \"" + a + "\" (relu, linear or tanh)");
        L.weight = floats(wn, tw, body);
        L.bias = floats(bn, tb, body);
        w.layers.push_back(std::move(L));
        in = uint32_t(out);
    }
    if (bool(mean) != bool(stdev)) bad("obs_mean and obs_std must be given together");
    if (mean) {
        const Tensor tm = read_entry("obs_mean", *mean, body_size), ts = read_entry("obs_std", *stdev, body_size);
        for (const auto* t : {&tm, &ts})
            if (t->shape.size() != 1 || t->shape[0] != w.obs_dim)
                bad(std::string(t == &tm ? "obs_mean" : "obs_std") + " has shape " + shape_text(t->shape) +
                    ", expected [" + std::to_string(w.obs_dim) + "]");
        w.obs_mean = floats("obs_mean", tm, body);
        w.obs_std = floats("obs_std", ts, body);
        for (size_t k = 0; k < w.obs_std.size(); ++k)
            if (!(w.obs_std[k] > 0.0f)) bad("obs_std element " + std::to_string(k) + " is not > 0");
    }
    return w;
}

std::string read_policy_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) fail(Status::Io, "policy weights: cannot open '" + path + "'");
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) fail(Status::Io, "policy weights: cannot read '" + path + "'");
    return bytes;
}

PolicyWeights load_policy_weights(const std::string& path) {
    const std::string bytes = read_policy_file(path);
    try {
        return parse_policy_weights(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    } catch (const Error& e) {
        fail(e.status(), path + ": " + e.what());
    }
}

}  // namespace swarmcl

// Reading one JSON object of a scenario file (nlohmann-json): typed getters
// that name the key path in their errors (Error(Parse), "model.noise.scale:
// expected a number > 0"), and a check that no unknown key is left over.
// Shared by the scenario section readers of every model (host/scenario/).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace swarmcl {

[[noreturn]] inline void bad_json(const std::string& path, const std::string& what) {
    fail(Status::Parse, path + ": " + what);
}

class JsonObject {
public:
    using json = nlohmann::json;

    // `skip`: keys another reader of the same object handles (not unknown).
    JsonObject(const json& j, std::string path, std::set<std::string> skip = {})
        : j_(j), path_(std::move(path)), seen_(std::move(skip)) {
        if (!j_.is_object()) bad_json(label(), "expected an object");
    }

    bool has(const std::string& key) {
        seen_.insert(key);
        return j_.contains(key);
    }
    std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

    double number(const std::string& key, double def, double lo, double hi, const char* range) {
        if (!has(key)) return def;
        const json& v = j_[key];
        if (!v.is_number()) bad_json(at(key), std::string("expected a number ") + range);
        const double x = v.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi) bad_json(at(key), std::string("expected a number ") + range);
        return x;
    }
    float positive(const std::string& key, float def) {
        const double x = number(key, def, 0.0, std::numeric_limits<float>::max(), "> 0");
        // > 0 as a float too: 1e-320 is a positive double but 0 as a float.
        if (!(float(x) > 0.0f)) bad_json(at(key), "expected a number > 0");
        return float(x);
    }
    float non_negative(const std::string& key, float def) {
        return float(number(key, def, 0.0, std::numeric_limits<float>::max(), ">= 0"));
    }
    uint64_t integer(const std::string& key, uint64_t def, uint64_t hi) { return integer(key, def, 0, hi); }
    uint64_t integer(const std::string& key, uint64_t def, uint64_t lo, uint64_t hi) {
        if (!has(key)) return def;
        const json& v = j_[key];
        if (!v.is_number_integer() || (!v.is_number_unsigned() && v.get<int64_t>() < 0) ||
            v.get<uint64_t>() < lo || v.get<uint64_t>() > hi)
            bad_json(at(key), "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return v.get<uint64_t>();
    }
    bool boolean(const std::string& key, bool def) {
        if (!has(key)) return def;
        if (!j_[key].is_boolean()) bad_json(at(key), "expected true or false");
        return j_[key].get<bool>();
    }
    std::string string(const std::string& key, const std::string& def) {
        if (!has(key)) return def;
        if (!j_[key].is_string()) bad_json(at(key), "expected a string");
        return j_[key].get<std::string>();
    }
    std::array<float, 3> vec3(const std::string& key, std::array<float, 3> def) {
        if (!has(key)) return def;
        return to_vec3(j_[key], at(key));
    }
    std::array<float, 3> required_vec3(const std::string& key) {
        require_key(key);
        return vec3(key, {});
    }
    const json& child(const std::string& key) {
        seen_.insert(key);
        return j_[key];
    }
    // Reports a key not in `keys` as unknown before any value is read, so a
    // typo of a required key says "unknown key", not "missing".
    void allow(std::initializer_list<const char*> keys) const {
        for (auto it = j_.begin(); it != j_.end(); ++it) {
            bool known = false;
            for (const char* k : keys) known = known || it.key() == k;
            if (!known) bad_json(at(it.key()), "unknown key");
        }
    }
    void require_key(const std::string& key) {
        if (!has(key)) bad_json(at(key), "missing");
    }
    // Unknown keys: a typo must not be silently ignored.
    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!seen_.count(it.key())) bad_json(at(it.key()), "unknown key");
    }
    std::string label() const { return path_.empty() ? "(top level)" : path_; }

    static std::array<float, 3> to_vec3(const json& v, const std::string& path) {
        if (!v.is_array() || v.size() != 3) bad_json(path, "expected an array of 3 numbers");
        std::array<float, 3> out{};
        for (int a = 0; a < 3; ++a) {
            // Finite as a float too: 1e39 is a finite double but inf as a float.
            if (!v[a].is_number() || !std::isfinite(v[a].get<double>()) ||
                std::fabs(v[a].get<double>()) > std::numeric_limits<float>::max())
                bad_json(path, "expected an array of 3 finite numbers");
            out[a] = float(v[a].get<double>());
        }
        return out;
    }

private:
    const json& j_;
    std::string path_;
    std::set<std::string> seen_;
};

}  // namespace swarmcl

#include "params/param_table.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "core/error.hpp"
#include "io/json_object.hpp"
#include "params/world_params.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

// The shortest text that reads back as the same float ("0.4", "1e+30").
std::string number_text(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    // Integers as integers ("4294967295", not "4.2949673e+09").
    if (v == std::floor(v) && std::fabs(v) < 1e15) return std::to_string(int64_t(v));
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
}

// The shortest decimal that reads back as the float f, as a double (0.4,
// not 0.4000000059604645), for JSON and the docs.
double shortest(float f) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, f);
    return std::strtod(std::string(buf, r.ptr).c_str(), nullptr);
}

std::string upper_name(const std::string& key) {
    std::string out;
    for (char ch : key) out += ch == '.' ? '_' : char(std::toupper(static_cast<unsigned char>(ch)));
    return out;
}

bool is_integer(ParamType t) { return t == ParamType::UInt32 || t == ParamType::UInt64 || t == ParamType::UInt3; }

double integer_hi(const Param& p) {
    if (std::isfinite(p.hi)) return p.hi;
    return p.type == ParamType::UInt64 ? 18446744073709551615.0 : 4294967295.0;
}

}  // namespace

const char* param_type_name(ParamType t) {
    switch (t) {
        case ParamType::Float: return "float";
        case ParamType::UInt32: return "uint32";
        case ParamType::UInt64: return "uint64";
        case ParamType::Bool: return "bool";
        case ParamType::Vec3: return "vec3";
        case ParamType::Enum: return "enum";
        case ParamType::UInt3: return "uint3";
        case ParamType::Double: return "float";
    }
    return "?";
}

std::string Param::range_text() const {
    if (type == ParamType::Bool) return "true | false";
    if (type == ParamType::Enum) {
        std::string s;
        for (const auto& n : enum_names) s += (s.empty() ? "" : " | ") + n;
        return s;
    }
    if (is_integer(type)) {
        const std::string hi_text = type == ParamType::UInt64 && !std::isfinite(hi) ? "2^64 - 1" : number_text(integer_hi(*this));
        return "[" + number_text(std::isfinite(lo) ? lo : 0.0) + ", " + hi_text + "]";
    }
    return std::string(lo_open || std::isinf(lo) ? "(" : "[") + number_text(lo) + ", " + number_text(hi) +
           (std::isinf(hi) ? ")" : "]");
}

std::string Param::expectation() const {
    switch (type) {
        case ParamType::Bool: return "true or false";
        case ParamType::Enum: {
            std::string s = "one of ";
            for (size_t i = 0; i < enum_names.size(); ++i) s += (i ? ", \"" : "\"") + enum_names[i] + "\"";
            return s;
        }
        case ParamType::UInt32:
        case ParamType::UInt64: {
            const std::string hi_text = type == ParamType::UInt64 && !std::isfinite(hi) ? "18446744073709551615"
                                                                                       : number_text(integer_hi(*this));
            return "an integer in [" + number_text(std::isfinite(lo) ? lo : 0.0) + ", " + hi_text + "]";
        }
        case ParamType::UInt3:
            return "an integer in [" + number_text(lo) + ", " + number_text(integer_hi(*this)) + "] or 3 of them";
        case ParamType::Vec3:
        case ParamType::Double:
        case ParamType::Float: {
            const std::string what = type == ParamType::Vec3 ? "an array of 3 " : "a ";
            const std::string noun = type == ParamType::Vec3 ? "numbers" : "number";
            std::string r;
            if (std::isinf(lo) && std::isinf(hi)) return what + "finite " + noun;
            if (std::isinf(hi)) r = (lo_open ? "> " : ">= ") + number_text(lo);
            else if (std::isinf(lo)) r = "<= " + number_text(hi);
            else r = "in " + range_text();
            return what + noun + " " + r;
        }
    }
    return "?";
}

double Param::get(void* config, int a) const {
    void* p = field(config);
    switch (type) {
        case ParamType::Float: return *static_cast<float*>(p);
        case ParamType::Double: return *static_cast<double*>(p);
        case ParamType::UInt32: return *static_cast<uint32_t*>(p);
        case ParamType::UInt64: return double(*static_cast<uint64_t*>(p));
        case ParamType::Bool: return *static_cast<bool*>(p) ? 1.0 : 0.0;
        case ParamType::Vec3: return static_cast<float*>(p)[a];
        case ParamType::UInt3: return static_cast<uint32_t*>(p)[a];
        case ParamType::Enum: {
            int32_t v;
            std::memcpy(&v, p, sizeof v);
            return v;
        }
    }
    return 0.0;
}

void Param::set(void* config, double v, int a) const {
    void* p = field(config);
    switch (type) {
        case ParamType::Float: *static_cast<float*>(p) = float(v); break;
        case ParamType::Double: *static_cast<double*>(p) = v; break;
        case ParamType::UInt32: *static_cast<uint32_t*>(p) = uint32_t(v); break;
        case ParamType::UInt64: *static_cast<uint64_t*>(p) = uint64_t(v); break;
        case ParamType::Bool: *static_cast<bool*>(p) = v != 0.0; break;
        case ParamType::Vec3: static_cast<float*>(p)[a] = float(v); break;
        case ParamType::UInt3: static_cast<uint32_t*>(p)[a] = uint32_t(v); break;
        case ParamType::Enum: {
            const int32_t x = int32_t(v);
            std::memcpy(p, &x, sizeof x);
            break;
        }
    }
}

bool Param::valid(double v) const {
    if (!std::isfinite(v)) return false;
    switch (type) {
        case ParamType::Bool: return v == 0.0 || v == 1.0;
        case ParamType::Enum: return v >= 0 && v < double(enum_names.size()) && v == std::floor(v);
        case ParamType::UInt32:
        case ParamType::UInt64:
        case ParamType::UInt3:
            return v == std::floor(v) && v >= (std::isfinite(lo) ? lo : 0.0) && v <= integer_hi(*this);
        case ParamType::Float:
        case ParamType::Double:
        case ParamType::Vec3: {
            if (std::fabs(v) > double(std::numeric_limits<float>::max())) return false;
            const float f = float(v);
            if (lo_open ? !(v > lo && double(f) > lo) : !(v >= lo)) return false;
            return v <= hi;
        }
    }
    return false;
}

ParamTable::ParamTable(std::string model, std::string config_type)
    : model_(std::move(model)), config_type_(std::move(config_type)) {}

const Param* ParamTable::find(const std::string& key) const {
    for (const Param& p : params_)
        if (p.key == key) return &p;
    return nullptr;
}

Param& ParamTable::row(const std::string& key) {
    for (Param& p : params_)
        if (p.key == key) return p;
    fail(Status::Internal, model_ + " parameter table has no row " + key);
}

const Param* ParamTable::find_c_field(const std::string& c_field) const {
    for (const Param& p : params_)
        if (p.c_field == c_field) return &p;
    return nullptr;
}

std::string ParamTable::key_list() const {
    std::string s;
    for (const Param& p : params_)
        if (p.in_scenario) s += (s.empty() ? "" : ", ") + p.key;
    return s;
}

void ParamTable::finish_layout(void* defaults) {
    device_floats_ = 0;
    for (Param& p : params_) {
        for (int a = 0; a < p.components(); ++a) p.def[a] = p.get(defaults, a);
        if (p.device >= 0) {
            if (p.type == ParamType::UInt64) fail(Status::Internal, model_ + " parameter " + p.key + ": 64-bit integers are host only");
            p.device = int(device_floats_);
            device_floats_ += uint32_t(p.components());
        }
    }
}

void ParamTable::validate(void* config, const std::string& prefix) const {
    for (const Param& p : params_) {
        if (p.key.compare(0, prefix.size(), prefix) != 0) continue;
        if (p.type == ParamType::UInt64 && !std::isfinite(p.hi)) continue;  // every value is valid (seeds)
        for (int a = 0; a < p.components(); ++a) {
            const double v = p.get(config, a);
            if (p.valid(v)) continue;
            std::string name = p.c_field;
            if (p.components() > 1) name += "[" + std::to_string(a) + "]";
            const bool is_float = p.type == ParamType::Float || p.type == ParamType::Vec3 || p.type == ParamType::Double;
            const std::string value = is_float && std::isfinite(v) ? number_text(shortest(float(v))) : number_text(v);
            fail(Status::InvalidArgument, model_ + " model " + name + " = " + value + " is outside " +
                                              p.range_text() + (p.unit.empty() ? "" : " (" + p.unit + ")"));
        }
    }
}

void ParamTable::read_json(const json& model, const std::string& path, void* config,
                           const std::set<std::string>& handled) const {
    read_object(model, path, "", config, handled);
}

void ParamTable::read_object(const json& j, const std::string& path, const std::string& prefix, void* config,
                             const std::set<std::string>& handled) const {
    if (!j.is_object()) bad_json(path, "expected an object");
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string full = prefix + it.key();
        const std::string at = path + "." + it.key();
        if (handled.count(full)) continue;
        const json& v = it.value();
        const Param* p = find(full);
        if (p && p->in_scenario) {
            const auto bad = [&]() { bad_json(at, "expected " + p->expectation()); };
            switch (p->type) {
                case ParamType::Bool:
                    if (!v.is_boolean()) bad();
                    p->set(config, v.get<bool>() ? 1.0 : 0.0);
                    break;
                case ParamType::Enum: {
                    if (!v.is_string()) bad();
                    bool found = false;
                    for (size_t i = 0; i < p->enum_names.size() && !found; ++i)
                        if (p->enum_names[i] == v.get<std::string>()) p->set(config, double(i)), found = true;
                    if (!found) bad();
                    break;
                }
                case ParamType::UInt64:
                    // A finite hi bounds it (keyframe_period); else every value (seeds).
                    if (!v.is_number_unsigned() || (std::isfinite(p->hi) && double(v.get<uint64_t>()) > p->hi)) bad();
                    *static_cast<uint64_t*>(p->field(config)) = v.get<uint64_t>();
                    break;
                case ParamType::UInt32:
                    if (!v.is_number_integer() || (!v.is_number_unsigned() && v.get<int64_t>() < 0) ||
                        !p->valid(double(v.get<uint64_t>())))
                        bad();
                    p->set(config, double(v.get<uint64_t>()));
                    break;
                case ParamType::UInt3: {
                    // One integer for all three axes, or three.
                    if (v.is_number_integer()) {
                        const double x = double(v.get<int64_t>());
                        if (!p->valid(x)) bad();
                        for (int a = 0; a < 3; ++a) p->set(config, x, a);
                    } else {
                        if (!v.is_array() || v.size() != 3) bad();
                        for (int a = 0; a < 3; ++a)
                            if (!v[a].is_number() || !p->valid(v[a].get<double>())) bad();
                        for (int a = 0; a < 3; ++a) p->set(config, v[a].get<double>(), a);
                    }
                    break;
                }
                case ParamType::Vec3: {
                    const auto x = JsonObject::to_vec3(v, at);  // 3 finite numbers as floats
                    for (int a = 0; a < 3; ++a)
                        if (!p->valid(x[a])) bad();
                    for (int a = 0; a < 3; ++a) p->set(config, x[a], a);
                    break;
                }
                case ParamType::Float:
                    if (!v.is_number() || !p->valid(v.get<double>())) bad();
                    p->set(config, v.get<double>());
                    break;
                case ParamType::Double:  // read as a float (see ParamType)
                    if (!v.is_number() || !p->valid(v.get<double>())) bad();
                    p->set(config, double(float(v.get<double>())));
                    break;
            }
            continue;
        }
        bool is_prefix = false;
        for (const Param& q : params_) is_prefix = is_prefix || (q.in_scenario && q.key.rfind(full + ".", 0) == 0);
        if (!is_prefix) bad_json(at, "unknown key; the " + model_ + " model's parameters: " + key_list());
        read_object(v, at, full + ".", config, handled);
    }
    // Keys required when their object is given (prefix "" is the model
    // object itself, always given).
    for (const Param& q : params_) {
        if (!q.required || !q.in_scenario || q.key.rfind(prefix, 0) != 0) continue;
        const std::string rest = q.key.substr(prefix.size());
        if (rest.find('.') == std::string::npos && !j.contains(rest)) bad_json(path + "." + rest, "missing");
    }
}

void ParamTable::write_device_block(void* config, float* out) const {
    for (const Param& p : params_) {
        if (p.device < 0) continue;
        for (int a = 0; a < p.components(); ++a) {
            float f = 0.0f;
            switch (p.type) {
                case ParamType::Float:
                case ParamType::Double:
                case ParamType::Vec3:
                case ParamType::Bool: f = float(p.get(config, a)); break;
                default: {
                    const uint32_t u = uint32_t(p.get(config, a));  // read as_uint() by the kernels
                    std::memcpy(&f, &u, sizeof f);
                }
            }
            out[p.device + a] = f;
        }
    }
}

std::string ParamTable::device_defines(const std::string& prefix) const {
    std::string s;
    for (const Param& p : params_)
        if (p.device >= 0) s += " -D" + prefix + "_" + upper_name(p.key) + "=" + std::to_string(p.device);
    s += " -D" + prefix + "_FLOATS=" + std::to_string(device_floats_);
    return s;
}

json ParamTable::to_json() const {
    json rows = json::array();
    for (const Param& p : params_) {
        json r;
        r["key"] = p.key;
        r["c_field"] = p.c_field;
        r["type"] = param_type_name(p.type);
        const auto value = [&](double v) -> json {
            switch (p.type) {
                case ParamType::Bool: return v != 0.0;
                case ParamType::Enum: return p.enum_names.at(size_t(v));
                case ParamType::UInt32:
                case ParamType::UInt64:
                case ParamType::UInt3: return uint64_t(v);
                default: return shortest(float(v));
            }
        };
        if (p.components() == 3) r["default"] = {value(p.def[0]), value(p.def[1]), value(p.def[2])};
        else r["default"] = value(p.def[0]);
        if (p.type == ParamType::Float || p.type == ParamType::Double || p.type == ParamType::Vec3 ||
            is_integer(p.type)) {
            r["min"] = std::isfinite(p.lo) ? json(p.lo) : json(nullptr);
            r["max"] = std::isfinite(p.hi) ? json(p.hi) : json(nullptr);
            r["min_exclusive"] = p.lo_open;
        }
        if (p.type == ParamType::Enum) r["values"] = p.enum_names;
        r["range"] = p.range_text();
        r["unit"] = p.unit;
        r["doc"] = p.doc;
        r["ref"] = p.ref;
        r["device"] = p.device >= 0;
        r["scenario"] = p.in_scenario;
        r["per_world"] = p.one_world.empty();
        rows.push_back(std::move(r));
    }
    return rows;
}

std::string ParamTable::to_markdown() const {
    std::string s = "| key | type | default | valid | unit | meaning | paper |\n|---|---|---|---|---|---|---|\n";
    const json rows = to_json();
    for (size_t i = 0; i < params_.size(); ++i) {
        const Param& p = params_[i];
        if (!p.in_scenario) continue;
        std::string def = rows[i]["default"].dump();
        std::string range = p.range_text();
        for (auto* t : {&def, &range})
            for (size_t k = t->find('|'); k != std::string::npos; k = t->find('|', k + 2)) t->replace(k, 1, "\\|");
        s += "| `" + p.key + "` | " + param_type_name(p.type) + " | `" + def + "` | " + range + " | " + p.unit +
             " | " + p.doc + " | " + p.ref + " |\n";
    }
    return s;
}

}  // namespace swarmcl

// ---- per-world values (params/world_params.hpp) ------------------------------

namespace swarmcl {

const Param& world_param_row(const ParamTable& table, const std::string& key) {
    const Param* p = table.find(key);
    if (!p) p = table.find_c_field(key);
    if (!p)
        fail(Status::InvalidArgument, "the " + table.model() + " model has no parameter '" + key +
                                          "'; its parameters: " + table.key_list());
    return *p;
}

void check_world_values(const ParamTable& table, const Param& row, const double* values, size_t count,
                        uint32_t worlds) {
    const size_t want = size_t(worlds) * row.components();
    if (values == nullptr && count > 0)
        fail(Status::InvalidArgument, table.model() + " model " + row.key + ": values is NULL");
    if (count != want)
        fail(Status::InvalidArgument, table.model() + " model " + row.key + ": " + std::to_string(count) +
                                          " values given for " + std::to_string(worlds) + " worlds (" +
                                          std::to_string(want) + " expected" +
                                          (row.components() > 1 ? ", 3 per world" : "") + ")");
    for (size_t i = 0; i < count; ++i) {
        if (row.type == ParamType::UInt64 && !std::isfinite(row.hi) && values[i] >= 0 &&
            values[i] == std::floor(values[i]) && values[i] < 18446744073709551616.0)
            continue;  // seeds: any integer
        if (row.valid(values[i])) continue;
        const std::string name = row.components() > 1 ? row.key + "[" + std::to_string(i % 3) + "]" : row.key;
        fail(Status::InvalidArgument, table.model() + " model " + name + " = " + number_text(values[i]) +
                                          " in world " + std::to_string(i / row.components()) + " is outside " +
                                          row.range_text() + (row.unit.empty() ? "" : " (" + row.unit + ")") +
                                          "; nothing was set");
    }
}

void check_same_in_every_world(const ParamTable& table, const Param& row, const double* values, uint32_t worlds) {
    if (row.one_world.empty()) return;
    const size_t c = size_t(row.components());
    for (size_t i = c; i < size_t(worlds) * c; ++i)
        if (!(values[i] == values[i % c]))
            fail(Status::InvalidArgument, table.model() + " model " + row.key +
                                              " cannot differ between worlds: " + row.one_world + "; nothing was set");
}

}  // namespace swarmcl

// A model's parameters declared once (issue 24): each scalar parameter of a
// model's config is one row of its table (scenario key, C descriptor field,
// type, valid range, unit, one-line doc, the paper's section/equation, and
// whether the kernels read it from the model's parameter block).  From the
// table come the scenario section's reading and its errors, the model's
// range checks, the parameter block on the device, the exported description
// (swcl_model_parameters), fit ranges' checks and the tables of
// docs/scenarios.md.  Defaults are not written here: a row reads its default
// from a default-constructed config, so the config's initialiser (next to
// the field and its comment) stays the one place a default is declared.
// Structured parts (meshes, obstacle lists, keyframes, waypoints) are not
// parameters: each model's section reader keeps them.
#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace swarmcl {

// Double: a float parameter kept in a double field (the path model's cost
// weights): read from a scenario as a float (as the C descriptor's float
// field), checkpointed as the double it is; named "float" outside.
enum class ParamType { Float, UInt32, UInt64, Bool, Vec3, Enum, UInt3, Double };

const char* param_type_name(ParamType t);

struct Param {
    std::string key;      // under "model" in a scenario file: "goal.radius", "noise.scale"
    std::string c_field;  // the C descriptor's field: "goal_radius", "noise.scale"
    ParamType type = ParamType::Float;
    double lo = -std::numeric_limits<double>::infinity();  // valid range
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;  // lo itself is outside the range (> 0)
    std::string unit;      // SI; "" for a pure number, "1" never written
    std::string doc;       // one line
    std::string ref;       // the paper's section / equation, or "ours" with the doc saying why
    std::vector<std::string> enum_names;  // Enum: the names of values 0, 1, ...
    bool required = false;  // must be given when its enclosing object is
    bool in_scenario = true;  // false: implied by a scenario's structure (has_goal), not a key
    int device = -1;        // first float of its slot in the device block; -1: host only
    // Why the value is one for every world of a swarm (what selects a kernel,
    // what the host uses once for all worlds); empty: it may differ between
    // worlds (set_world_param).  Fits and sweeps read it from the table
    // ("per_world") to know what they may run as worlds.
    std::string one_world;
    // Where the value lives in a config of the table's model.
    std::function<void*(void*)> field;
    double def[3] = {0, 0, 0};  // read from a default-constructed config

    // Builders, chained in the table definitions.
    Param& range(double l, double h) { lo = l, hi = h, lo_open = false; return *this; }
    Param& positive() { lo = 0, hi = std::numeric_limits<double>::infinity(), lo_open = true; return *this; }
    Param& non_negative() { return range(0, std::numeric_limits<double>::infinity()); }
    Param& in(const char* u) { unit = u; return *this; }
    Param& says(const char* d) { doc = d; return *this; }
    Param& cites(const char* r) { ref = r; return *this; }
    Param& c(const char* f) { c_field = f; return *this; }
    Param& names(std::vector<std::string> n) { enum_names = std::move(n); return *this; }
    Param& needed() { required = true; return *this; }
    Param& implied() { in_scenario = false; return *this; }
    Param& on_device() { device = 0; return *this; }  // the slot is laid out by ParamTable::finish
    Param& same_in_every_world(const char* why) { one_world = why; return *this; }

    int components() const { return type == ParamType::Vec3 || type == ParamType::UInt3 ? 3 : 1; }
    // "a number >= 0", "an integer in [2, 4096]", ...: the phrase of errors and docs.
    std::string expectation() const;
    // "[0, inf)", "(0, inf)", "[0, 1]", "curl | perlin | ...".
    std::string range_text() const;
    // The value in `config` (component a) as a double, and back.
    double get(void* config, int a = 0) const;
    void set(void* config, double v, int a = 0) const;
    // Within the range and finite (the float value as the kernels see it).
    bool valid(double v) const;
};

class ParamTable {
public:
    // `model`: the model's name ("field"); `config_type`: its config struct.
    ParamTable(std::string model, std::string config_type);

    const std::string& model() const { return model_; }
    const std::string& config_type() const { return config_type_; }
    const std::vector<Param>& params() const { return params_; }
    const Param* find(const std::string& key) const;
    // The parameter whose C descriptor field is `c_field`.
    const Param* find_c_field(const std::string& c_field) const;
    // "goal.center, goal.radius, ...": for errors naming what is known.
    std::string key_list() const;

    // Floats in the device block (per world, once worlds come).
    uint32_t device_floats() const { return device_floats_; }

    // Throws Error(InvalidArgument) naming the first parameter of `config`
    // outside its range: "field model goal_radius = -1 is outside [0, inf) (m)".
    // `prefix`: only the rows whose keys start with it ("lamp.").
    void validate(void* config, const std::string& prefix = "") const;

    // Reads every parameter present in the scenario object `model`
    // ("model" at path `path`) into `config`; keys in `handled` (full keys
    // such as "type" or "keyframes") are read by the section itself.  An
    // unknown key names the model's parameters; a bad value names the key
    // and its range (Error(Parse)).
    void read_json(const nlohmann::json& model, const std::string& path, void* config,
                   const std::set<std::string>& handled) const;

    // The parameters of `config` laid out for the device: device_floats()
    // floats, integers bit-cast (uint32), bools as 0/1.
    void write_device_block(void* config, float* out) const;
    // "-DPREFIX_KEY=slot" for each device parameter (PREFIX_NOISE_SCALE
    // for "noise.scale") and "-DPREFIX_FLOATS=n": the kernels' names for
    // the slots.
    std::string device_defines(const std::string& prefix) const;

    // The table as JSON (an array of rows): swcl_model_parameters, Python.
    nlohmann::json to_json() const;
    // The table as a Markdown table (docs/scenarios.md).
    std::string to_markdown() const;

    // Building: rows of a member of `Config`.
    template <class Config, class T>
    Param& add(const char* key, ParamType type, T Config::*member) {
        Param p;
        p.key = key;
        p.c_field = key;
        for (char& ch : p.c_field) ch = ch == '.' ? '_' : ch;
        p.type = type;
        p.field = [member](void* c) -> void* { return &(static_cast<Config*>(c)->*member); };
        params_.push_back(std::move(p));
        return params_.back();
    }
    // A row of a member of a struct held by `Config` (the path model's
    // lamp.radius: PathModelConfig::lamp, PathLamp::radius).
    template <class Config, class Inner, class T>
    Param& add(const char* key, ParamType type, Inner Config::*outer, T Inner::*member) {
        Param& p = add(key, type, outer);
        p.field = [outer, member](void* c) -> void* { return &((static_cast<Config*>(c)->*outer).*member); };
        return p;
    }
    // Every row of `inner` (a table of a struct held by `Config`), its keys
    // under `prefix` ("noise.").  Its device rows join this table's block
    // (the energy model's weight sets), or, with Block::Own, stay in the
    // inner struct's own block (the noise's: NoiseField::block()).
    enum class Block { Shared, Own };
    template <class Config, class Inner>
    void include(const std::string& prefix, const ParamTable& inner, Inner Config::*member,
                 Block block = Block::Shared) {
        for (const Param& q : inner.params()) {
            Param p = q;
            if (block == Block::Own) p.device = -1;
            p.key = prefix + q.key;
            p.c_field = prefix + q.c_field;
            auto get_inner = q.field;
            p.field = [member, get_inner](void* c) -> void* { return get_inner(&(static_cast<Config*>(c)->*member)); };
            params_.push_back(std::move(p));
        }
    }
    // The row of `key`, to amend while building (an included row's C field:
    // the force model's "noise.scale" is its descriptor's "rho").
    Param& row(const std::string& key);
    // Reads the defaults from a default-constructed config and lays out the
    // device block; the last step of a table's definition.
    template <class Config>
    void finish() {
        Config c;
        finish_layout(&c);
    }

private:
    void finish_layout(void* defaults);
    void read_object(const nlohmann::json& j, const std::string& path, const std::string& prefix, void* config,
                     const std::set<std::string>& handled) const;

    std::string model_, config_type_;
    std::vector<Param> params_;
    uint32_t device_floats_ = 0;
};

// Every model's table, in ModelSpec order (field, path, force, energy, policy),
// and the one named `model` (nullptr when there is none).
const std::vector<const ParamTable*>& model_param_tables();
const ParamTable* find_param_table(const std::string& model);

}  // namespace swarmcl

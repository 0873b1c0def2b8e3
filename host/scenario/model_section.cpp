#include "scenario/model_section.hpp"

#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

template <class Config>
constexpr const char* type_of = ModelTraits<Config>::name;

// "expected \"field\", \"path\", ... or \"ballistic\"": every type in the table.
std::string expected_types() {
    const auto& table = model_sections();
    std::string s = "expected ";
    for (size_t i = 0; i < table.size(); ++i) {
        if (i > 0) s += i + 1 == table.size() ? " or " : ", ";
        s += std::string("\"") + table[i].type + "\"";
    }
    return s;
}

// "model.type" as given, when it names a section ("field" when absent).
const ModelSection* section_of(const json& model) {
    if (!model.is_object()) return nullptr;
    if (!model.contains("type")) return find_model_section(type_of<FieldModelConfig>);
    const json& type = model["type"];
    return type.is_string() ? find_model_section(type.get<std::string>()) : nullptr;
}

}  // namespace

ModelSpec read_ballistic_section(const SectionInput& in) {
    const std::vector<Boundary> obstacles = read_obstacles(in.obstacles);
    JsonObject o(in.model, "model");
    o.string("type", "field");
    o.finish();
    if (!obstacles.empty()) bad_json("obstacles", "a ballistic model ignores obstacles: remove them or use \"field\"");
    return Ballistic{};
}

const std::vector<ModelSection>& model_sections() {
    static const std::vector<ModelSection> table{
        {type_of<FieldModelConfig>, read_field_section, check_field_section},
        {type_of<PathModelConfig>, read_path_section, check_path_section},
        {type_of<ForceModelConfig>, read_force_section, nullptr},
        {type_of<EnergySpec>, read_energy_section, check_energy_section},
        {type_of<PolicySpec>, read_policy_section, nullptr},
        {type_of<Ballistic>, read_ballistic_section, nullptr},
    };
    return table;
}

const ModelSection* find_model_section(const std::string& type) {
    for (const ModelSection& s : model_sections())
        if (type == s.type) return &s;
    return nullptr;
}

ModelSectionResult read_model_section(const json* model, const json* obstacles, const std::string& base_dir) {
    if (!model) {
        if (!read_obstacles(obstacles).empty())
            bad_json("obstacles", "obstacles need a model (\"model\": {\"type\": \"field\"})");
        return {Ballistic{}, nullptr};
    }
    const ModelSection* section = section_of(*model);
    if (!section) {
        // Reported in the order the field-like models read: obstacles, the
        // model object, its type.
        read_obstacles(obstacles);
        JsonObject o(*model, "model");
        o.string("type", "field");
        bad_json("model.type", expected_types());
    }
    return {section->read({*model, obstacles, base_dir}), section};
}

}  // namespace swarmcl

// The model section of a scenario file ("model" and the "obstacles" it
// takes): one reader per model, in one table keyed by "model.type"
// (model_section.cpp).  Each reader reads its model object and the scenario's
// obstacles in the order its messages have always come; `check` runs after
// the whole file is read (checks against the domain).  Error(Parse) naming
// the key path.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "models/model_spec.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

struct SectionInput {
    const nlohmann::json& model;      // the "model" object as given (maybe not an object)
    const nlohmann::json* obstacles;  // the "obstacles" array, nullptr when absent
    const std::string& base_dir;      // OBJ files are read relative to it unless absolute
};

struct ModelSection {
    const char* type;  // "model.type" (ModelTraits<Config>::name)
    ModelSpec (*read)(const SectionInput& in);
    void (*check)(const ModelSpec& spec, const SwarmConfig& swarm);  // nullptr: nothing to check
};

// The table, in the order the "model.type" error lists them.
const std::vector<ModelSection>& model_sections();
const ModelSection* find_model_section(const std::string& type);  // nullptr: unknown

struct ModelSectionResult {
    ModelSpec spec;
    const ModelSection* section = nullptr;  // nullptr: no "model" key
};
// `model`/`obstacles`: the top-level values, nullptr when absent.  Without a
// "model" the swarm is ballistic and obstacles are an error; without
// "model.type" the model is "field".
ModelSectionResult read_model_section(const nlohmann::json* model, const nlohmann::json* obstacles,
                                      const std::string& base_dir);

// The readers (host/scenario/<model>_section.cpp).
ModelSpec read_ballistic_section(const SectionInput& in);
ModelSpec read_field_section(const SectionInput& in);
ModelSpec read_path_section(const SectionInput& in);
ModelSpec read_force_section(const SectionInput& in);
ModelSpec read_energy_section(const SectionInput& in);
ModelSpec read_policy_section(const SectionInput& in);
// Their noise against the domain (NoiseField::validate), as "model.noise: ...".
void check_field_section(const ModelSpec& spec, const SwarmConfig& swarm);
void check_path_section(const ModelSpec& spec, const SwarmConfig& swarm);
void check_energy_section(const ModelSpec& spec, const SwarmConfig& swarm);

}  // namespace swarmcl

// The registry of every model's parameter table (docs/architecture.md, "How
// to add a parameter").
#include "fields/noise_field.hpp"
#include "models/energy_model.hpp"
#include "models/field_model.hpp"
#include "models/force_model.hpp"
#include "models/path_model.hpp"
#include "models/policy_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

const std::vector<const ParamTable*>& model_param_tables() {
    // ModelSpec's order.
    static const std::vector<const ParamTable*> tables = {
        &field_param_table(),
        &path_param_table(),
        &force_param_table(),
        &energy_param_table(),
        &policy_param_table(),
    };
    return tables;
}

const ParamTable* find_param_table(const std::string& model) {
    for (const ParamTable* t : model_param_tables())
        if (t->model() == model) return t;
    return model == "noise" ? &noise_param_table() : nullptr;
}

}  // namespace swarmcl

// swcl_model_parameters: the parameter tables (host/params/) as JSON text.
#include <map>
#include <string>

#include "capi_common.hpp"
#include "params/param_table.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

// Every table's text, made once (static initialisation is thread-safe) and
// kept for the life of the library: the pointers handed out stay valid.
const std::map<std::string, std::string>& texts() {
    static const std::map<std::string, std::string> t = [] {
        std::map<std::string, std::string> m;
        nlohmann::json all = nlohmann::json::object();
        for (const ParamTable* table : model_param_tables()) {
            all[table->model()] = table->to_json();
            m[table->model()] = all[table->model()].dump();
        }
        m["noise"] = find_param_table("noise")->to_json().dump();
        m[""] = all.dump();
        return m;
    }();
    return t;
}

}  // namespace

extern "C" {

swcl_status swcl_model_parameters(const char* model, const char** out_json) {
    return guarded(__func__, [&] {
        require(out_json != nullptr, "out_json must not be NULL");
        const auto& t = texts();
        const auto it = t.find(model ? model : "");
        if (it == t.end() || (model && !*model)) {
            std::string known;
            for (const auto& kv : t)
                if (!kv.first.empty()) known += (known.empty() ? "" : ", ") + kv.first;
            fail(Status::InvalidArgument, std::string("unknown model '") + (model ? model : "") + "' (known: " + known + ")");
        }
        *out_json = it->second.c_str();
    });
}

}  // extern "C"

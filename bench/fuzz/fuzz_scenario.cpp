// Scenario files (host/scenario/: the JSON, every model's section, the
// energy spec, keyframes and obstacle specs, and the OBJ meshes they name).
// Meshes are read relative to examples/scenarios/ (SWARMCL_FUZZ_SCENARIO_DIR),
// as load_scenario would for a file there.  So that a mutated file name never
// reaches outside the project's examples (/dev/zero, a FIFO: a hang, not a
// finding), inputs with a string holding a '/' other than "../meshes/<name>"
// or a NUL are skipped.
#include <nlohmann/json.hpp>

#include "fuzz_target.hpp"
#include "scenario/scenario.hpp"

namespace {

bool safe_string(const std::string& s) {
    if (s.find('\0') != std::string::npos) return false;
    if (s.find('/') == std::string::npos) return true;
    const std::string prefix = "../meshes/";
    return s.compare(0, prefix.size(), prefix) == 0 && s.find('/', prefix.size()) == std::string::npos &&
           s.find("..", prefix.size()) == std::string::npos;
}

bool safe_paths(const nlohmann::json& j) {
    if (j.is_string()) return safe_string(j.get_ref<const std::string&>());
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!safe_string(it.key()) || !safe_paths(it.value())) return false;
    } else if (j.is_array()) {
        for (const auto& v : j)
            if (!safe_paths(v)) return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text = swarmcl::fuzz::bytes_of(data, size);
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_discarded() && !safe_paths(j)) return 0;
    return swarmcl::fuzz::expect_error_or_value([&] { swarmcl::parse_scenario(text, SWARMCL_FUZZ_SCENARIO_DIR); });
}

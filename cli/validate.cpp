// `swarmcl validate SCENARIO.json`: loads the scenario as `run` would and
// says what it describes, or what is wrong with it (the key path).
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_support.hpp"
#include "commands.hpp"

namespace swarmcl_cli {
namespace {

int validate(const std::string& path) {
    Owned<swcl_scenario, swcl_scenario_destroy> scn;
    check(swcl_scenario_load(path.c_str(), &scn.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scn.handle, &info), "reading the scenario");
    std::printf("%s: valid (%s: %u agents, %s model, %u steps of %g s)\n", path.c_str(), info.name, info.agents,
                info.model, info.steps, double(info.dt));
    return 0;
}

}  // namespace

Command add_validate(CLI::App& program) {
    CLI::App* app = program.add_subcommand("validate", "Check a scenario file without running it");
    auto path = std::make_shared<std::string>();
    app->add_option("SCENARIO.json", *path, "the scenario file (docs/scenarios.md)")->required()->type_name("");
    app->footer("Exit status: 0 valid, 1 invalid (the message names the key path),\n"
                "2 usage error.");
    return {app, [path] { return validate(*path); }};
}

}  // namespace swarmcl_cli

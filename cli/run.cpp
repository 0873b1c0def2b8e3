// `swarmcl run SCENARIO.json [...]` and `swarmcl resume DIR [...]`: their
// options, and the plan each hands to the run loop (run_loop.cpp).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_options.hpp"
#include "cli_support.hpp"
#include "commands.hpp"
#include "run_checkpoint.hpp"
#include "run_plan.hpp"

namespace swarmcl_cli {
namespace {

struct RunArgs {
    std::string path, out_dir, device;
    std::optional<uint32_t> steps, every, formats;
    uint32_t checkpoint_every = 0;
    bool quiet = false;
};

// "csv,npy" through the library's table of formats (swcl_export_formats_parse).
uint32_t parse_formats(const std::string& list) {
    uint32_t mask = 0;
    if (swcl_export_formats_parse(list.c_str(), &mask) != SWCL_OK)
        throw Usage{"--format: " + without_function_name(swcl_last_error())};
    return mask;
}

int run(const RunArgs& a) {
    Owned<swcl_scenario, swcl_scenario_destroy> scenario;
    check(swcl_scenario_load(a.path.c_str(), &scenario.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scenario.handle, &info), "reading the scenario");
    RunPlan plan;
    plan.path = a.path;
    plan.steps = a.steps ? *a.steps : info.steps;
    plan.every = a.every ? *a.every : info.output_every;
    plan.formats = a.formats ? *a.formats : info.output_formats;
    plan.out_dir = a.out_dir.empty() ? std::string(info.output_dir) : a.out_dir;
    plan.device = a.device;
    plan.quiet = a.quiet;
    plan.checkpoint_every = a.checkpoint_every;
    std::error_code ec;
    plan.scenario_absolute = std::filesystem::absolute(a.path, ec).string();
    if (ec) plan.scenario_absolute = a.path;
    return execute(plan, scenario.handle, info, nullptr);
}

struct ResumeArgs {
    std::string dir, device;
    bool quiet = false, device_given = false;
};

// Finishes a run from the checkpoint `swarmcl run --checkpoint-every` left in
// DIR: the frames before it are recorded again, then the run goes on to its
// end, so the outputs are those of the run uninterrupted.
int resume(const ResumeArgs& a) {
    const std::string& dir = a.dir;
    swarmcl::cli::RunCheckpoint run;
    ResumePoint point;
    try {
        run = swarmcl::cli::read_run_checkpoint(dir);
        point.frames = swarmcl::cli::read_frames(dir + "/" + run.frames_file, point.agents);
    } catch (const swarmcl::Error& e) {
        throw Failure{std::string("cannot resume: ") + e.what()};
    }
    // The scenario gives the run its name, agent count and dt: the file it
    // began with, unchanged.
    try {
        if (swarmcl::cli::file_crc32(run.scenario_absolute) != run.scenario_crc32)
            throw Failure{"cannot resume: the scenario file '" + run.scenario_absolute +
                          "' changed since the run began"};
    } catch (const swarmcl::Error& e) {
        throw Failure{std::string("cannot resume: ") + e.what()};
    }
    point.swarm_file = dir + "/" + run.swarm_file;
    point.frames_file = run.frames_file;
    point.done = run.done;
    Owned<swcl_scenario, swcl_scenario_destroy> scenario;
    check(swcl_scenario_load(run.scenario_absolute.c_str(), &scenario.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scenario.handle, &info), "reading the scenario");
    RunPlan plan;
    plan.path = run.scenario_file;
    plan.scenario_absolute = run.scenario_absolute;
    plan.out_dir = dir;
    plan.device = a.device_given ? a.device : run.device;
    plan.steps = run.steps;
    plan.every = run.every;
    plan.formats = run.formats;
    plan.checkpoint_every = run.checkpoint_every;
    plan.quiet = a.quiet;
    return execute(plan, scenario.handle, info, &point);
}

}  // namespace

Command add_run(CLI::App& program) {
    CLI::App* app = program.add_subcommand("run", "Run a scenario file and record its trajectories");
    auto a = std::make_shared<RunArgs>();
    app->add_option("SCENARIO.json", a->path, "the scenario file")->required()->type_name("");
    add_count(*app, "--steps", a->steps, 0, "steps to run (default: the scenario's steps)");
    app->add_option("--out", a->out_dir, "the output folder (default: the scenario's output.dir)")->type_name("DIR");
    app->add_option_function<std::string>(
           "--format", [a](const std::string& list) { a->formats = parse_formats(list); },
           "export formats (default: the scenario's output.formats)")
        ->type_name("csv,npy,vtp");
    add_count(*app, "--every", a->every, 1, "record a frame every K steps (default: the scenario's output.every)")
        ->type_name("K");
    add_device(*app, a->device);
    app->add_flag("--quiet", a->quiet, "print nothing but errors (no table, no progress bar)");
    add_count(*app, "--checkpoint-every", a->checkpoint_every, 1,
              "save the run every K steps, for swarmcl resume")
        ->type_name("K");
    app->footer("Writes a frame at step 0 and every K steps, then run.json (the run's statistics)\n"
                "in the output folder; a progress bar shows when stderr is a terminal.\n"
                "Exit status: 0 done, 1 failed (the message on stderr; no output that looks\n"
                "complete is left), 2 usage error.  docs/scenarios.md has the scenario keys.");
    return {app, [a] { return run(*a); }};
}

Command add_resume(CLI::App& program) {
    CLI::App* app = program.add_subcommand(
        "resume", "Finish a stopped run from its last checkpoint (swarmcl run --checkpoint-every)");
    auto a = std::make_shared<ResumeArgs>();
    app->add_option("DIR", a->dir, "the run's output folder (holds checkpoint.json)")->required()->type_name("");
    CLI::Option* device =
        add_device(*app, a->device)->description("device index or part of its name (default: the run's own)");
    app->add_flag("--quiet", a->quiet, "print nothing but errors");
    app->footer("The outputs are those of the uninterrupted run, byte for byte\n"
                "(docs/checkpoint-format.md, \"The CLI's run checkpoints\").");
    return {app, [a, device] {
                a->device_given = device->count() > 0;
                return resume(*a);
            }};
}

}  // namespace swarmcl_cli

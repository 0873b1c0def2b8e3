// The loop of `swarmcl run` and `swarmcl resume`: steps to each frame and
// checkpoint, records, prints the statistics table and a progress bar, and
// writes run.json when the outputs are complete.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

#include <nlohmann/json.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_support.hpp"
#include "frame_stats.hpp"
#include "run_checkpoint.hpp"
#include "run_plan.hpp"

namespace swarmcl_cli {
namespace {

// Ctrl-C or a termination request: the run stops between steps, and the
// unfinished outputs are removed as for any other failure.
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_signal(int) { g_interrupted = 1; }

}  // namespace

int execute(const RunPlan& plan, swcl_scenario scn, const swcl_scenario_info& info, const ResumePoint* resume) {
    const std::string& path = plan.path;
    const std::string& out_dir = plan.out_dir;
    const std::string& device = plan.device;
    const uint32_t steps = plan.steps, every = plan.every, formats = plan.formats;
    const bool quiet = plan.quiet;

    swcl_context_desc cd = swcl_context_desc_default();
    if (!device.empty()) cd.device = device.c_str();
    Owned<swcl_context, swcl_context_destroy> context;
    check(swcl_context_create(&cd, &context.handle), "opening the device");
    const swcl_context ctx = context.handle;
    swcl_device_info dev;
    dev.struct_size = sizeof(dev);
    check(swcl_context_device_info(ctx, &dev), "reading device info");
    Owned<swcl_swarm, swcl_swarm_destroy> owned_swarm;
    if (resume) {
        check(swcl_swarm_load(ctx, resume->swarm_file.c_str(), &owned_swarm.handle), "loading the checkpoint");
    } else {
        check(swcl_scenario_create_swarm(scn, ctx, &owned_swarm.handle), "creating the swarm");
    }
    const swcl_swarm swarm = owned_swarm.handle;
    Owned<swcl_recorder, swcl_recorder_destroy> recorder;
    check(swcl_recorder_create(out_dir.c_str(), info.name, formats, &recorder.handle), "opening the output folder");
    const swcl_recorder rec = recorder.handle;

    // Frames kept for checkpoints (the resumed run records them again).
    std::vector<swarmcl::cli::Frame> kept;
    std::string previous_swarm_file, previous_frames_file;
    swarmcl::cli::RunCheckpoint run_state;
    if (plan.checkpoint_every) {
        run_state.scenario_file = path;
        run_state.scenario_absolute = plan.scenario_absolute;
        try {
            run_state.scenario_crc32 = swarmcl::cli::file_crc32(plan.scenario_absolute);
        } catch (const swarmcl::Error& e) {
            throw Failure{e.what()};
        }
        run_state.out_dir = out_dir;
        run_state.device = device;
        run_state.steps = steps;
        run_state.every = every;
        run_state.formats = formats;
        run_state.checkpoint_every = plan.checkpoint_every;
    }
    auto read_frame = [&](uint32_t frame, double time) {
        swarmcl::cli::Frame f;
        f.frame = frame;
        f.time = time;
        f.pos.resize(size_t(info.agents) * 3);
        f.vel.resize(size_t(info.agents) * 3);
        check(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, f.pos.data(), info.agents), "reading positions");
        check(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, f.vel.data(), info.agents), "reading velocities");
        kept.push_back(std::move(f));
    };
    auto record = [&](uint32_t frame, double time, const char* what) {
        check(swcl_recorder_add_frame(rec, swarm, frame, time), what);
        if (plan.checkpoint_every) read_frame(frame, time);
    };

    const bool show = !quiet && isatty(STDERR_FILENO);
    if (!quiet) {
        std::printf("%s: %u agents, %s model, %u steps of %g s on %s / %s%s\n", info.name, info.agents, info.model,
                    steps, double(info.dt), dev.platform_name, dev.device_name,
                    resume ? (", resumed at step " + std::to_string(resume->done)).c_str() : "");
        print_stats_header();
    }
    FrameStats last;
    const auto start = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    uint32_t frames = 0;
    uint32_t done = 0;
    if (resume) {
        // The frames before the checkpoint, as they were recorded: through a
        // swarm without a model holding each frame's values (written and read
        // back unchanged).
        swcl_swarm_desc sd = swcl_swarm_desc_default();
        sd.capacity = std::max(resume->agents, 1u);
        Owned<swcl_swarm, swcl_swarm_destroy> holder;
        check(swcl_swarm_create(ctx, &sd, &holder.handle), "replaying the recorded frames");
        for (const auto& f : resume->frames) {
            check(swcl_swarm_write(holder.handle, SWCL_ATTRIBUTE_POSITION, f.pos.data(), resume->agents), "replaying frames");
            check(swcl_swarm_write(holder.handle, SWCL_ATTRIBUTE_VELOCITY, f.vel.data(), resume->agents), "replaying frames");
            check(swcl_recorder_add_frame(rec, holder.handle, f.frame, f.time), "recording");
            ++frames;
        }
        if (resume->agents != info.agents) throw Failure{"cannot resume: the frames hold another agent count"};
        if (plan.checkpoint_every) kept = resume->frames;
        done = resume->done;
        previous_swarm_file = std::filesystem::path(resume->swarm_file).filename().string();
        previous_frames_file = resume->frames_file;
    } else {
        record(0, 0.0, "recording frame 0");
        ++frames;
        if (!quiet) print_stats(0, last = frame_stats(swarm, info.agents, info.min_distance));
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const uint32_t ck = plan.checkpoint_every;
    while (done < steps) {
        if (g_interrupted)
            throw Failure{"interrupted at step " + std::to_string(done) + "; no output was kept" +
                          (ck ? " (checkpoint.json: swarmcl resume " + out_dir + " goes on from its step)" : "")};
        // To the next frame, the next checkpoint or the end, whichever is first
        // (the frames fall where they fall without checkpoints).
        uint64_t next = std::min<uint64_t>((uint64_t(done) / every + 1) * every, steps);
        if (ck) next = std::min<uint64_t>(next, (uint64_t(done) / ck + 1) * ck);
        const uint32_t k = uint32_t(next - done);
        check(swcl_swarm_step(swarm, k), "stepping");
        done += k;
        if (done % every == 0 || done == steps) {
            record(done, double(done) * info.dt, "recording");
            ++frames;
            if (!quiet) {
                if (show) std::fputs("\r\033[K", stderr);  // the table line replaces the bar
                print_stats(done, last = frame_stats(swarm, info.agents, info.min_distance));
                std::fflush(stdout);
            }
            progress(show, done, steps, seconds());
        }
        if (ck && done % ck == 0 && done < steps) {
            // Named by step: checkpoint.json, written last, names complete files only.
            char name[64];
            std::snprintf(name, sizeof name, "checkpoint-%09u", done);
            run_state.done = done;
            run_state.swarm_file = std::string(name) + ".swcl";
            run_state.frames_file = std::string(name) + ".frames";
            check(swcl_swarm_save(swarm, (out_dir + "/" + run_state.swarm_file).c_str()), "writing a checkpoint");
            try {
                swarmcl::cli::write_run_checkpoint(run_state, kept, info.agents, previous_swarm_file,
                                                   previous_frames_file);
            } catch (const swarmcl::Error& e) {
                throw Failure{std::string("writing a checkpoint: ") + e.what()};
            }
            previous_swarm_file = run_state.swarm_file;
            previous_frames_file = run_state.frames_file;
        }
    }
    check(swcl_recorder_finish(rec), "writing the outputs");
    const double wall = seconds();
    if (quiet) last = frame_stats(swarm, info.agents, info.min_distance);

    nlohmann::json run;
    run["scenario"] = info.name;
    run["scenario_file"] = path;
    run["device"] = std::string(dev.platform_name) + " / " + dev.device_name;
    run["agents"] = info.agents;
    run["steps"] = steps;
    run["dt"] = info.dt;
    run["seed"] = info.seed;
    run["frames"] = frames;
    run["every"] = every;
    run["seconds"] = wall;
    run["steps_per_second"] = wall > 0 ? steps / wall : 0.0;
    run["final"] = {{"mean_speed", last.mean_speed},
                    {"nearest_neighbor_p5", last.nn_p5},
                    {"nearest_neighbor_p50", last.nn_p50},
                    {"nearest_neighbor_p95", last.nn_p95},
                    {"close_pair_fraction", last.close_pair_fraction},
                    {"mde_moved_fraction", last.mde_moved}};
    run["formats"] = export_format_names(formats);
    run["output_dir"] = out_dir;
    run["parameters"] = nlohmann::json::parse(read_file(plan.scenario_absolute), nullptr, false);
    write_atomically(out_dir + "/run.json", run.dump(2) + "\n");
    if (!quiet)
        std::printf("done: %u steps in %.2f s (%.1f steps/s), %u frames written to %s/ (run.json has the statistics)\n",
                    steps, wall, wall > 0 ? steps / wall : 0.0, frames, out_dir.c_str());
    return 0;
}

}  // namespace swarmcl_cli

// The swarmcl command line: run a scenario file, list devices, validate a
// scenario.  It uses only the public C API, like any other program would.
//
//   swarmcl run scenario.json [--steps N] [--out DIR] [--format csv,npy,vtp]
//                             [--every K] [--device D] [--quiet] [--checkpoint-every K]
//   swarmcl resume DIR [--device D] [--quiet]
//   swarmcl evaluate scenario.json --tracks tracks.csv [...]   (cli/evaluate.cpp)
//   swarmcl fit scenario.json --tracks tracks.csv --ranges ranges.json [...]   (cli/fit.cpp)
//   swarmcl devices
//   swarmcl validate scenario.json
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <nlohmann/json.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_support.hpp"
#include "evaluate.hpp"
#include "fit.hpp"
#include "run_checkpoint.hpp"

using namespace swarmcl_cli;

namespace {

const char* kUsage =
    "usage:\n"
    "  swarmcl run SCENARIO.json [--steps N] [--out DIR] [--format csv,npy,vtp] [--every K]\n"
    "                            [--device D] [--quiet] [--checkpoint-every K]\n"
    "  swarmcl resume DIR [--device D] [--quiet]\n"
    "  swarmcl evaluate SCENARIO.json --tracks FILE.csv [--columns id,time,x,y,z] [--unit-scale S]\n"
    "                            [--window FROM,TO] [--warmup N] [--steps N] [--every K] [--bins M]\n"
    "                            [--half-width H] [--out FILE.json] [--plot] [--device D] [--quiet]\n"
    "  swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json [--method cmaes|ga]\n"
    "                            [--generations G] [--population P] [--seed S] [...]  (in Python; --help)\n"
    "  swarmcl devices\n"
    "  swarmcl validate SCENARIO.json\n";

// Ctrl-C or a termination request: the run stops between steps, and the
// unfinished outputs are removed as for any other failure.
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_signal(int) { g_interrupted = 1; }

int cmd_devices() {
    uint32_t n = 0;
    check(swcl_device_count(&n), "listing devices");
    for (uint32_t i = 0; i < n; ++i) {
        swcl_device_info info;
        info.struct_size = sizeof(info);
        check(swcl_device_get_info(i, &info), "reading device info");
        const char* type = info.type == SWCL_DEVICE_TYPE_GPU   ? "GPU"
                           : info.type == SWCL_DEVICE_TYPE_CPU ? "CPU"
                                                               : "other";
        std::printf("%u  %-5s %s / %s  (%u compute units, %.1f GiB, %s)\n", i, type, info.platform_name,
                    info.device_name, info.compute_units, double(info.global_memory_bytes) / (1u << 30), info.version);
    }
    return 0;
}

int cmd_validate(const std::string& path) {
    Owned<swcl_scenario, swcl_scenario_destroy> scn;
    check(swcl_scenario_load(path.c_str(), &scn.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scn.handle, &info), "reading the scenario");
    std::printf("%s: valid (%s: %u agents, %s model, %u steps of %g s)\n", path.c_str(), info.name, info.agents,
                info.model, info.steps, double(info.dt));
    return 0;
}

uint32_t parse_formats(const std::string& list) {
    uint32_t mask = 0;
    std::stringstream in(list);
    std::string f;
    while (std::getline(in, f, ',')) {
        if (f == "csv") mask |= SWCL_EXPORT_CSV;
        else if (f == "npy") mask |= SWCL_EXPORT_NPY;
        else if (f == "vtp") mask |= SWCL_EXPORT_VTP;
        else throw Usage{"--format: unknown format '" + f + "' (expected csv, npy, vtp)"};
    }
    if (!mask) throw Usage{"--format: no format given"};
    return mask;
}

// Statistics of the swarm now (main job, curl-noise paper item 8): mean
// speed, nearest-neighbour distance percentiles, the fraction of pairs
// closer than the MDE distance, and the share MDE moved per step since the
// last call.
struct FrameStats {
    double mean_speed = 0, nn_p5 = 0, nn_p50 = 0, nn_p95 = 0, close_pair_fraction = 0, mde_moved = 0;
};

FrameStats frame_stats(swcl_swarm swarm, uint32_t n, float min_distance) {
    FrameStats f;
    if (n == 0) return f;
    std::vector<float> vel(size_t(n) * 3), nn(n);
    check(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, vel.data(), n), "reading velocities");
    for (uint32_t i = 0; i < n; ++i)
        f.mean_speed += std::sqrt(double(vel[3 * i]) * vel[3 * i] + double(vel[3 * i + 1]) * vel[3 * i + 1] +
                                  double(vel[3 * i + 2]) * vel[3 * i + 2]) / n;
    if (n > 1) {
        check(swcl_swarm_nearest_neighbor(swarm, nn.data(), nullptr, n), "nearest neighbours");
        std::sort(nn.begin(), nn.end());
        auto pct = [&](double q) { return double(nn[size_t(q * (n - 1) + 0.5)]); };
        f.nn_p5 = pct(0.05), f.nn_p50 = pct(0.5), f.nn_p95 = pct(0.95);
        if (min_distance > 0) {
            std::vector<uint32_t> close(n);
            // Just below the threshold: pairs MDE left at exactly d do not count.
            check(swcl_swarm_neighbor_count(swarm, min_distance * 0.999f, close.data(), n), "counting close pairs");
            double pairs = 0;
            for (uint32_t c : close) pairs += c;
            f.close_pair_fraction = pairs / 2.0 / (0.5 * double(n) * (n - 1.0));
        }
    }
    swcl_step_stats st;
    st.struct_size = sizeof(st);
    check(swcl_swarm_take_step_stats(swarm, &st), "reading statistics");
    if (st.steps) f.mde_moved = double(st.mde_moved_total) / (double(st.steps) * n);
    return f;
}

void print_stats(uint32_t step, const FrameStats& f) {
    std::printf("%8u %8.3f %9.4f %9.4f %9.4f %10.2e %8.3f%%\n", step, f.mean_speed, f.nn_p5, f.nn_p50, f.nn_p95,
                f.close_pair_fraction, 100.0 * f.mde_moved);
}

// A run's settings, from the command line and the scenario (run) or from
// checkpoint.json (resume).
struct RunPlan {
    std::string path, out_dir, device;
    std::string scenario_absolute;  // the scenario file, wherever the run is resumed from
    uint32_t steps = 0, every = 1, formats = 0, checkpoint_every = 0;
    bool quiet = false;
};

// Where a resumed run starts: the swarm, the step and the frames recorded before.
struct ResumePoint {
    std::string swarm_file, frames_file;
    uint32_t done = 0;
    uint32_t agents = 0;
    std::vector<swarmcl::cli::Frame> frames;
};

int execute(const RunPlan& plan, swcl_scenario scn, const swcl_scenario_info& info, const ResumePoint* resume);

int cmd_run(int argc, char** argv) {
    std::string path, out_dir, device;
    long steps_override = -1, every_override = -1;
    uint32_t formats_override = 0, checkpoint_every = 0;
    bool quiet = false;
    for (int i = 0; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* flag) -> const char* {
            if (i + 1 >= argc) throw Usage{std::string(flag) + ": missing value"};
            return argv[++i];
        };
        if (a == "--steps") steps_override = parse_count("--steps", value("--steps"), 0);
        else if (a == "--every") every_override = parse_count("--every", value("--every"), 1);
        else if (a == "--out") out_dir = value("--out");
        else if (a == "--format") formats_override = parse_formats(value("--format"));
        else if (a == "--device") device = value("--device");
        else if (a == "--quiet") quiet = true;
        else if (a == "--checkpoint-every")
            checkpoint_every = parse_count("--checkpoint-every", value("--checkpoint-every"), 1);
        else if (!a.empty() && a[0] == '-') throw Usage{"unknown option '" + a + "'"};
        else if (path.empty()) path = a;
        else throw Usage{"unexpected argument '" + a + "'"};
    }
    if (path.empty()) throw Usage{"run: no scenario file"};

    Owned<swcl_scenario, swcl_scenario_destroy> scenario;
    check(swcl_scenario_load(path.c_str(), &scenario.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scenario.handle, &info), "reading the scenario");
    RunPlan plan;
    plan.path = path;
    plan.steps = steps_override >= 0 ? uint32_t(steps_override) : info.steps;
    plan.every = every_override > 0 ? uint32_t(every_override) : info.output_every;
    plan.formats = formats_override ? formats_override : info.output_formats;
    plan.out_dir = out_dir.empty() ? std::string(info.output_dir) : out_dir;
    plan.device = device;
    plan.quiet = quiet;
    plan.checkpoint_every = checkpoint_every;
    std::error_code ec;
    plan.scenario_absolute = std::filesystem::absolute(path, ec).string();
    if (ec) plan.scenario_absolute = path;
    return execute(plan, scenario.handle, info, nullptr);
}

// Finishes a run from the checkpoint `swarmcl run --checkpoint-every` left in
// DIR: the frames before it are recorded again, then the run goes on to its
// end, so the outputs are those of the run uninterrupted.
int cmd_resume(int argc, char** argv) {
    std::string dir, device;
    bool quiet = false, device_given = false;
    for (int i = 0; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--device") {
            if (i + 1 >= argc) throw Usage{"--device: missing value"};
            device = argv[++i];
            device_given = true;
        } else if (a == "--quiet") {
            quiet = true;
        } else if (!a.empty() && a[0] == '-') {
            throw Usage{"unknown option '" + a + "'"};
        } else if (dir.empty()) {
            dir = a;
        } else {
            throw Usage{"unexpected argument '" + a + "'"};
        }
    }
    if (dir.empty()) throw Usage{"resume: no output folder"};
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
    plan.device = device_given ? device : run.device;
    plan.steps = run.steps;
    plan.every = run.every;
    plan.formats = run.formats;
    plan.checkpoint_every = run.checkpoint_every;
    plan.quiet = quiet;
    return execute(plan, scenario.handle, info, &point);
}

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
        std::printf("%8s %8s %9s %9s %9s %10s %9s\n", "step", "speed", "nn p5", "nn p50", "nn p95", "pairs<mde",
                    "MDE moved");
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
    nlohmann::json fmts = nlohmann::json::array();
    if (formats & SWCL_EXPORT_CSV) fmts.push_back("csv");
    if (formats & SWCL_EXPORT_NPY) fmts.push_back("npy");
    if (formats & SWCL_EXPORT_VTP) fmts.push_back("vtp");
    run["formats"] = fmts;
    run["output_dir"] = out_dir;
    run["parameters"] = nlohmann::json::parse(read_file(plan.scenario_absolute), nullptr, false);
    write_atomically(out_dir + "/run.json", run.dump(2) + "\n");
    if (!quiet)
        std::printf("done: %u steps in %.2f s (%.1f steps/s), %u frames written to %s/ (run.json has the statistics)\n",
                    steps, wall, wall > 0 ? steps / wall : 0.0, frames, out_dir.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    const std::string cmd = argv[1];
    try {
        if (cmd == "run") return cmd_run(argc - 2, argv + 2);
        if (cmd == "resume") return cmd_resume(argc - 2, argv + 2);
        if (cmd == "devices") return cmd_devices();
        if (cmd == "evaluate") return cmd_evaluate(argc - 2, argv + 2);
        if (cmd == "fit") return cmd_fit(argc - 2, argv + 2);
        if (cmd == "validate") {
            if (argc != 3) throw Usage{"validate: expected one scenario file"};
            return cmd_validate(argv[2]);
        }
        if (cmd == "--help" || cmd == "-h" || cmd == "help") {
            std::fputs(kUsage, stdout);
            return 0;
        }
        std::fprintf(stderr, "unknown command '%s'\n%s", cmd.c_str(), kUsage);
        return 2;
    } catch (const Usage& u) {
        std::fprintf(stderr, "swarmcl: %s\n%s", u.message.c_str(), kUsage);
        return 2;
    } catch (const Failure& f) {
        std::fprintf(stderr, "swarmcl: %s\n", f.message.c_str());
        return 1;
    }
}

// `swarmcl evaluate`: runs a scenario and scores it against real tracks with
// the seven-metric evaluation of the noise paper (§3; docs/evaluation.md).
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_options.hpp"
#include "cli_support.hpp"
#include "commands.hpp"

namespace swarmcl_cli {
namespace {

struct EvaluateArgs {
    std::string scenario, tracks, out, device;
    std::vector<std::string> columns = {"id", "time", "x", "y", "z"};
    double unit_scale = 1.0, window_from = 0.0, window_to = 1.0;
    char delimiter = ',';
    std::optional<uint32_t> every, steps;
    uint32_t warmup = 0, runs = 1;
    std::optional<uint64_t> seed;
    swcl_pdf_options pdf = swcl_pdf_options_default();
    bool quiet = false, plot = false;
};

// The options, on the command's CLI11 app; `a` is filled as they are parsed.
void add_options(CLI::App& app, EvaluateArgs& a) {
    app.add_option("SCENARIO.json", a.scenario, "the scenario to run (docs/scenarios.md)")->required()->type_name("");
    app.add_option("--tracks", a.tracks, "the real tracks, a CSV of id,time,x,y,z rows")
        ->type_name("FILE.csv")
        ->required();
    app.add_option_function<std::string>(
           "--columns",
           [&a](const std::string& text) {
               a.columns = split_commas(text);
               if (a.columns.size() != 5) throw Usage{"--columns: expected five names: id,time,x,y,z"};
           },
           "the tracks' columns (default id,time,x,y,z)")
        ->type_name("ID,T,X,Y,Z");
    add_delimiter(app, a.delimiter);
    add_number(app, "--unit-scale", a.unit_scale, "the tracks' length unit in metres (default 1)");
    app.add_option_function<std::string>(
           "--window",
           [&a](const std::string& text) {
               const auto w = split_commas(text);
               if (w.size() != 2) throw Usage{"--window: expected FROM,TO (fractions of the recording, e.g. 0.5,1)"};
               a.window_from = parse_number("--window", w[0]);
               a.window_to = parse_number("--window", w[1]);
           },
           "fractions of the recording compared (default 0,1)")
        ->type_name("FROM,TO");
    add_count(app, "--warmup", a.warmup, 0, "steps before the first sample (default 0)");
    add_count(app, "--steps", a.steps, 1, "steps sampled after it (default: the scenario's)");
    add_count(app, "--every", a.every, 1,
              "steps between samples (default: the tracks' frame time / dt)");
    add_count(app, "--runs", a.runs, 1,
              "runs of the scenario, their samples pooled (worlds of one swarm; default 1)");
    app.add_option_function<std::string>(
           "--seed",
           [&a](const std::string& text) {
               // Every 64-bit seed, exactly (a double would round above 2^53).
               char* end = nullptr;
               errno = 0;
               const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
               if (text.empty() || *end || errno || text[0] == '-')
                   throw Usage{"--seed: expected an integer >= 0, got '" + text + "'"};
               a.seed = uint64_t(v);
           },
           "the first run's simulation seed, the next run's +1 (default: the scenario's), e.g. seeds a fit did "
           "not use")
        ->type_name("S");
    add_count(app, "--bins", a.pdf.bins, 1, "bins of each metric's PDF (default 50)");
    add_number(app, "--half-width", a.pdf.half_width, "the PDFs' half width in sigma (default 4)");
    app.add_option("--out", a.out, "the result (default: the scenario's output.dir/evaluation.json)")
        ->type_name("FILE.json");
    app.add_flag_function(
        "--robust",
        [&a](int64_t) { a.pdf.standardise = SWCL_STANDARDISE_MEDIAN_MAD; },
        "z-score each side with its median and 1.4826 MAD, not its mean and sigma (a few tracking glitches "
        "do not move it)");
    app.add_flag("--plot", a.plot, "draw the PDFs beside the JSON (FILE.png, in Python)");
    add_device(app, a.device);
    app.add_flag("--quiet", a.quiet, "print nothing but errors");
}

nlohmann::json side_json(swcl_metrics m, swcl_metric k, const swcl_pdf_options& pdf) {
    swcl_metric_info info;
    info.struct_size = sizeof(info);
    check(swcl_metrics_get_info(m, k, &info), "reading a metric");
    std::vector<double> q(pdf.bins);
    check(swcl_metrics_pdf(m, k, &pdf, q.data(), q.size()), "computing a PDF");
    return {{"count", info.count}, {"mean", info.mean},   {"sigma", info.sigma},
            {"median", info.median}, {"mad", info.mad}, {"pdf", q}};
}

// The Wasserstein-1 distance of one metric in its unit, or null when a side
// has none of its samples (one insect in view: no d); other errors throw.
nlohmann::json wasserstein_json(swcl_metrics real, swcl_metrics sim, swcl_metric k) {
    double w = 0.0;
    const swcl_status st = swcl_metrics_wasserstein(real, sim, k, &w);
    if (st == SWCL_OK) return w;
    swcl_metric_info a, b;
    a.struct_size = b.struct_size = sizeof(swcl_metric_info);
    check(swcl_metrics_get_info(real, k, &a), "reading a metric");
    check(swcl_metrics_get_info(sim, k, &b), "reading a metric");
    if (a.count == 0 || b.count == 0) return nullptr;
    check(st, "computing a Wasserstein distance");
    return nullptr;
}

// The seven PDFs as a PNG beside the JSON, drawn by the Python package
// (matplotlib): `$SWARMCL_PYTHON -m swarmcl.evaluation plot FILE.json`.
std::string plot_beside(const std::string& json_path) {
    const char* env = std::getenv("SWARMCL_PYTHON");
    std::string python = env && *env ? env : "python3";
    std::vector<std::string> args = {python, "-m", "swarmcl.evaluation", "plot", json_path};
    std::vector<char*> raw;
    for (auto& x : args) raw.push_back(x.data());
    raw.push_back(nullptr);
    pid_t pid = 0;
    std::fflush(stdout);
    if (posix_spawnp(&pid, python.c_str(), nullptr, nullptr, raw.data(), environ) != 0)
        throw Failure{"--plot: cannot start '" + python + "' (set SWARMCL_PYTHON to a Python with swarmcl[plot])"};
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Failure{"--plot: '" + python + " -m swarmcl.evaluation plot' failed (pip install 'swarmcl[plot]'); " +
                      json_path + " is complete"};
    const auto dot = json_path.rfind('.');
    return (dot == std::string::npos ? json_path : json_path.substr(0, dot)) + ".png";
}

int evaluate(const EvaluateArgs& a) {

    // The real side: tracks in the time window.
    swcl_dataset_desc td = swcl_dataset_desc_default();
    td.column_id = a.columns[0].c_str();
    td.column_time = a.columns[1].c_str();
    td.column_x = a.columns[2].c_str();
    td.column_y = a.columns[3].c_str();
    td.column_z = a.columns[4].c_str();
    td.unit_scale = a.unit_scale;
    td.delimiter = a.delimiter;
    Owned<swcl_metrics, swcl_metrics_destroy> real;
    check(swcl_metrics_from_csv(a.tracks.c_str(), &td, a.window_from, a.window_to, &real.handle), "reading the tracks");
    double frame_time = 0.0;
    check(swcl_metrics_frame_time(real.handle, &frame_time), "reading the tracks' frame time");

    // The simulated side: the scenario, sampled every K steps after the warm-up.
    Owned<swcl_scenario, swcl_scenario_destroy> scenario;
    check(swcl_scenario_load(a.scenario.c_str(), &scenario.handle), "invalid scenario");
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    check(swcl_scenario_get_info(scenario.handle, &info), "reading the scenario");
    const uint32_t steps = a.steps ? *a.steps : info.steps;
    // By default the samples are as far apart as the real frames, so both
    // sides' derivatives are taken over the same clock.
    const uint32_t every =
        a.every ? *a.every : uint32_t(std::max(1.0, std::round(frame_time / double(info.dt))));
    const double sample_dt = double(every) * info.dt;
    if (info.agents < 2) throw Failure{"evaluate: the scenario needs at least two agents (nearest distances)"};

    swcl_context_desc cd = swcl_context_desc_default();
    if (!a.device.empty()) cd.device = a.device.c_str();
    Owned<swcl_context, swcl_context_destroy> context;
    check(swcl_context_create(&cd, &context.handle), "opening the device");
    // Several runs (or another seed): the worlds of one swarm, world k the
    // scenario alone with seed first + k, so one run with --seed S is the
    // scenario run with seed S; their samples are pooled below.
    Owned<swcl_swarm, swcl_swarm_destroy> swarm;
    const uint64_t first_seed = a.seed ? *a.seed : info.seed;
    const uint32_t runs = a.runs;
    if (runs == 1 && !a.seed) {
        check(swcl_scenario_create_swarm(scenario.handle, context.handle, &swarm.handle), "creating the swarm");
    } else {
        std::vector<uint64_t> seeds(runs);
        for (uint32_t k = 0; k < runs; ++k) seeds[k] = first_seed + k;
        check(swcl_scenario_create_world_swarm(scenario.handle, context.handle, runs, seeds.data(), &swarm.handle),
              "creating the runs as worlds");
    }
    const size_t n = info.agents, all = n * runs;
    std::vector<float> frames;
    const bool show = !a.quiet && isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const uint32_t total = a.warmup + steps;
    uint32_t done = 0;
    auto sample = [&] {
        frames.resize(frames.size() + 3 * all);
        check(swcl_swarm_read(swarm.handle, SWCL_ATTRIBUTE_POSITION, frames.data() + frames.size() - 3 * all, all),
              "reading positions");
    };
    for (; done < a.warmup;) {
        const uint32_t k = std::min<uint32_t>(every, a.warmup - done);
        check(swcl_swarm_step(swarm.handle, k), "stepping");
        done += k;
        progress(show, done, total, seconds());
    }
    sample();
    for (uint32_t s = 0; s + every <= steps; s += every) {
        check(swcl_swarm_step(swarm.handle, every), "stepping");
        done += every;
        sample();
        progress(show, done, total, seconds());
    }
    progress(show, total, total, seconds());
    const size_t frame_count = frames.size() / (3 * all);
    Owned<swcl_metrics, swcl_metrics_destroy> sim;
    if (runs == 1) {
        check(swcl_metrics_from_frames(frames.data(), frame_count, n, sample_dt, &sim.handle),
              "computing the metrics");
    } else {  // each run's frames where they lie, then pooled (swcl_metrics_merge)
        std::vector<Owned<swcl_metrics, swcl_metrics_destroy>> parts(runs);
        std::vector<swcl_metrics> handles(runs);
        for (uint32_t k = 0; k < runs; ++k) {
            check(swcl_metrics_from_frames_strided(frames.data() + 3 * n * k, frame_count, n, 3 * all, sample_dt,
                                                   &parts[k].handle),
                  "computing the metrics");
            handles[k] = parts[k].handle;
        }
        check(swcl_metrics_merge(handles.data(), runs, &sim.handle), "pooling the runs");
    }

    double e[SWCL_METRIC_COUNT];
    check(swcl_metrics_distances(real.handle, sim.handle, &a.pdf, e, SWCL_METRIC_COUNT), "comparing the PDFs");
    const swcl_score_weights w = swcl_score_weights_default();
    double score = 0.0;
    check(swcl_score(e, SWCL_METRIC_COUNT, &w, &score), "scoring");

    nlohmann::json out;
    out["scenario"] = info.name;
    out["scenario_file"] = a.scenario;
    out["tracks"] = a.tracks;
    out["window"] = {a.window_from, a.window_to};
    out["tracks_frame_time"] = frame_time;
    out["agents"] = n;
    out["dt"] = info.dt;
    out["warmup_steps"] = a.warmup;
    out["steps"] = steps;
    out["every"] = every;
    out["frames"] = frame_count;
    out["runs"] = runs;
    out["first_seed"] = first_seed;
    out["pdf"] = {{"bins", a.pdf.bins},
                  {"half_width", a.pdf.half_width},
                  {"standardise", a.pdf.standardise == SWCL_STANDARDISE_MEDIAN_MAD ? "median_mad" : "mean_sigma"}};
    out["weights"] = {{"w", w.w}, {"p1", w.p1}, {"p2", w.p2}};
    // The names are the library's metric table (swcl_metric_name).
    // Beside each E_phi, the Wasserstein-1 distance in the metric's unit
    // (the z-scored E_phi ignores scale).
    std::vector<nlohmann::json> w1(SWCL_METRIC_COUNT);
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        const swcl_metric m = swcl_metric(k);
        w1[k] = wasserstein_json(real.handle, sim.handle, m);
        auto& row = out["metrics"][swcl_metric_name(m)];
        row = {{"distance", e[k]},
               {"wasserstein", w1[k]},
               {"unit", swcl_metric_unit(m)},
               {"real", side_json(real.handle, m, a.pdf)},
               {"sim", side_json(sim.handle, m, a.pdf)}};
    }
    out["score"] = score;
    // The data's own floor (issue 26, item 4): the window's first half of
    // the tracks (by time) scored against its second half, the same way, so
    // a model's E reads against how close the data is to itself.
    const double mid = a.window_from + (a.window_to - a.window_from) / 2.0;
    Owned<swcl_metrics, swcl_metrics_destroy> first, second;
    check(swcl_metrics_from_csv(a.tracks.c_str(), &td, a.window_from, mid, &first.handle), "reading the tracks");
    check(swcl_metrics_from_csv(a.tracks.c_str(), &td, mid, a.window_to, &second.handle), "reading the tracks");
    double ef[SWCL_METRIC_COUNT];
    check(swcl_metrics_distances(first.handle, second.handle, &a.pdf, ef, SWCL_METRIC_COUNT), "comparing the halves");
    double floor_score = 0.0;
    check(swcl_score(ef, SWCL_METRIC_COUNT, &w, &floor_score), "scoring the halves");
    out["data_floor"] = {{"score", floor_score},
                         {"window_halves", {{a.window_from, mid}, {mid, a.window_to}}},
                         {"distances", std::vector<double>(ef, ef + SWCL_METRIC_COUNT)}};
    out["seconds"] = seconds();
    const std::string path = a.out.empty() ? std::string(info.output_dir) + "/evaluation.json" : a.out;
    write_atomically(path, out.dump(2) + "\n");
    if (!a.quiet) {
        std::printf("%s against %s: %zu frames of %zu agents every %u steps (%.4g s), %u run%s from seed %llu\n",
                    info.name, a.tracks.c_str(), frame_count, n, every, sample_dt, runs, runs == 1 ? "" : "s pooled",
                    (unsigned long long)first_seed);
        std::printf("%-22s %10s %12s  %-8s %12s %12s\n", "metric", "E_phi", "W1", "unit", "median real",
                    "median sim");
        for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
            const auto& row = out["metrics"][swcl_metric_name(swcl_metric(k))];
            char w[32] = "-";
            if (!w1[k].is_null()) std::snprintf(w, sizeof w, "%.4g", w1[k].get<double>());
            std::printf("%-22s %10.4f %12s  %-8s %12.4g %12.4g\n", swcl_metric_name(swcl_metric(k)), e[k], w,
                        swcl_metric_unit(swcl_metric(k)), row["real"]["median"].get<double>(),
                        row["sim"]["median"].get<double>());
        }
        std::printf("score E = %.4f (equal weights; Eq. 1); the tracks' own halves score %.4f against each other "
                    "(%.4f from that floor)   written to %s\n",
                    score, floor_score, floor_score - score, path.c_str());
    }
    if (a.plot) {
        const std::string png = plot_beside(path);
        if (!a.quiet) std::printf("plot: %s\n", png.c_str());
    }
    return 0;
}

}  // namespace

Command add_evaluate(CLI::App& program) {
    CLI::App* app = program.add_subcommand(
        "evaluate", "Run a scenario and score it against real tracks (the seven metrics of the noise paper, §3)");
    auto args = std::make_shared<EvaluateArgs>();
    add_options(*app, *args);
    app->footer("Writes the seven metrics' distances and PDFs and the score E to a JSON file;\n"
                "--plot runs $SWARMCL_PYTHON (python3) -m swarmcl.evaluation plot on it (pip install\n"
                "'swarmcl[plot]').  docs/evaluation.md explains the metrics.");
    return {app, [args] { return evaluate(*args); }};
}

}  // namespace swarmcl_cli

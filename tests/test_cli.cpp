// The `swarmcl` program end to end, run as a user runs it: exit status,
// messages, and the files it writes (read back by the formats' rules).
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <fcntl.h>

#include <nlohmann/json.hpp>
#include <swarmcl/swarmcl.h>

#include "data/tracks.hpp"
#include "scenario/scenario.hpp"
#include "io_test_support.hpp"

#ifndef SWARMCL_CLI
#error "SWARMCL_CLI must name the swarmcl binary"
#endif

namespace {

using namespace swarmcl;
using namespace swarmcl::iotest;

struct Result {
    int status = -1;  // exit status; -1 when it did not exit normally
    std::string out, err;
};

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Runs `swarmcl ARGS` in `cwd` with stdout and stderr captured in files.
Result cli(const std::string& args, const std::string& cwd) {
    const std::string out = cwd + "/.cli-stdout", err = cwd + "/.cli-stderr";
    const std::string cmd = "cd " + quote(cwd) + " && " + quote(SWARMCL_CLI) + " " + args + " >" + quote(out) +
                            " 2>" + quote(err) + " </dev/null";
    const int raw = std::system(cmd.c_str());
    Result r;
    r.status = (raw != -1 && WIFEXITED(raw)) ? WEXITSTATUS(raw) : -1;
    r.out = read_bytes(out);
    r.err = read_bytes(err);
    std::remove(out.c_str());
    std::remove(err.c_str());
    return r;
}

// A small field-model scenario: 24 agents in a box, curl noise and a goal.
const char* kTiny = R"({
  "name": "tiny",
  "seed": 9,
  "dt": 0.02,
  "steps": 50,
  "domain": {"min": [0, 0, 0], "max": [2, 2, 2]},
  "interaction_radius": 0.2,
  "agents": {"count": 24, "velocity": [0.1, 0, 0], "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
  "model": {
    "type": "field",
    "noise": {"type": "curl", "scale": 0.5, "gain": 0.2, "seed": 1, "domain_walls": true},
    "goal": {"center": [1, 1, 1.5], "speed": 0.5},
    "min_distance": 0.02
  },
  "output": {"dir": "results", "formats": ["csv", "npy", "vtp"], "every": 5}
})";

class Cli : public ::testing::Test {
protected:
    void SetUp() override { write_text(dir / "tiny.json", kTiny); }
    TempDir dir;
};

TEST_F(Cli, RunWritesEveryOutputAndRunJson) {
    const Result r = cli("run tiny.json --steps 6 --every 2 --out outdir", dir.path());
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("24 agents"), std::string::npos) << r.out;

    const std::string out = dir / "outdir";
    std::set<std::string> expected{"tiny.csv",        "tiny_positions.npy", "tiny_velocities.npy", "tiny.pvd",
                                   "run.json",        "tiny_000000.vtp",    "tiny_000002.vtp",     "tiny_000004.vtp",
                                   "tiny_000006.vtp"};
    EXPECT_EQ(list_dir(out), expected) << "no temporaries, nothing else";

    // frames = steps / every + 1, at steps 0, 2, 4, 6.
    const auto rows = parse_trajectory_csv(read_bytes(out + "/tiny.csv"));
    ASSERT_EQ(rows.size(), 4u * 24u);
    for (size_t k = 0; k < 4; ++k)
        for (size_t i = 0; i < 24; ++i) {
            EXPECT_EQ(rows[k * 24 + i].frame, 2 * k);
            EXPECT_EQ(rows[k * 24 + i].id, i);
        }
    // Frame 0 is the scenario's initial state, bit for bit.
    const Scenario s = parse_scenario(kTiny);
    const auto initial = s.initial_positions();
    for (size_t i = 0; i < 24; ++i)
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(rows[i].p[a], initial[3 * i + a]);
            EXPECT_EQ(rows[i].v[a], s.initial.velocity[a]);
        }
    // The swarm moved, and stayed sane.
    int moved = 0;
    for (size_t i = 0; i < 24; ++i)
        for (int a = 0; a < 3; ++a) {
            moved += rows[3 * 24 + i].p[a] != rows[i].p[a];
            EXPECT_TRUE(std::isfinite(rows[3 * 24 + i].p[a]));
        }
    EXPECT_GT(moved, 24);

    // .npy: the same numbers as the CSV.
    for (const char* name : {"tiny_positions.npy", "tiny_velocities.npy"}) {
        const Npy npy = read_npy(out + "/" + name);
        EXPECT_EQ(npy.descr, "<f4");
        EXPECT_EQ(npy.shape, (std::vector<uint64_t>{4, 24, 3})) << name;
        ASSERT_EQ(npy.data.size(), 4u * 24u * 12u);
        const auto v = as_vector<float>(npy.data);
        const bool positions = std::string(name) == "tiny_positions.npy";
        for (size_t r = 0; r < rows.size(); ++r)
            for (int a = 0; a < 3; ++a) EXPECT_EQ(v[3 * r + a], positions ? rows[r].p[a] : rows[r].v[a]);
    }
    // .vtp and .pvd.
    const auto pvd = read_pvd(out + "/tiny.pvd");
    ASSERT_EQ(pvd.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "tiny_%06zu.vtp", 2 * k);
        EXPECT_EQ(pvd[k].first, name);
        EXPECT_NEAR(pvd[k].second, 2 * k * double(0.02f), 1e-6);
        const Vtp vtp = read_vtp(out + "/" + name);
        EXPECT_EQ(vtp.points, 24u);
        ASSERT_EQ(vtp.arrays.count("Points"), 1u);
        const auto p = as_vector<float>(vtp.arrays.at("Points").bytes);
        ASSERT_EQ(p.size(), 72u);
        for (size_t i = 0; i < 24; ++i)
            for (int a = 0; a < 3; ++a) EXPECT_EQ(p[3 * i + a], rows[k * 24 + i].p[a]);
    }

    // run.json: the statistics, with --steps overriding the file's 50.
    const auto run = nlohmann::json::parse(read_bytes(out + "/run.json"));
    ASSERT_TRUE(run.is_object());
    ASSERT_TRUE(run.contains("device") && run["device"].is_string());
    EXPECT_FALSE(run["device"].get<std::string>().empty());
    EXPECT_EQ(run.at("agents"), 24);
    EXPECT_EQ(run.at("steps"), 6);
    EXPECT_EQ(run.at("frames"), 4);
    EXPECT_EQ(run.at("every"), 2);
    EXPECT_EQ(run.at("seed"), 9);
    EXPECT_EQ(run.at("scenario"), "tiny");
    ASSERT_TRUE(run.at("seconds").is_number());
    EXPECT_GE(run["seconds"].get<double>(), 0.0);
    ASSERT_TRUE(run.at("steps_per_second").is_number());
    EXPECT_GE(run["steps_per_second"].get<double>(), 0.0);
    EXPECT_EQ(run.at("parameters"), nlohmann::json::parse(kTiny)) << "the scenario as given";
    EXPECT_EQ(run.at("formats"), nlohmann::json::parse(R"(["csv", "npy", "vtp"])"));

    // The final figures agree with a brute-force reference on the last frame
    // as written to the CSV.
    ASSERT_TRUE(run.contains("final") && run["final"].is_object()) << run.dump(2);
    const auto& fin = run["final"];
    const CsvRow* last = &rows[3 * 24];
    double mean_speed = 0;
    std::vector<double> nn(24, INFINITY);
    int close_lo = 0, close_hi = 0;  // pairs surely / possibly below 0.999 * min_distance
    const double md = 0.999 * double(0.02f);
    for (size_t i = 0; i < 24; ++i) {
        mean_speed += std::sqrt(double(last[i].v[0]) * last[i].v[0] + double(last[i].v[1]) * last[i].v[1] +
                                double(last[i].v[2]) * last[i].v[2]) / 24;
        for (size_t j = 0; j < 24; ++j) {
            if (i == j) continue;
            const double dx = last[i].p[0] - last[j].p[0], dy = last[i].p[1] - last[j].p[1],
                         dz = last[i].p[2] - last[j].p[2];
            const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
            nn[i] = std::min(nn[i], d);
            if (j > i) close_lo += d < md * (1 - 1e-5), close_hi += d <= md * (1 + 1e-5);
        }
    }
    std::sort(nn.begin(), nn.end());
    EXPECT_NEAR(fin.at("mean_speed").get<double>(), mean_speed, 1e-5 * std::max(1.0, mean_speed));
    // Percentiles: an order statistic next to q * (n - 1).
    for (const auto& [key, q] : {std::pair<const char*, double>{"nearest_neighbor_p5", 0.05},
                                 {"nearest_neighbor_p50", 0.5}, {"nearest_neighbor_p95", 0.95}}) {
        const double x = fin.at(key).get<double>(), r = q * 23;
        const double lo = nn[size_t(std::floor(r))], hi = nn[size_t(std::ceil(r))];
        EXPECT_TRUE(x >= lo * (1 - 1e-5) - 1e-7 && x <= hi * (1 + 1e-5) + 1e-7) << key << " " << x << " not in [" << lo
                                                                                << ", " << hi << "]";
    }
    const double pairs = 24.0 * 23.0 / 2.0;
    EXPECT_GE(fin.at("close_pair_fraction").get<double>(), close_lo / pairs - 1e-12);
    EXPECT_LE(fin.at("close_pair_fraction").get<double>(), close_hi / pairs + 1e-12);
    ASSERT_TRUE(fin.at("mde_moved_fraction").is_number());
    EXPECT_GE(fin["mde_moved_fraction"].get<double>(), 0.0);
    EXPECT_LE(fin["mde_moved_fraction"].get<double>(), 1.0);
}

TEST_F(Cli, RunUsesTheScenarioOutputSettingsAndIsDeterministic) {
    // --steps 7 with the file's every = 5: frames at 0, 5, 7.
    const Result r = cli("run tiny.json --steps 7 --quiet", dir.path());
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_TRUE(r.out.empty()) << "--quiet: " << r.out;
    const std::string out = dir / "results";  // output.dir, relative to the working folder
    EXPECT_EQ(list_dir(out), (std::set<std::string>{"tiny.csv", "tiny_positions.npy", "tiny_velocities.npy", "tiny.pvd",
                                                      "run.json", "tiny_000000.vtp", "tiny_000005.vtp",
                                                      "tiny_000007.vtp"}));
    const auto run = nlohmann::json::parse(read_bytes(out + "/run.json"));
    EXPECT_EQ(run.at("steps"), 7);
    EXPECT_EQ(run.at("frames"), 3);
    EXPECT_EQ(run.at("every"), 5);
    EXPECT_EQ(read_npy(out + "/tiny_positions.npy").shape, (std::vector<uint64_t>{3, 24, 3}));

    // The same run again, into another folder and as CSV only: the same numbers.
    const Result again = cli("run tiny.json --steps 7 --quiet --format csv --out again", dir.path());
    ASSERT_EQ(again.status, 0) << again.err;
    EXPECT_EQ(list_dir(dir / "again"), (std::set<std::string>{"tiny.csv", "run.json"}));
    EXPECT_EQ(read_bytes(dir / "again/tiny.csv"), read_bytes(out + "/tiny.csv"));
}

TEST_F(Cli, ZeroStepsWritesOneFrame) {
    const Result r = cli("run tiny.json --steps 0 --format npy --out zero --quiet", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(read_npy(dir / "zero/tiny_positions.npy").shape, (std::vector<uint64_t>{1, 24, 3}));
    EXPECT_EQ(nlohmann::json::parse(read_bytes(dir / "zero/run.json")).at("frames"), 1);
}

TEST_F(Cli, Validate) {
    Result r = cli("validate tiny.json", dir.path());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("valid"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("24 agents"), std::string::npos) << r.out;

    write_text(dir / "bad.json", R"({"agents": {"count": 3}, "model": {"noise": {"scale": -2}}})");
    r = cli("validate bad.json", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("model.noise.scale: expected a number > 0"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("valid"), std::string::npos) << r.out;

    write_text(dir / "typo.json", "{\n  \"agents\": {\"count\": 3},\n  \"stpes\": 4\n}");
    r = cli("validate typo.json", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("stpes: unknown key"), std::string::npos) << r.err;

    write_text(dir / "broken.json", "{\n  \"agents\": {\"count\": 3}\n  \"steps\": 4\n}");
    r = cli("validate broken.json", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_AT_TOKEN(r.err, 3, 3, 9);  // the string "steps" where a ',' belongs

    r = cli("validate missing.json", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("missing.json"), std::string::npos) << r.err;

    for (const auto& e : fs::directory_iterator(std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios")) {
        r = cli("validate " + quote(e.path().string()), dir.path());
        EXPECT_EQ(r.status, 0) << e.path() << ": " << r.err;
    }
}

TEST_F(Cli, RunFailuresWriteNothing) {
    // A bad scenario: exit 1 with the key path, and no output folder.
    write_text(dir / "bad.json", R"({"agents": {"count": 3}, "dt": -1, "output": {"dir": "never"}})");
    Result r = cli("run bad.json", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("dt:"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never"));

    r = cli("run missing.json --out never", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_FALSE(fs::exists(dir / "never"));

    // An output folder that cannot be created.
    r = cli("run tiny.json --steps 2 --out /proc/swarmcl-nope", dir.path());
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("/proc/swarmcl-nope"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists("/proc/swarmcl-nope"));

    write_text(dir / "plain", "a regular file");
    r = cli("run tiny.json --steps 2 --out plain/sub", dir.path());
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("plain/sub"), std::string::npos) << r.err;
    EXPECT_EQ(read_bytes(dir / "plain"), "a regular file");

    // A device that does not exist.
    r = cli("run tiny.json --steps 2 --out nodev --device no-such-device-xyz", dir.path());
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_FALSE(r.err.empty());
    EXPECT_FALSE(fs::exists(dir / "nodev"));

    EXPECT_EQ(list_dir(dir.path()), (std::set<std::string>{"tiny.json", "bad.json", "plain"}));
}

TEST_F(Cli, UsageErrorsExitWith2) {
    Result r = cli("", dir.path());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("usage"), std::string::npos) << r.err;

    r = cli("fly tiny.json", dir.path());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("usage"), std::string::npos) << r.err;

    r = cli("run tiny.json --bogus", dir.path());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--bogus"), std::string::npos) << r.err;

    r = cli("run", dir.path());
    EXPECT_EQ(r.status, 2) << r.err;

    r = cli("run tiny.json --steps", dir.path());  // a missing value
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--steps"), std::string::npos) << r.err;

    r = cli("validate", dir.path());
    EXPECT_EQ(r.status, 2) << r.err;

    // Bad option values are refused before anything runs or is written.
    for (const char* bad : {"--steps -3", "--steps 12x", "--every 0", "--format gif", "--steps 99999999999"}) {
        r = cli(std::string("run tiny.json --out written ") + bad, dir.path());
        EXPECT_NE(r.status, 0) << bad;
        EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
            << bad << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "written")) << bad;
    }

    r = cli("--help", dir.path());
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("usage"), std::string::npos);
}

// `swarmcl COMMAND --help` for every command, `swarmcl help COMMAND` the
// same: the command's usage line and each of its options, on stdout, exit 0,
// nothing run or written.
TEST_F(Cli, EveryCommandHasHelp) {
    const std::map<std::string, std::vector<std::string>> options = {
        {"run", {"SCENARIO.json", "--steps", "--out", "--format", "--every", "--device", "--quiet", "--checkpoint-every"}},
        {"resume", {"DIR", "--device", "--quiet"}},
        {"evaluate", {"SCENARIO.json", "--tracks", "--columns", "--delimiter", "--unit-scale", "--window", "--warmup", "--steps",
                      "--every", "--bins", "--half-width", "--robust", "--out", "--plot", "--device", "--quiet",
                      "--runs", "--seed"}},
        {"fit", {"--tracks", "--ranges", "--method", "--generations"}},
        {"sweep", {"SCENARIO.json", "--grid", "--tracks", "--out"}},
        {"devices", {}},
        {"validate", {"SCENARIO.json"}},
    };
    // fit's own options come from Python; without one, its help says so and still succeeds.
    setenv("SWARMCL_PYTHON", "/no/such/python", 1);
    for (const auto& [command, names] : options) {
        for (const std::string& args : {command + " --help", command + " -h", "help " + command}) {
            SCOPED_TRACE(args);
            const Result r = cli(args, dir.path());
            EXPECT_EQ(r.status, 0) << r.err;
            EXPECT_NE(r.out.find("usage: swarmcl " + command + " "), std::string::npos) << r.out;
            for (const std::string& name : names) EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
            EXPECT_NE(r.out.find("--help"), std::string::npos) << r.out;
        }
    }
    const Result fit = cli("fit --help", dir.path());
    EXPECT_NE(fit.out.find("the options could not be listed"), std::string::npos) << fit.out;
    unsetenv("SWARMCL_PYTHON");
    EXPECT_EQ(list_dir(dir.path()), (std::set<std::string>{"tiny.json"})) << "--help runs nothing";

    // The program's own help lists every command.
    for (const std::string& args : {std::string("--help"), std::string("help")}) {
        const Result r = cli(args, dir.path());
        EXPECT_EQ(r.status, 0);
        EXPECT_NE(r.out.find("usage: swarmcl [OPTIONS] SUBCOMMAND"), std::string::npos) << r.out;
        for (const auto& [command, names] : options) EXPECT_NE(r.out.find("\n  " + command + " "), std::string::npos) << command;
        EXPECT_NE(r.out.find("--version"), std::string::npos) << r.out;
    }
}

TEST_F(Cli, VersionNamesTheProgramAndTheLibrary) {
    const Result r = cli("--version", dir.path());
    EXPECT_EQ(r.status, 0) << r.err;
    const std::string v = std::to_string(SWCL_VERSION_MAJOR) + "." + std::to_string(SWCL_VERSION_MINOR) + "." +
                          std::to_string(SWCL_VERSION_PATCH);
    EXPECT_EQ(r.out, "swarmcl " + v + " (library " + swcl_version_string() + ")\n");
    EXPECT_TRUE(r.err.empty()) << r.err;
}

// A bad command line: exit 2, the message names what is wrong, then the
// command's usage line; never a crash, nothing written.
TEST_F(Cli, BadArgumentsSayWhatIsWrong) {
    const std::map<std::string, std::string> cases = {
        {"run tiny.json --bogus", "--bogus"},
        {"evaluate tiny.json --tracks t.csv --bogus 3", "--bogus"},
        {"evaluate tiny.json --tracks t.csv --help-me", "--help-me"},
        {"resume", "DIR is required"},
        {"resume a b", "b"},
        {"devices extra", "extra"},
        {"validate a.json b.json", "b.json"},
        {"run tiny.json --format csv,,npy", "--format: empty export format name (expected csv, npy or vtp)"},
        {"run tiny.json --format gif", "--format: unknown export format 'gif' (expected csv, npy or vtp)"},
        {"run tiny.json --every", "--every"},
        {"run tiny.json --checkpoint-every 0", "--checkpoint-every: expected an integer >= 1, got '0'"},
        {"evaluate tiny.json --tracks t.csv --window 0.5", "--window: expected FROM,TO"},
        {"evaluate tiny.json --tracks t.csv --columns id,t", "--columns: expected five names"},
        {"evaluate tiny.json --tracks t.csv --delimiter ab", "--delimiter: expected one character"},
        {"evaluate tiny.json --tracks t.csv --unit-scale nan", "--unit-scale: expected a number, got 'nan'"},
        {"evaluate tiny.json --tracks t.csv --bins 0", "--bins: expected an integer >= 1, got '0'"},
        {"evaluate tiny.json --tracks t.csv --runs 0", "--runs: expected an integer >= 1, got '0'"},
        {"evaluate tiny.json --tracks t.csv --seed -3", "--seed: expected an integer >= 0, got '-3'"},
        {"evaluate tiny.json --tracks t.csv --seed 1.5", "--seed: expected an integer >= 0, got '1.5'"},
        {"help nope", "unknown command 'nope'"},
        {"fly", "unknown command 'fly'"},
    };
    for (const auto& [args, message] : cases) {
        SCOPED_TRACE(args);
        const Result r = cli(args, dir.path());
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_EQ(r.err.rfind("swarmcl: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("usage: swarmcl"), std::string::npos) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }
    EXPECT_EQ(list_dir(dir.path()), (std::set<std::string>{"tiny.json"}));
    // Options take "--flag=value" as well; one given twice takes its last value.
    const Result r = cli("run tiny.json --steps=2 --every=2 --format=csv --format=npy --out=eq --quiet --steps 4", dir.path());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(list_dir(dir / "eq"), (std::set<std::string>{"tiny_positions.npy", "tiny_velocities.npy", "run.json"}));
    EXPECT_EQ(nlohmann::json::parse(read_bytes(dir / "eq/run.json"))["steps"], 4);
}

TEST_F(Cli, InterruptRemovesUnfinishedOutputs) {
    // A run far too long to finish; once frame 5 is on disk (so the run is in
    // its step loop), SIGINT must stop it with exit 1 and remove every frame.
    // The waits below only bound a hang; the outcome does not depend on them.
    const std::string out = dir / "sig";
    const std::string cli_path = SWARMCL_CLI, err_path = dir / "sig.err";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> args{cli_path, "run", dir / "tiny.json", "--steps", "100000000", "--every", "1",
                                  "--format", "vtp", "--out", out, "--quiet"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, cli_path.c_str(), &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);

    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    int status = 0;
    bool exited = false;
    while (!fs::exists(out + "/tiny_000005.vtp") && std::chrono::steady_clock::now() < deadline) {
        if (waitpid(pid, &status, WNOHANG) == pid) {
            exited = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_FALSE(exited) << "the run ended on its own: " << read_bytes(err_path);
    ASSERT_TRUE(fs::exists(out + "/tiny_000005.vtp")) << "no frame 5 after 120 s";
    kill(pid, SIGINT);
    while (!exited && std::chrono::steady_clock::now() < deadline + std::chrono::seconds(60)) {
        exited = waitpid(pid, &status, WNOHANG) == pid;
        if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!exited) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        FAIL() << "SIGINT did not stop the run";
    }
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_NE(read_bytes(err_path).find("interrupted"), std::string::npos) << read_bytes(err_path);
    EXPECT_TRUE(list_dir(out).empty()) << list_dir(out).size() << " files left, e.g. " << *list_dir(out).begin();
}

// ---- checkpoints: --checkpoint-every and resume ------------------------------

// The outputs (not run.json, whose timings differ; not the checkpoints).
std::map<std::string, std::string> outputs(const std::string& dir) {
    std::map<std::string, std::string> files;
    for (const std::string& name : list_dir(dir))
        if (name != "run.json" && name.rfind("checkpoint", 0) != 0) files[name] = read_bytes(dir + "/" + name);
    return files;
}

void expect_same_outputs(const std::string& want_dir, const std::string& got_dir) {
    const auto want = outputs(want_dir), got = outputs(got_dir);
    ASSERT_FALSE(want.empty());
    ASSERT_EQ(want.size(), got.size());
    for (const auto& [name, bytes] : want) {
        ASSERT_TRUE(got.count(name)) << name << " missing";
        EXPECT_TRUE(got.at(name) == bytes) << name << " differs";
    }
}

TEST_F(Cli, ResumeFromACheckpointWritesTheUninterruptedOutputs) {
    // Not --quiet: the statistics of every frame are read (and their counters
    // reset) as the resumed run below does, so run.json's "final" agrees too.
    Result r = cli("run tiny.json --steps 50 --every 5 --out ref", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    // Checkpoints every 20 steps change no output; the last one (step 40) is kept.
    r = cli("run tiny.json --steps 50 --every 5 --out ck --checkpoint-every 20", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    expect_same_outputs(dir / "ref", dir / "ck");
    const auto names = list_dir(dir / "ck");
    EXPECT_TRUE(names.count("checkpoint.json"));
    EXPECT_TRUE(names.count("checkpoint-000000040.swcl"));
    EXPECT_TRUE(names.count("checkpoint-000000040.frames"));
    EXPECT_FALSE(names.count("checkpoint-000000020.swcl")) << "the older checkpoint is removed";
    const auto run = nlohmann::json::parse(read_bytes(dir / "ck/checkpoint.json"));
    EXPECT_EQ(run["done"], 40);
    EXPECT_EQ(run["steps"], 50);

    // As if the run had stopped after step 40: only the checkpoint is left.
    for (const std::string& name : names)
        if (name.rfind("checkpoint", 0) != 0) fs::remove(dir / ("ck/" + name));
    r = cli("resume ck", dir.path());
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("resumed at step 40"), std::string::npos) << r.out;
    expect_same_outputs(dir / "ref", dir / "ck");
    const auto meta = nlohmann::json::parse(read_bytes(dir / "ck/run.json"));
    EXPECT_EQ(meta["steps"], 50);
    EXPECT_EQ(meta["frames"], 11);
    EXPECT_EQ(meta["scenario"], "tiny");
    EXPECT_EQ(meta["final"], nlohmann::json::parse(read_bytes(dir / "ref/run.json"))["final"]);
}

TEST_F(Cli, InterruptKeepsTheCheckpointAndResumeFinishesTheRun) {
    const std::string args = " --steps 3000 --every 1000 --format csv,npy --quiet";
    Result r = cli("run tiny.json --out ref" + args, dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    // Stopped by SIGINT once a checkpoint exists (if the run is done by then,
    // the resume below starts from its last checkpoint all the same).
    const std::string out = dir / "sig";
    const std::string cli_path = SWARMCL_CLI, err_path = dir / "sig.err";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> argv_s{cli_path, "run", dir / "tiny.json", "--steps", "3000", "--every", "1000",
                                    "--format", "csv,npy", "--quiet", "--out", out, "--checkpoint-every", "10"};
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, cli_path.c_str(), &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    int status = 0;
    bool exited = false;
    while (!fs::exists(out + "/checkpoint.json") && std::chrono::steady_clock::now() < deadline) {
        if ((exited = waitpid(pid, &status, WNOHANG) == pid)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (!exited) {
        kill(pid, SIGINT);
        waitpid(pid, &status, 0);
    }
    ASSERT_TRUE(WIFEXITED(status)) << read_bytes(err_path);
    if (WEXITSTATUS(status) != 0) {
        EXPECT_EQ(WEXITSTATUS(status), 1);
        EXPECT_NE(read_bytes(err_path).find("swarmcl resume"), std::string::npos) << read_bytes(err_path);
        for (const std::string& name : list_dir(out)) EXPECT_EQ(name.rfind("checkpoint", 0), 0u) << name << " left";
    }
    ASSERT_TRUE(fs::exists(out + "/checkpoint.json"));
    r = cli("resume sig --quiet", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    expect_same_outputs(dir / "ref", out);
}

TEST_F(Cli, ResumeRefusesWhatIsNotACheckpoint) {
    Result r = cli("resume", dir.path());
    EXPECT_EQ(r.status, 2) << r.err;
    r = cli("resume nowhere", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("cannot resume"), std::string::npos) << r.err;
    r = cli("run tiny.json --steps 20 --every 5 --out ck --quiet --checkpoint-every 7", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    r = cli("run tiny.json --checkpoint-every 0", dir.path());
    EXPECT_EQ(r.status, 2);
    // A flipped byte in the swarm checkpoint, then in the frames.
    std::string swarm = read_bytes(dir / "ck/checkpoint-000000014.swcl");
    ASSERT_FALSE(swarm.empty());
    swarm[swarm.size() / 2] ^= 1;
    write_text(dir / "ck/checkpoint-000000014.swcl", swarm);
    r = cli("resume ck --quiet", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("checksum mismatch"), std::string::npos) << r.err;
    swarm[swarm.size() / 2] ^= 1;
    write_text(dir / "ck/checkpoint-000000014.swcl", swarm);
    std::string frames = read_bytes(dir / "ck/checkpoint-000000014.frames");
    write_text(dir / "ck/checkpoint-000000014.frames", frames.substr(0, frames.size() - 9));
    r = cli("resume ck --quiet", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("checksum mismatch"), std::string::npos) << r.err;
    write_text(dir / "ck/checkpoint-000000014.frames", frames);
    write_text(dir / "tiny.json", std::string(kTiny) + " ");
    r = cli("resume ck --quiet", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("changed since the run began"), std::string::npos) << r.err;
    write_text(dir / "ck/checkpoint.json", "{\"format\": \"something else\"}");
    r = cli("resume ck --quiet", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("not a swarmcl run checkpoint"), std::string::npos) << r.err;
    // A "format" that is not a string (fuzzing finding: nlohmann's type_error escaped).
    write_text(dir / "ck/checkpoint.json", "{\"format\": 1}");
    r = cli("resume ck --quiet", dir.path());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("not a swarmcl run checkpoint"), std::string::npos) << r.err;
}

TEST_F(Cli, DevicesListsAtLeastOne) {
    const Result r = cli("devices", dir.path());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.rfind("0 ", 0), 0u) << r.out;
    EXPECT_TRUE(r.out.find("CPU") != std::string::npos || r.out.find("GPU") != std::string::npos) << r.out;
}

// `swarmcl evaluate`: a run scored against its own recorded trajectory (the
// same positions on a clock 50x slower: z-scoring removes the scale, so
// every distance is zero up to a sample rounding across a bin edge), then
// against other tracks, deterministically; and its errors.
TEST_F(Cli, EvaluateScoresARunAgainstItsOwnRecordingAsIdentical) {
    const Result run = cli("run tiny.json --steps 40 --every 1 --format csv --out rec --quiet", dir.path());
    ASSERT_EQ(run.status, 0) << run.err;
    // The recorder's CSV: id,frame,P.x,P.y,P.z (frames count as seconds here).
    const Result r = cli("evaluate tiny.json --tracks rec/tiny.csv --columns id,frame,P.x,P.y,P.z --steps 40 "
                         "--every 1 --out eval.json",
                         dir.path());
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("score E"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(read_bytes(dir / "eval.json"));
    EXPECT_EQ(j["frames"], 41);
    EXPECT_EQ(j["every"], 1);
    ASSERT_EQ(j["metrics"].size(), 7u);
    for (const auto& [name, m] : j["metrics"].items()) {
        EXPECT_EQ(m["real"]["count"], m["sim"]["count"]) << name;
        EXPECT_EQ(m["real"]["pdf"].size(), 50u) << name;
        EXPECT_LT(m["distance"].get<double>(), 0.02) << name;
        EXPECT_TRUE(m["real"].contains("median") && m["real"].contains("mad")) << name;
    }
    EXPECT_GT(j["score"].get<double>(), 0.99);
    // ... while the Wasserstein-1 distances, in the metrics' units, see the
    // clock: the same nearest distances (m), speeds 50x slower (m/s).
    const auto& d = j["metrics"]["nearest_distance"];
    EXPECT_EQ(d["unit"], "m");
    EXPECT_LT(d["wasserstein"].get<double>(), 1e-4 * d["sim"]["mean"].get<double>());
    const auto& v = j["metrics"]["speed"];
    EXPECT_EQ(v["unit"], "m/s");
    EXPECT_NEAR(v["wasserstein"].get<double>(), (1.0 - 1.0 / 50.0) * v["sim"]["mean"].get<double>(),
                1e-3 * v["sim"]["mean"].get<double>());
    EXPECT_NEAR(v["real"]["median"].get<double>() * 50.0, v["sim"]["median"].get<double>(),
                1e-3 * v["sim"]["median"].get<double>());
    EXPECT_NE(r.out.find("W1"), std::string::npos) << r.out;
    EXPECT_EQ(j["pdf"]["standardise"], "mean_sigma");
    const Result robust = cli("evaluate tiny.json --tracks rec/tiny.csv --columns id,frame,P.x,P.y,P.z --steps 40 "
                              "--every 1 --robust --out robust.json --quiet",
                              dir.path());
    ASSERT_EQ(robust.status, 0) << robust.err;
    const auto jr = nlohmann::json::parse(read_bytes(dir / "robust.json"));
    EXPECT_EQ(jr["pdf"]["standardise"], "median_mad");
    // Identical up to the CSV's 9 digits, which third differences (jerk)
    // amplify: z-scored by a MAD (narrower than σ for these long tails) a
    // few more jerk samples cross a bin edge (E_jerk 0.096 measured).
    EXPECT_GT(jr["score"].get<double>(), 0.97);
    for (const auto& [name, m] : jr["metrics"].items())
        EXPECT_LT(m["distance"].get<double>(), name == "jerk" ? 0.15 : 0.05) << name;
}

// --runs N --seed S: N runs (seeds S, S+1, ...) as the worlds of one swarm,
// their samples pooled; one run with --seed 9 is the scenario's own run
// (tiny.json's seed is 9), other seeds are other runs.
TEST_F(Cli, EvaluatePoolsRunsFromAGivenSeed) {
    const auto tracks = swarmcl::synthetic_tracks(8, 120, 0.02, 0.5f, 4);
    write_text(dir / "tracks.csv", swarmcl::tracks_to_csv(tracks));
    auto eval = [&](const std::string& extra, const std::string& out) {
        const Result r = cli("evaluate tiny.json --tracks tracks.csv --warmup 10 --steps 40 --quiet --out " + out +
                                 " " + extra,
                             dir.path());
        EXPECT_EQ(r.status, 0) << r.err;
        auto j = nlohmann::json::parse(read_bytes(dir / out));
        j.erase("seconds");
        return j;
    };
    const auto own = eval("", "own.json"), nine = eval("--seed 9", "nine.json"), ten = eval("--seed 10", "ten.json");
    EXPECT_EQ(own["runs"], 1);
    EXPECT_EQ(own["first_seed"], 9);
    EXPECT_EQ(own["metrics"], nine["metrics"]);
    EXPECT_NE(own["metrics"], ten["metrics"]);
    const auto three = eval("--runs 3 --seed 9", "three.json");
    EXPECT_EQ(three["runs"], 3);
    EXPECT_EQ(three["frames"], own["frames"]);  // frames a run
    for (const auto& [name, m] : three["metrics"].items()) {
        // Each run's samples, one after the other (nearest neighbours within a run).
        EXPECT_EQ(m["sim"]["count"].get<int64_t>(), 3 * own["metrics"][name]["sim"]["count"].get<int64_t>()) << name;
    }
    EXPECT_NE(three["score"], own["score"]);
}

TEST_F(Cli, EvaluateIsDeterministicAndRefusesBadInput) {
    const auto tracks = swarmcl::synthetic_tracks(8, 120, 0.02, 0.5f, 4);
    write_text(dir / "tracks.csv", swarmcl::tracks_to_csv(tracks));
    const Result a = cli("evaluate tiny.json --tracks tracks.csv --window 0.5,1 --warmup 10 --out a.json --quiet",
                         dir.path());
    ASSERT_EQ(a.status, 0) << a.err;
    const Result b = cli("evaluate tiny.json --tracks tracks.csv --window 0.5,1 --warmup 10 --out b.json --quiet",
                         dir.path());
    ASSERT_EQ(b.status, 0) << b.err;
    auto ja = nlohmann::json::parse(read_bytes(dir / "a.json"));
    auto jb = nlohmann::json::parse(read_bytes(dir / "b.json"));
    EXPECT_EQ(ja["every"], 1);  // the tracks' 0.02 s frames over dt 0.02
    ja.erase("seconds"), jb.erase("seconds");
    EXPECT_EQ(ja, jb);
    // The same tracks with ';' and with tabs between the fields.
    std::string text = swarmcl::tracks_to_csv(tracks), semi = text, tabs = text;
    std::replace(semi.begin(), semi.end(), ',', ';');
    std::replace(tabs.begin(), tabs.end(), ',', '\t');
    write_text(dir / "semi.csv", semi);
    write_text(dir / "tabs.csv", tabs);
    for (const auto& [file, flag] : {std::pair{"semi.csv", "';'"}, std::pair{"tabs.csv", "tab"}}) {
        const Result r = cli(std::string("evaluate tiny.json --tracks ") + file + " --delimiter " + flag +
                                 " --window 0.5,1 --warmup 10 --out other.json --quiet",
                             dir.path());
        ASSERT_EQ(r.status, 0) << file << r.err;
        auto jo = nlohmann::json::parse(read_bytes(dir / "other.json"));
        jo.erase("seconds");
        jo["tracks"] = ja["tracks"];
        EXPECT_EQ(jo, ja) << file;
    }
    const Result wrong = cli("evaluate tiny.json --tracks semi.csv --out w.json --quiet", dir.path());
    EXPECT_EQ(wrong.status, 1);  // one column named "id;time;x;y;z": no "id"
    EXPECT_FALSE(fs::exists(dir / "w.json"));
    const double score = ja["score"];
    EXPECT_TRUE(std::isfinite(score) && score < 1.0) << score;
    // The data's floor: the window's halves (0.5-0.75, 0.75-1) scored
    // against each other, as the C API scores them.
    {
        swcl_dataset_desc d = swcl_dataset_desc_default();
        const std::string csv = dir / "tracks.csv";
        swcl_metrics h1{}, h2{};
        ASSERT_EQ(swcl_metrics_from_csv(csv.c_str(), &d, 0.5, 0.75, &h1), SWCL_OK);
        ASSERT_EQ(swcl_metrics_from_csv(csv.c_str(), &d, 0.75, 1.0, &h2), SWCL_OK);
        double e[SWCL_METRIC_COUNT], floor_score = 0;
        ASSERT_EQ(swcl_metrics_distances(h1, h2, nullptr, e, SWCL_METRIC_COUNT), SWCL_OK);
        ASSERT_EQ(swcl_score(e, SWCL_METRIC_COUNT, nullptr, &floor_score), SWCL_OK);
        EXPECT_EQ(ja["data_floor"]["score"].get<double>(), floor_score);
        EXPECT_LT(floor_score, 1.0);
        swcl_metrics_destroy(h1);
        swcl_metrics_destroy(h2);
    }

    const Result no_tracks = cli("evaluate tiny.json", dir.path());
    EXPECT_EQ(no_tracks.status, 2);
    EXPECT_NE(no_tracks.err.find("--tracks"), std::string::npos) << no_tracks.err;
    const Result bad_window = cli("evaluate tiny.json --tracks tracks.csv --window 0.7,0.2 --out c.json", dir.path());
    EXPECT_EQ(bad_window.status, 1);
    EXPECT_NE(bad_window.err.find("from < to"), std::string::npos) << bad_window.err;
    const Result bad_column = cli("evaluate tiny.json --tracks tracks.csv --columns id,t,x,y,z --out c.json", dir.path());
    EXPECT_EQ(bad_column.status, 1);
    EXPECT_NE(bad_column.err.find("\"t\""), std::string::npos) << bad_column.err;
    EXPECT_FALSE(fs::exists(dir / "c.json"));

    // --plot hands the JSON to Python; without one, a clear error and the
    // JSON (complete) stays.
    setenv("SWARMCL_PYTHON", "/no/such/python", 1);
    const Result no_python = cli("evaluate tiny.json --tracks tracks.csv --out d.json --plot --quiet", dir.path());
    unsetenv("SWARMCL_PYTHON");
    EXPECT_EQ(no_python.status, 1);
    EXPECT_NE(no_python.err.find("--plot"), std::string::npos) << no_python.err;
    EXPECT_TRUE(fs::exists(dir / "d.json"));
}

TEST_F(Cli, FitHandsOverToPythonAndSaysSoWhenItCannot) {
    setenv("SWARMCL_PYTHON", "/no/such/python", 1);
    const Result missing = cli("fit tiny.json --tracks t.csv --ranges r.json", dir.path());
    unsetenv("SWARMCL_PYTHON");
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.err.find("/no/such/python"), std::string::npos) << missing.err;
    EXPECT_NE(missing.err.find("swarmcl[fit]"), std::string::npos) << missing.err;
}

}  // namespace

// Writes the generated part of the fuzz seed corpora, bench/fuzz/corpus/<target>/
// (committed; rerun after a format change):  fuzz_make_seeds <corpus dir>.
// Checkpoints are saved from small swarms of the example scenarios (needs an
// OpenCL device: PoCL is enough); datasets, tracks and the CLI's run
// checkpoint files come from the library's own writers.  The first byte of a
// seed is the target's mode byte (see each bench/fuzz/fuzz_<target>.cpp).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "../../cli/run_checkpoint.hpp"
#include "data/dataset.hpp"
#include "data/tracks.hpp"
#include "device/context.hpp"
#include "models/swarm_checkpoint.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/scenario.hpp"

namespace fs = std::filesystem;
using namespace swarmcl;

namespace {

void put(const fs::path& file, const std::string& bytes) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << bytes;
    std::printf("%s (%zu bytes)\n", file.string().c_str(), bytes.size());
}

std::string slurp(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: fuzz_make_seeds CORPUS_DIR\n");
        return 2;
    }
    const fs::path out = argv[1];
    const std::string examples = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/";

    // Tracks: the writer's CSV, and the other time formats by hand.
    put(out / "tracks_csv/synthetic.csv", std::string(2, '\0') + tracks_to_csv(synthetic_tracks(2, 6, 0.01, 0.5f, 1)));
    put(out / "tracks_csv/datetime.csv",
        std::string("\3\0", 2) + "id,time,x,y,z\na,2024-05-01 10:00:00.000,1,2,3\na,2024-05-01 10:00:00.010,1.1,2,3\n"
                               "a,2024-05-01T10:00:00.020,1.2,2,3\na,2024-05-01 10:00:00.040,1.3,2.1,3\n");
    put(out / "tracks_csv/frames_semicolon.csv",
        std::string{char(2 | 4 | (1 << 3) | (1 << 5)), char(1 | 4)} + "id;time;x;y;z\n7;1;0;0;0\n7;2;0.1;0;0\n7;3;0.2;0;0\n7;5;0.3;0;0\n"
                                                      "8;1;1;1;1\n8;2;1;1.1;1\n8;3;1;1.2;1\n");
    put(out / "tracks_csv/by_index.csv",
        std::string{char(0x80 | 1), char(2 | 8)} + "a,b,c,d,e\n1,0.0,5,5,5\n1,0.1,5,5,6\n1,0.2,5,5,7\n");

    // Dataset: checksum as written (mode 0) and rewritten by the target (mode 1).
    const std::string ds = dataset_to_bytes(synthetic_dataset({16, 4, 3}));
    put(out / "dataset/k16_g4", std::string(1, '\0') + ds);
    put(out / "dataset/k16_g4_fix", std::string(1, '\1') + ds);

    // Checkpoints of every model, 8 agents after 3 steps.
    auto ctx = std::make_shared<Context>("", "");
    for (const char* name : {"aggregation", "path_aggregation", "force_moon_5k", "energy_aggregation_37",
                             "baseline_bswarm"}) {
        Scenario s = load_scenario(examples + name + ".json");
        s.swarm.agent_count = 8;
        s.swarm.capacity = 8;
        s.initial.kind = InitialDistribution::Kind::Uniform;
        s.initial.points.clear();
        auto swarm = make_swarm(ctx, s);
        swarm->step(3);
        const std::string bytes = swarm_checkpoint_bytes(*swarm);
        put(out / "checkpoint" / name, std::string(1, '\1') + bytes);
        put(out / "checkpoint" / (std::string(name) + "_nocrc"), std::string(1, '\0') + bytes);
    }

    // The CLI's run checkpoint: checkpoint.json and a frames file of 2 frames of 3 agents.
    const fs::path tmp = fs::temp_directory_path() / "swarmcl_fuzz_seeds";
    fs::create_directories(tmp);
    cli::RunCheckpoint run;
    run.scenario_file = "aggregation.json";
    run.scenario_absolute = (tmp / "aggregation.json").string();
    run.scenario_crc32 = 12345;
    run.out_dir = tmp.string();
    run.device = "cpu";
    run.steps = 100;
    run.every = 10;
    run.formats = 3;
    run.checkpoint_every = 20;
    run.done = 40;
    run.swarm_file = "checkpoint-40.swcl";
    run.frames_file = "checkpoint-40.frames";
    std::vector<cli::Frame> frames(2);
    for (uint32_t f = 0; f < 2; ++f) {
        frames[f].frame = f;
        frames[f].time = 0.1 * f;
        frames[f].pos = {0, 1, 2, 3, 4, 5, 6, 7, 8};
        frames[f].vel = {1, 1, 1, 2, 2, 2, 3, 3, 3};
    }
    cli::write_run_checkpoint(run, frames, 3, "", "");
    // The seed names no folder of this machine (tests check tracked files for one).
    nlohmann::json seed = nlohmann::json::parse(slurp(tmp / "checkpoint.json"));
    seed["out_dir"] = "out/run";
    seed["scenario_absolute"] = "examples/scenarios/aggregation.json";
    put(out / "run_checkpoint/checkpoint.json", std::string(1, '\0') + seed.dump(2) + "\n");
    const std::string fr = slurp(tmp / run.frames_file);
    put(out / "run_checkpoint/frames", std::string(1, char(0x81)) + fr);
    put(out / "run_checkpoint/frames_nocrc", std::string(1, char(0x80)) + fr);
    fs::remove_all(tmp);

    // OBJ: small meshes the example does not use (the example is a seed too).
    put(out / "obj/quad_groups.obj",
        "# a quad and a triangle in two groups\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
        "g first\nf 1/1/1 2/1/1 3/1/1 4/1/1\ng second\nf -1 -2 -3\n");
    put(out / "obj/tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    return 0;
}

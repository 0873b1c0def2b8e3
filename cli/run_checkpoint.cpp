#include "run_checkpoint.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <swarmcl/swarmcl.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"

namespace swarmcl::cli {
namespace {

constexpr uint32_t kRunCheckpointVersion = 1;
constexpr uint32_t kFramesSectionVersion = 1;

void write_text(const std::string& path, const std::string& text) {
    AtomicFile f(path);
    f.write(text);
    f.commit();
}

}  // namespace

void write_run_checkpoint(const RunCheckpoint& run, const std::vector<Frame>& frames, uint32_t agents,
                          const std::string& previous_swarm_file, const std::string& previous_frames_file) {
    // Frames: one section FRMS in the checkpoint container (CRC-32 checked).
    ByteWriter w;
    w.u32(agents);
    w.u64(frames.size());
    for (const Frame& f : frames) {
        w.u32(f.frame);
        w.f64(f.time);
        for (float v : f.pos) w.f32(v);
        for (float v : f.vel) w.f32(v);
    }
    CheckpointSection s;
    s.tag = section_tag("FRMS");
    s.version = kFramesSectionVersion;
    s.bytes = w.take();
    write_checkpoint_file(run.out_dir + "/" + run.frames_file, checkpoint_to_bytes({s}));

    nlohmann::json j;
    j["format"] = "swarmcl run checkpoint";
    j["version"] = kRunCheckpointVersion;
    j["scenario_file"] = run.scenario_file;
    j["scenario_absolute"] = run.scenario_absolute;
    j["scenario_crc32"] = run.scenario_crc32;
    j["out_dir"] = run.out_dir;
    j["device"] = run.device;
    j["steps"] = run.steps;
    j["every"] = run.every;
    j["formats"] = run.formats;
    j["checkpoint_every"] = run.checkpoint_every;
    j["done"] = run.done;
    j["swarm_file"] = run.swarm_file;
    j["frames_file"] = run.frames_file;
    write_text(run.out_dir + "/checkpoint.json", j.dump(2) + "\n");
    // Only now are the previous files unnamed.
    for (const std::string& old : {previous_swarm_file, previous_frames_file})
        if (!old.empty() && old != run.swarm_file && old != run.frames_file)
            std::remove((run.out_dir + "/" + old).c_str());
}

RunCheckpoint read_run_checkpoint(const std::string& dir) {
    const std::string path = dir + "/checkpoint.json";
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(Status::Io, "'" + path + "' cannot be read (was the run started with --checkpoint-every?)");
    std::ostringstream text;
    text << in.rdbuf();
    RunCheckpoint r = parse_run_checkpoint(text.str(), path);
    r.out_dir = dir;  // where it is now (the folder may have moved)
    return r;
}

RunCheckpoint parse_run_checkpoint(const std::string& text, const std::string& path) {
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    auto bad = [&](const std::string& why) { fail(Status::Parse, "'" + path + "': " + why); };
    if (!j.is_object() || !j.contains("format") || !j["format"].is_string() ||
        j["format"].get<std::string>() != "swarmcl run checkpoint")
        bad("not a swarmcl run checkpoint");
    if (!j.contains("version") || !j["version"].is_number_unsigned() || j["version"] != kRunCheckpointVersion)
        bad("unknown version (this swarmcl reads version " + std::to_string(kRunCheckpointVersion) + ")");
    RunCheckpoint r;
    auto str = [&](const char* key) {
        if (!j.contains(key) || !j[key].is_string()) bad(std::string("'") + key + "' is missing or not a string");
        return j[key].get<std::string>();
    };
    auto u32 = [&](const char* key) {
        if (!j.contains(key) || !j[key].is_number_unsigned() || j[key].get<uint64_t>() > 0xFFFFFFFFu)
            bad(std::string("'") + key + "' is missing or not a count");
        return j[key].get<uint32_t>();
    };
    r.scenario_file = str("scenario_file");
    r.scenario_absolute = str("scenario_absolute");
    r.scenario_crc32 = u32("scenario_crc32");
    r.device = str("device");
    r.steps = u32("steps");
    r.every = u32("every");
    r.formats = u32("formats");
    r.checkpoint_every = u32("checkpoint_every");
    r.done = u32("done");
    r.swarm_file = str("swarm_file");
    r.frames_file = str("frames_file");
    if (r.every == 0 || r.checkpoint_every == 0 || r.done > r.steps || r.formats == 0)
        bad("inconsistent settings");
    for (uint32_t bit = 1; bit != 0; bit <<= 1)  // every format one the library's table names
        if ((r.formats & bit) && !swcl_export_format_name(bit)) bad("inconsistent settings");
    for (const std::string* f : {&r.swarm_file, &r.frames_file})
        if (f->empty() || f->find('/') != std::string::npos) bad("a file name is not a plain name in the folder");
    return r;
}

uint32_t file_crc32(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(Status::Io, "'" + path + "' cannot be read");
    std::ostringstream s;
    s << in.rdbuf();
    const std::string bytes = s.str();
    return crc32_of(bytes.data(), bytes.size());
}

std::vector<Frame> read_frames(const std::string& path, uint32_t& agents) {
    std::string bytes;
    try {
        bytes = read_checkpoint_file(path);
    } catch (const Error& e) {
        fail(e.status(), "'" + path + "': " + e.what());
    }
    return frames_from_bytes(bytes, path, agents);
}

std::vector<Frame> frames_from_bytes(const std::string& bytes, const std::string& name, uint32_t& agents,
                                     bool verify_checksum) {
    std::vector<CheckpointSection> sections;
    try {
        sections = parse_checkpoint(bytes, verify_checksum);
    } catch (const Error& e) {
        fail(e.status(), "'" + name + "': " + e.what());
    }
    const CheckpointSection& s = find_section(sections, "FRMS", kFramesSectionVersion);
    ByteReader r(s.bytes, "frames '" + name + "'");
    agents = r.u32();
    const uint64_t per_frame = 12 + uint64_t(agents) * 24;
    const uint64_t count = r.count(size_t(per_frame));
    std::vector<Frame> frames(static_cast<size_t>(count));
    for (Frame& f : frames) {
        f.frame = r.u32();
        f.time = r.f64();
        f.pos.resize(size_t(agents) * 3);
        f.vel.resize(size_t(agents) * 3);
        for (float& v : f.pos) v = r.f32();
        for (float& v : f.vel) v = r.f32();
    }
    r.expect_end();
    return frames;
}

}  // namespace swarmcl::cli

// Checkpoints (issue 16 item 3, docs/checkpoint-format.md): a run of N steps
// equals, bit for bit, k steps + save + load in another context + N - k
// steps, for every model and the example scenarios (positions, velocities
// and the step statistics); a checkpoint of a loaded swarm is the same bytes;
// truncated, corrupted and bit-flipped files and absurd values are refused
// with Error(Parse) / SWCL_ERROR_PARSE and nothing else changes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "models/swarm_checkpoint.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/scenario.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

namespace {

using namespace swarmcl;
namespace fs = std::filesystem;

const std::string kExamples = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios";

// The context resumed runs are loaded into: not the one they were saved from.
std::shared_ptr<Context> other_context() {
    static std::shared_ptr<Context> ctx;
    return test::kept_context(ctx);
}

std::vector<float> read_all(Swarm& s, Attribute a) {
    std::vector<float> v(size_t(s.agent_count()) * 3);
    s.read(a, v.data(), s.agent_count());
    return v;
}

struct Outcome {
    std::vector<float> pos, vel;
    std::optional<StepStats> stats;
    uint64_t steps = 0;
};

Outcome outcome(Swarm& s) {
    Outcome o;
    o.pos = read_all(s, Attribute::Position);
    o.vel = read_all(s, Attribute::Velocity);
    o.stats = s.take_step_stats();
    o.steps = s.step_count();
    return o;
}

void expect_same(const Outcome& a, const Outcome& b) {
    ASSERT_EQ(a.pos.size(), b.pos.size());
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(std::memcmp(a.pos.data(), b.pos.data(), a.pos.size() * sizeof(float)), 0) << "positions differ";
    EXPECT_EQ(std::memcmp(a.vel.data(), b.vel.data(), a.vel.size() * sizeof(float)), 0) << "velocities differ";
    ASSERT_EQ(a.stats.has_value(), b.stats.has_value());
    if (a.stats) {
        EXPECT_EQ(a.stats->agents, b.stats->agents);
        EXPECT_EQ(a.stats->mde_moved_last, b.stats->mde_moved_last);
        EXPECT_EQ(a.stats->mde_moved_total, b.stats->mde_moved_total);
        EXPECT_EQ(a.stats->steps, b.stats->steps);
    }
}

// N steps straight against k + save + load (other context) + N - k; also a
// checkpoint of the loaded swarm is byte for byte the saved one.  Returns the
// checkpoint's size.
size_t check_resume(const std::function<std::shared_ptr<Swarm>(std::shared_ptr<Context>)>& make, uint32_t n_steps,
                    uint32_t k) {
    auto ctx = test::shared_context();
    auto straight = make(ctx);
    const std::vector<float> start = read_all(*straight, Attribute::Position);
    straight->step(n_steps);
    const Outcome want = outcome(*straight);
    EXPECT_NE(want.pos, start) << "nothing moved: the comparison would show nothing";

    auto first = make(ctx);
    first->step(k);
    const std::string bytes = swarm_checkpoint_bytes(*first);
    auto resumed = swarm_from_checkpoint(other_context(), decode_swarm_checkpoint(bytes));
    EXPECT_EQ(swarm_checkpoint_bytes(*resumed), bytes) << "a loaded swarm saves different bytes";
    resumed->step(n_steps - k);
    expect_same(want, outcome(*resumed));
    // The swarm it was saved from goes on as if nothing happened.
    first->step(n_steps - k);
    expect_same(want, outcome(*first));
    return bytes.size();
}

Scenario example(const std::string& name) {
    Scenario s = load_scenario(kExamples + "/" + name);
    // The force model's big swarms, smaller (as tests/test_model_seam.cpp).
    if (std::holds_alternative<ForceModelConfig>(s.model) && s.swarm.agent_count > 300)
        s.swarm.agent_count = s.swarm.capacity = 300;
    return s;
}

void check_example(const Scenario& s, uint32_t n_steps, uint32_t k) {
    check_resume([&](std::shared_ptr<Context> ctx) { return make_swarm(ctx, s); }, n_steps, k);
}

// ---- every model, through the example scenarios -------------------------------

TEST(CheckpointResume, FieldModelExamples) {
    for (const char* f : {"aggregation.json", "chasing.json"}) {
        SCOPED_TRACE(f);
        check_example(example(f), 40, 17);
    }
}

TEST(CheckpointResume, PathModelExamples) {
    for (const char* f : {"path_two_blocks.json", "path_aggregation.json", "path_phototaxis.json"}) {
        SCOPED_TRACE(f);
        check_example(example(f), 40, 17);
    }
}

TEST(CheckpointResume, PathModelMovingGoalAcrossWaypoints) {
    // Goals move every 90 steps: saved after the first move (step 90), the
    // second (180) happens after the load.
    const Scenario s = example("path_chasing.json");
    ASSERT_EQ(std::get<PathModelConfig>(s.model).waypoint_every, 90u);
    check_example(s, 200, 100);
}

TEST(CheckpointResume, PathModelGoalsSetByTheCaller) {
    const Scenario s = example("path_two_blocks.json");
    check_resume(
        [&](std::shared_ptr<Context> ctx) {
            auto swarm = make_swarm(ctx, s);
            auto* path = dynamic_cast<PathModel*>(swarm->behavior());
            std::vector<Goal> goals = path->config().groups[0].goals;
            for (Goal& g : goals) g.center[0] += 0.5f;
            path->set_goals(0, goals);
            return swarm;
        },
        30, 12);
}

TEST(CheckpointResume, PathModelChasingTargetMovedByTheCaller) {
    // The target ball (a goal and a boundary of Eq. 2) moved through the API
    // before the save: its place, cost field and noise come back with it.
    const Scenario s = example("path_chasing.json");
    ASSERT_FALSE(std::get<PathModelConfig>(s.model).targets.empty());
    check_resume(
        [&](std::shared_ptr<Context> ctx) {
            auto swarm = make_swarm(ctx, s);
            auto* path = dynamic_cast<PathModel*>(swarm->behavior());
            auto c = path->config().targets[0].center;
            c[0] += 0.7f;
            path->set_target(0, c);
            return swarm;
        },
        30, 12);
}

TEST(CheckpointResume, ForceModelKeyframesAndPath) {
    // The horse gallops: keyframes every 6 steps with one topology (the
    // assignment is kept), repeating every 48 steps along a B-spline path.
    const Scenario s = example("force_horse_5k.json");
    const auto& c = std::get<ForceModelConfig>(s.model);
    ASSERT_EQ(c.keyframe_period, 48u);
    ASSERT_FALSE(c.path.empty());
    check_example(s, 60, 23);
}

TEST(CheckpointResume, ForceModelReassignsAfterLoad) {
    // Sphere, mammoth, shark (other topologies: each keyframe assigns anew
    // from the positions), brought forward to steps 20 and 45.
    Scenario s = example("force_sphere_mammoth_shark_5k.json");
    auto& c = std::get<ForceModelConfig>(s.model);
    ASSERT_EQ(c.keyframes.size(), 3u);
    c.keyframes[1].frame = 20;
    c.keyframes[2].frame = 45;
    check_example(s, 60, 30);
}

TEST(CheckpointResume, ForceModelMeshObstaclesAndTurn) {
    for (const char* f : {"force_mesh_hamlet.json", "force_shark_turn.json"}) {
        SCOPED_TRACE(f);
        check_example(example(f), 30, 11);
    }
}

TEST(CheckpointResume, EnergyModelExamples) {
    // Keypoints (per-agent goals are state), stimuli, the plain aggregation.
    for (const char* f : {"energy_heart.json", "energy_escaping.json", "energy_aggregation_37.json", "energy_mating.json"}) {
        SCOPED_TRACE(f);
        check_example(example(f), 40, 17);
    }
}

TEST(CheckpointResume, EnergyModelStimuliAndKeypointsSetByTheCaller) {
    const Scenario s = example("energy_star.json");
    check_resume(
        [&](std::shared_ptr<Context> ctx) {
            auto swarm = make_swarm(ctx, s);
            auto* e = dynamic_cast<EnergyModel*>(swarm->behavior());
            Stimulus st;
            st.kind = Stimulus::Kind::Startle;
            st.position = {0.2f, 0.1f, 0.0f};
            st.velocity = {-0.05f, 0.0f, 0.0f};
            e->set_stimuli({st});
            e->set_keypoints({{0.0f, 0.0f, 0.3f}, {0.3f, 0.0f, 0.3f}, {0.0f, 0.3f, 0.3f}}, true);
            return swarm;
        },
        30, 14);
}

TEST(CheckpointResume, PolicyModelExample) {
    // The shipped policy, its leader on a tour (the waypoint index is state).
    Scenario s = example("policy_roaming.json");
    s.swarm.agent_count = s.swarm.capacity = 120;
    check_example(s, 40, 17);
}

TEST(CheckpointResume, PolicyModelJoystickAndWaypointsPassed) {
    // Joystick controls set by the caller (state), and a navigation leader
    // that passes waypoints before and after the checkpoint.
    Scenario s = example("policy_roaming.json");
    s.swarm.agent_count = s.swarm.capacity = 60;
    check_resume(
        [&](std::shared_ptr<Context> ctx) {
            auto swarm = make_swarm(ctx, s);
            auto* p = dynamic_cast<PolicyModel*>(swarm->behavior());
            p->set_leader_controls({0.05f, 0.0f, 0.03f, 0.01f});
            return swarm;
        },
        30, 11);
    Scenario n = example("policy_roaming.json");
    n.swarm.agent_count = n.swarm.capacity = 60;
    auto& spec = std::get<PolicySpec>(n.model);
    spec.config.leader_mode = PolicyLeaderMode::Navigation;
    spec.config.waypoints = {{{1.0f, 0.0f, 0.0f, 0.6f}}, {{2.5f, 0.5f, 0.0f, 0.8f}}, {{4.0f, 2.0f, 0.0f, 1.0f}}};
    check_example(n, 60, 23);
}

TEST(CheckpointResume, BallisticSwarm) {
    check_resume(
        [](std::shared_ptr<Context> ctx) {
            auto swarm = std::make_shared<Swarm>(ctx, test::cube_config(64, -1, 1, 0.1f));
            swarm->write(Attribute::Position, test::random_points(50, -1, 1, 7).data(), 50);
            swarm->write(Attribute::Velocity, test::random_points(50, -0.3f, 0.3f, 8).data(), 50);
            return swarm;
        },
        25, 9);
}

TEST(CheckpointResume, SavedAfterANeighbourQueryAndAtStepZero) {
    // A query sorts the state into cell order between steps; a checkpoint at
    // step 0 has no step behind it.
    const Scenario s = example("aggregation.json");
    check_resume(
        [&](std::shared_ptr<Context> ctx) {
            auto swarm = make_swarm(ctx, s);
            std::vector<uint32_t> counts(swarm->agent_count());
            swarm->neighbor_count(0.1f, counts.data(), counts.size());
            return swarm;
        },
        12, 0);
}

TEST(CheckpointResume, AModelWithoutCheckpointHooksIsRefusedWhenSaved) {
    struct Still : Behavior {
        void advance(Swarm&, uint64_t) override {}
    };
    auto swarm = std::make_shared<Swarm>(test::shared_context(), test::cube_config(16, -1, 1, 0.1f));
    swarm->set_behavior(std::make_shared<Still>());
    try {
        swarm_checkpoint_bytes(*swarm);
        ADD_FAILURE() << "saved";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("cannot be saved"), std::string::npos) << e.what();
    }
}

// ---- files and the C API --------------------------------------------------------

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("swcl_ckpt_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    static int& counter() {
        static int c = 0;
        return c;
    }
};

std::string small_checkpoint() {
    const Scenario s = example("chasing.json");
    auto swarm = make_swarm(test::shared_context(), s);
    swarm->step(3);
    return swarm_checkpoint_bytes(*swarm);
}

void write_bytes(const fs::path& p, const std::string& bytes) {
    std::FILE* f = std::fopen(p.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
    std::fclose(f);
}

TEST(CheckpointCApi, SaveLoadAndStepThroughTheCApi) {
    TempDir dir;
    swcl_context_desc cd = swcl_context_desc_default();
    swcl_context ctx{}, ctx2{};
    ASSERT_EQ(swcl_context_create(&cd, &ctx), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_context_create(&cd, &ctx2), SWCL_OK) << swcl_last_error();
    swcl_scenario scn{};
    ASSERT_EQ(swcl_scenario_load((kExamples + "/chasing.json").c_str(), &scn), SWCL_OK) << swcl_last_error();
    swcl_swarm a{}, b{};
    ASSERT_EQ(swcl_scenario_create_swarm(scn, ctx, &a), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_scenario_create_swarm(scn, ctx, &b), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(a, 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_step(b, 4), SWCL_OK);
    const std::string path = (dir.path / "swarm.swcl").string();
    ASSERT_EQ(swcl_swarm_save(b, path.c_str()), SWCL_OK) << swcl_last_error();
    swcl_swarm c{};
    ASSERT_EQ(swcl_swarm_load(ctx2, path.c_str(), &c), SWCL_OK) << swcl_last_error();
    uint64_t steps = 0;
    ASSERT_EQ(swcl_swarm_step_count(c, &steps), SWCL_OK);
    EXPECT_EQ(steps, 4u);
    ASSERT_EQ(swcl_swarm_step(c, 6), SWCL_OK);
    uint32_t n = 0;
    ASSERT_EQ(swcl_swarm_agent_count(a, &n), SWCL_OK);
    std::vector<float> pa(3 * size_t(n)), pc(3 * size_t(n));
    ASSERT_EQ(swcl_swarm_read(a, SWCL_ATTRIBUTE_POSITION, pa.data(), n), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(c, SWCL_ATTRIBUTE_POSITION, pc.data(), n), SWCL_OK);
    EXPECT_EQ(std::memcmp(pa.data(), pc.data(), pa.size() * sizeof(float)), 0);
    // No temporary file is left beside it.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir.path)) files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 1u);

    // Bad arguments.
    EXPECT_EQ(swcl_swarm_save(b, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_load(ctx, nullptr, &c), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_load(ctx, path.c_str(), nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_save(b, (dir.path / "no" / "such" / "dir.swcl").c_str()), SWCL_ERROR_IO);
    const swcl_swarm before = c;
    EXPECT_EQ(swcl_swarm_load(ctx, (dir.path / "missing.swcl").c_str(), &c), SWCL_ERROR_IO);
    EXPECT_NE(std::string(swcl_last_error()).find("missing.swcl"), std::string::npos) << swcl_last_error();

    // A corrupted file: SWCL_ERROR_PARSE with the reason, *out and the
    // existing swarm untouched.
    std::string bytes;
    {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        ASSERT_NE(f, nullptr);
        char buf[4096];
        size_t got;
        while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.append(buf, got);
        std::fclose(f);
    }
    bytes[bytes.size() / 2] ^= 0x10;
    const fs::path bad = dir.path / "bad.swcl";
    write_bytes(bad, bytes);
    EXPECT_EQ(swcl_swarm_load(ctx, bad.c_str(), &c), SWCL_ERROR_PARSE);
    EXPECT_NE(std::string(swcl_last_error()).find("checksum mismatch"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(c.id, before.id);
    EXPECT_EQ(swcl_swarm_step(c, 1), SWCL_OK);
    // A failed save over an existing checkpoint leaves it as it was.
    const auto size_before = fs::file_size(path);
    swcl_swarm ballistic{};
    swcl_swarm_desc sd = swcl_swarm_desc_default();
    ASSERT_EQ(swcl_swarm_create(ctx, &sd, &ballistic), SWCL_OK);
    EXPECT_EQ(swcl_swarm_save(ballistic, (dir.path).c_str()), SWCL_ERROR_IO);  // a folder
    EXPECT_EQ(fs::file_size(path), size_before);

    swcl_swarm_destroy(a);
    swcl_swarm_destroy(b);
    swcl_swarm_destroy(c);
    swcl_swarm_destroy(ballistic);
    swcl_scenario_destroy(scn);
    swcl_context_destroy(ctx);
    swcl_context_destroy(ctx2);
}

// ---- refused files (parse only: no device) --------------------------------------

void expect_parse_error(const std::string& bytes, const std::string& fragment) {
    try {
        decode_swarm_checkpoint(bytes);
        ADD_FAILURE() << "accepted; expected an error containing '" << fragment << "'";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

// The sections of a valid checkpoint, changed by `edit`, written back with a
// correct checksum: what the checks behind the checksum must catch.
std::string resealed(const std::string& bytes, const std::function<void(std::vector<CheckpointSection>&)>& edit) {
    std::vector<CheckpointSection> s = parse_checkpoint(bytes);
    edit(s);
    return checkpoint_to_bytes(s);
}

CheckpointSection& section_of(std::vector<CheckpointSection>& s, const char (&tag)[5]) {
    for (auto& x : s)
        if (x.tag == section_tag(tag)) return x;
    throw std::runtime_error("no section");
}

void put_u64(std::string& b, size_t at, uint64_t v) {
    for (int i = 0; i < 8; ++i) b[at + size_t(i)] = char(uint8_t(v >> (8 * i)));
}

TEST(CheckpointRefused, EveryTruncation) {
    const std::string bytes = small_checkpoint();
    ASSERT_NO_THROW(decode_swarm_checkpoint(bytes));
    for (size_t len = 0; len < bytes.size(); ++len) {
        SCOPED_TRACE(len);
        EXPECT_THROW(decode_swarm_checkpoint(bytes.substr(0, len)), Error);
    }
    expect_parse_error(bytes.substr(0, 10), "shorter than a header");
    expect_parse_error(bytes.substr(0, bytes.size() - 1), "checksum mismatch");
    expect_parse_error(bytes + "x", "checksum mismatch");
}

TEST(CheckpointRefused, EveryBitFlip) {
    const std::string bytes = small_checkpoint();
    for (size_t bit = 0; bit < bytes.size() * 8; ++bit) {
        std::string b = bytes;
        b[bit / 8] = char(b[bit / 8] ^ (1 << (bit % 8)));
        try {
            decode_swarm_checkpoint(b);
            ADD_FAILURE() << "bit " << bit << " flipped was accepted";
        } catch (const Error& e) {
            ASSERT_EQ(e.status(), Status::Parse) << e.what();
        }
    }
}

TEST(CheckpointRefused, HeaderMagicVersionAndSections) {
    const std::string bytes = small_checkpoint();
    std::string b = bytes;
    b[0] = 'X';
    expect_parse_error(b, "bad magic");
    b = bytes;
    b[8] = 2;  // container version 2
    expect_parse_error(b, "container version 2");
    expect_parse_error(std::string(), "shorter than a header");
    expect_parse_error(resealed(bytes, [](auto& s) { section_of(s, "AGNT").version = 9; }),
                       "section AGNT has version 9");
    expect_parse_error(resealed(bytes, [](auto& s) { s.erase(s.begin() + 1); }), "section AGNT is missing");
    expect_parse_error(resealed(bytes, [](auto& s) { s.push_back(s[0]); }), "appears twice");
    expect_parse_error(resealed(bytes, [](auto& s) {
                           CheckpointSection x;
                           x.tag = section_tag("NEWS");
                           s.push_back(x);
                       }),
                       "unknown section NEWS");
    // A section count far above what any file holds.
    b = bytes;
    b[12] = char(0xFF), b[13] = char(0xFF);
    expect_parse_error(b, "checksum mismatch");  // the checksum is checked first
}

TEST(CheckpointRefused, AbsurdCountsBehindAValidChecksum) {
    const std::string bytes = small_checkpoint();
    // The agent count (after the u64 step counter) far beyond the bytes.
    expect_parse_error(resealed(bytes, [](auto& s) { put_u64(section_of(s, "AGNT").bytes, 8, uint64_t(1) << 60); }),
                       "does not fit");
    // More agents than the capacity (the bytes are there).
    expect_parse_error(resealed(bytes,
                                [](auto& s) {
                                    std::string& a = section_of(s, "AGNT").bytes;
                                    uint32_t cap = 0;
                                    std::memcpy(&cap, section_of(s, "SWRM").bytes.data(), 4);
                                    const uint64_t n = uint64_t(cap) + 1;
                                    a.resize(16);
                                    put_u64(a, 8, n);
                                    a.append(size_t(n) * 36, '\0');
                                }),
                       "exceed the capacity");
    // A vector count inside the model descriptor (the noise's boundaries).
    expect_parse_error(resealed(bytes,
                                [](auto& s) {
                                    std::string& m = section_of(s, "MODL").bytes;
                                    m.resize(m.size() / 2);
                                }),
                       "section MODL");
    expect_parse_error(resealed(bytes,
                                [](auto& s) {
                                    std::string& m = section_of(s, "MODL").bytes;
                                    put_u64(m, 0, uint64_t(1) << 62);  // the model name's length
                                }),
                       "does not fit");
    expect_parse_error(resealed(bytes,
                                [](auto& s) {
                                    ByteWriter w;
                                    w.string("flock");
                                    section_of(s, "MODL").bytes = w.take();
                                }),
                       "unknown model 'flock'");
    // A trailing byte in a section.
    expect_parse_error(resealed(bytes, [](auto& s) { section_of(s, "STAT").bytes += "x"; }), "unexpected bytes");
}

TEST(CheckpointRefused, ValuesThatMakeNoSwarm) {
    const std::string bytes = small_checkpoint();
    auto load = [](const std::string& b) { return swarm_from_checkpoint(other_context(), decode_swarm_checkpoint(b)); };
    auto expect_refused = [&](const std::string& b, const std::string& fragment) {
        try {
            load(b);
            ADD_FAILURE() << "accepted; expected '" << fragment << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::Parse) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    ASSERT_NO_THROW(load(bytes));
    // Two agents with one id: slot_of would be written out of order.
    expect_refused(resealed(bytes,
                            [](auto& s) {
                                std::string& a = section_of(s, "AGNT").bytes;
                                uint64_t n = 0;
                                std::memcpy(&n, a.data() + 8, 8);
                                const size_t ids = 16 + size_t(n) * 32;
                                std::memcpy(&a[ids], &a[ids + 4], 4);
                            }),
                   "not a permutation");
    // A NaN position.
    expect_refused(resealed(bytes,
                            [](auto& s) {
                                std::string& a = section_of(s, "AGNT").bytes;
                                const uint32_t nan = 0x7FC00000u;
                                std::memcpy(&a[16], &nan, 4);
                            }),
                   "not finite");
    // A swarm setting its constructor refuses (dt, after capacity, count,
    // seed, the domain and the radius).
    expect_refused(resealed(bytes,
                            [](auto& s) {
                                std::string& c = section_of(s, "SWRM").bytes;
                                const float dt = -1.0f;
                                std::memcpy(&c[16 + 24 + 4], &dt, 4);
                            }),
                   "dt must be");
    // Model state that does not fit the model (the field model keeps none).
    expect_refused(resealed(bytes, [](auto& s) { section_of(s, "MDST").bytes = "abc"; }), "unexpected bytes");
}

TEST(CheckpointRefused, RandomMutationsNeverCrash) {
    // A small stand-in for the fuzzer: random byte edits behind a valid
    // checksum either decode or are refused with Error(Parse).
    const std::string bytes = small_checkpoint();
    std::mt19937 rng(5);
    size_t refused = 0, accepted = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<CheckpointSection> s = parse_checkpoint(bytes);
        CheckpointSection& x = s[rng() % s.size()];
        if (x.bytes.empty()) continue;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) x.bytes[rng() % x.bytes.size()] = char(rng());
        if (rng() % 8 == 0) x.bytes.resize(rng() % (x.bytes.size() + 1));
        try {
            decode_swarm_checkpoint(checkpoint_to_bytes(s));
            ++accepted;
        } catch (const Error& e) {
            ASSERT_EQ(e.status(), Status::Parse) << e.what();
            ++refused;
        }
    }
    EXPECT_GT(refused, 0u);
    EXPECT_GT(accepted, 0u);  // edits of plain values (positions) parse
    // As the fuzzer sees it: raw byte edits anywhere, the checksum not checked.
    for (int trial = 0; trial < 3000; ++trial) {
        std::string b = bytes;
        const int edits = 1 + int(rng() % 6);
        for (int e = 0; e < edits; ++e) b[rng() % b.size()] = char(rng());
        if (rng() % 8 == 0) b.resize(rng() % (b.size() + 1));
        try {
            decode_swarm_checkpoint(b, /*verify_checksum=*/false);
        } catch (const Error& e) {
            ASSERT_EQ(e.status(), Status::Parse) << e.what();
        }
    }
}

}  // namespace

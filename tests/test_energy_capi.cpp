// FASTSWARM through the C API and scenario files: datasets from arrays, CSV,
// synthetic tracks and files; the energy model on a swarm with stimuli and
// keypoints; model.type "energy" in scenarios; bad input gives a status and a
// message and changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "c_enum_callers.h"
#include "data/tracks.hpp"
#include "swarmcl/swarmcl.h"

namespace {

class EnergyCapi : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx_), SWCL_OK) << swcl_last_error();
        swcl_dataset_desc dd = swcl_dataset_desc_default();
        ASSERT_EQ(swcl_dataset_synthetic(&dd, &data_), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        swcl_dataset_destroy(data_);
        for (auto s : swarms_) swcl_swarm_destroy(s);
        swcl_context_destroy(ctx_);
    }
    swcl_swarm make_swarm(uint32_t n) {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        d.capacity = 256;
        d.agent_count = n;
        d.seed = 3;
        for (int a = 0; a < 3; ++a) d.domain_min[a] = -0.3f, d.domain_max[a] = 0.3f;
        d.interaction_radius = 0.2f;
        d.dt = 0.01f;
        swcl_swarm s{};
        EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_OK) << swcl_last_error();
        swarms_.push_back(s);
        return s;
    }
    swcl_context ctx_{};
    swcl_dataset data_{};
    std::vector<swcl_swarm> swarms_;
};

std::string temp(const char* name) { return testing::TempDir() + "/" + name; }

}  // namespace

TEST_F(EnergyCapi, DefaultsAreThePapers) {
    const swcl_energy_model_desc d = swcl_energy_model_desc_default();
    EXPECT_EQ(d.struct_size, sizeof(d));
    EXPECT_FLOAT_EQ(d.rho, 2.5f);
    EXPECT_FLOAT_EQ(d.weights.rep, 1.0f);
    EXPECT_FLOAT_EQ(d.weights.cos, 0.05f);
    EXPECT_FLOAT_EQ(d.weights.noise, 0.2f);
    EXPECT_FLOAT_EQ(d.weights.env, 0.0f);
    EXPECT_FLOAT_EQ(d.danger_weights.oa, 0.0f);
    EXPECT_FLOAT_EQ(d.danger_weights.env, 2.0f);
    EXPECT_EQ(d.keep_out, 1);
    EXPECT_EQ(swcl_dataset_desc_default().k, 300u);
    swcl_dataset_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_dataset_get_info(data_, &info), SWCL_OK);
    EXPECT_EQ(info.samples, 300u);
    EXPECT_EQ(info.groups, 10u);
    EXPECT_DOUBLE_EQ(info.frame_time, 0.01);
}

TEST_F(EnergyCapi, DatasetsFromArraysCsvAndFiles) {
    const swarmcl::TrackSet set = swarmcl::synthetic_tracks(6, 30, 0.01, 0.5f, 9);
    std::vector<uint32_t> counts;
    std::vector<double> t;
    std::vector<float> xyz;
    for (const auto& tr : set.tracks) {
        counts.push_back(uint32_t(tr.t.size()));
        for (size_t k = 0; k < tr.t.size(); ++k) {
            t.push_back(tr.t[k]);
            for (int a = 0; a < 3; ++a) xyz.push_back(float(tr.p[k][a] * 100.0));  // centimetres
        }
    }
    swcl_dataset_desc dd = swcl_dataset_desc_default();
    dd.unit_scale = 0.01;
    dd.k = 50;
    dd.groups = 5;
    swcl_dataset from_arrays{};
    ASSERT_EQ(swcl_dataset_from_tracks(counts.data(), counts.size(), t.data(), xyz.data(), &dd, &from_arrays),
              SWCL_OK)
        << swcl_last_error();
    std::vector<float> v(150), a(150);
    ASSERT_EQ(swcl_dataset_read(from_arrays, v.data(), a.data(), 50), SWCL_OK);
    for (int i = 1; i < 50; ++i)
        EXPECT_LE(std::hypot(v[3 * i - 3], v[3 * i - 2], v[3 * i - 1]), std::hypot(v[3 * i], v[3 * i + 1], v[3 * i + 2]));
    EXPECT_EQ(swcl_dataset_read(from_arrays, v.data(), nullptr, 49), SWCL_ERROR_INVALID_ARGUMENT);

    // The same tracks as CSV in metres give the same dataset.
    const std::string csv = temp("energy_tracks.csv");
    std::ofstream(csv) << swarmcl::tracks_to_csv(set);
    dd.unit_scale = 1.0;
    dd.column_time = "time";
    swcl_dataset from_csv{};
    ASSERT_EQ(swcl_dataset_from_csv(csv.c_str(), &dd, &from_csv), SWCL_OK) << swcl_last_error();
    std::vector<float> v2(150);
    ASSERT_EQ(swcl_dataset_read(from_csv, v2.data(), nullptr, 50), SWCL_OK);
    for (int i = 0; i < 150; ++i) EXPECT_NEAR(v[i], v2[i], 1e-3f);

    // Save, load, compare; a damaged file is refused.
    const std::string file = temp("energy_dataset.swds");
    ASSERT_EQ(swcl_dataset_save(from_csv, file.c_str()), SWCL_OK) << swcl_last_error();
    swcl_dataset loaded{};
    ASSERT_EQ(swcl_dataset_load(file.c_str(), &loaded), SWCL_OK) << swcl_last_error();
    std::vector<float> v3(150);
    ASSERT_EQ(swcl_dataset_read(loaded, v3.data(), nullptr, 50), SWCL_OK);
    EXPECT_EQ(v2, v3);
    {
        std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(40);
        f.put('\x7f');
    }
    swcl_dataset bad{};
    EXPECT_EQ(swcl_dataset_load(file.c_str(), &bad), SWCL_ERROR_PARSE);
    EXPECT_NE(std::string(swcl_last_error()).find("checksum"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_dataset_load(temp("missing.swds").c_str(), &bad), SWCL_ERROR_IO);

    // Bad input: a short track, k = 0, an unknown column, NaN.
    uint32_t short_counts[1] = {2};
    EXPECT_EQ(swcl_dataset_from_tracks(short_counts, 1, t.data(), xyz.data(), &dd, &bad), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("3 or more"), std::string::npos) << swcl_last_error();
    swcl_dataset_desc k0 = dd;
    k0.k = 0;
    EXPECT_EQ(swcl_dataset_from_csv(csv.c_str(), &k0, &bad), SWCL_ERROR_INVALID_ARGUMENT);
    swcl_dataset_desc col = dd;
    col.column_x = "x_cm";
    EXPECT_EQ(swcl_dataset_from_csv(csv.c_str(), &col, &bad), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("x_cm"), std::string::npos) << swcl_last_error();
    xyz[7] = NAN;
    EXPECT_EQ(swcl_dataset_from_tracks(counts.data(), counts.size(), t.data(), xyz.data(), &dd, &bad),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_dataset_get_info(bad, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    swcl_dataset_destroy(from_arrays);
    swcl_dataset_destroy(from_csv);
    swcl_dataset_destroy(loaded);
    EXPECT_EQ(swcl_dataset_destroy(loaded), SWCL_ERROR_INVALID_HANDLE);
    std::remove(csv.c_str());
    std::remove(file.c_str());
}

TEST_F(EnergyCapi, ModelOnASwarmWithStimuliAndKeypoints) {
    swcl_swarm s = make_swarm(40);
    swcl_energy_model_desc d = swcl_energy_model_desc_default();
    // Not an energy model yet: the controls are refused.
    EXPECT_EQ(swcl_swarm_energy_set_stimuli(s, nullptr, 0), SWCL_ERROR_INVALID_ARGUMENT);
    const float kp[9] = {0.2f, 0, 0, 0, 0.2f, 0, -0.2f, 0, 0};
    d.keypoints = kp;
    d.keypoint_count = 1;  // fewer than 2
    EXPECT_EQ(swcl_swarm_energy_set_model(s, data_, &d), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("at least 2"), std::string::npos) << swcl_last_error();
    d.keypoint_count = 3;
    d.weights.user = 1.0f;
    ASSERT_EQ(swcl_swarm_energy_set_model(s, data_, &d), SWCL_OK) << swcl_last_error();
    std::vector<int32_t> goals(40);
    ASSERT_EQ(swcl_swarm_energy_get_goals(s, goals.data(), 40), SWCL_OK);
    for (int32_t g : goals) EXPECT_EQ(g, -1);
    ASSERT_EQ(swcl_swarm_step(s, 5), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_energy_get_goals(s, goals.data(), 40), SWCL_OK);
    for (int32_t g : goals) EXPECT_TRUE(g >= 0 && g < 3);
    const swcl_stimulus st[2] = {{SWCL_STIMULUS_ATTRACT, {0, 0, 0}, {0, 0, 0}, 0.0f},
                                 {SWCL_STIMULUS_STARTLE, {0.1f, 0, 0}, {0, 0, 0.1f}, 0.2f}};
    ASSERT_EQ(swcl_swarm_energy_set_stimuli(s, st, 2), SWCL_OK) << swcl_last_error();
    swcl_stimulus bad_st = st[1];
    bad_st.d_danger = -1.0f;
    EXPECT_EQ(swcl_swarm_energy_set_stimuli(s, &bad_st, 1), SWCL_ERROR_INVALID_ARGUMENT);
    bad_st = st[1];
    c_stimulus_kind(&bad_st, -1);  // only C can pass -1
    EXPECT_EQ(swcl_swarm_energy_set_stimuli(s, &bad_st, 1), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("stimuli[0].kind (-1)"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_energy_set_keypoints(s, kp, 1, 1), SWCL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(swcl_swarm_energy_set_keypoints(s, kp, 3, 0), SWCL_OK);
    ASSERT_EQ(swcl_swarm_step(s, 5), SWCL_OK) << swcl_last_error();
    std::vector<float> p(120);
    ASSERT_EQ(swcl_swarm_read(s, SWCL_ATTRIBUTE_POSITION, p.data(), 40), SWCL_OK);
    for (float x : p) EXPECT_TRUE(std::isfinite(x));
    // A bad descriptor leaves the model in place.
    swcl_energy_model_desc bad = d;
    bad.rho = -1.0f;
    EXPECT_EQ(swcl_swarm_energy_set_model(s, data_, &bad), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_energy_set_keypoints(s, kp, 3, 1), SWCL_OK);
    swcl_dataset gone{12345};
    EXPECT_EQ(swcl_swarm_energy_set_model(s, gone, &d), SWCL_ERROR_INVALID_HANDLE);
}

TEST_F(EnergyCapi, ScenarioModelTypeEnergy) {
    const std::string text = R"({
      "name": "energy_test", "seed": 2, "dt": 0.01, "steps": 20,
      "domain": {"min": [-1, -1, -1], "max": [1, 1, 1]}, "interaction_radius": 0.4,
      "agents": {"count": 30, "initial": {"type": "sphere", "center": [0, 0, 0], "radius": 0.3}},
      "model": {"type": "energy", "dataset": {"type": "synthetic", "k": 120, "groups": 6},
                "weights": {"rep": 1, "oa": 1, "cos": 0.05, "dir": 1, "acc": 1, "env": 1, "n": 0.2, "user": 0},
                "centre": [0, 0, 0], "noise": {"scale": 0.3, "time_scale": 0.5},
                "stimuli": [{"type": "startle", "position": [-1, 0, 0], "velocity": [0.5, 0, 0], "d_danger": 0.3}]}
    })";
    swcl_scenario sc{};
    ASSERT_EQ(swcl_scenario_parse(text.data(), text.size(), &sc), SWCL_OK) << swcl_last_error();
    swcl_scenario_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_scenario_get_info(sc, &info), SWCL_OK);
    EXPECT_STREQ(info.model, "energy");
    swcl_swarm s{};
    ASSERT_EQ(swcl_scenario_create_swarm(sc, ctx_, &s), SWCL_OK) << swcl_last_error();
    swarms_.push_back(s);
    ASSERT_EQ(swcl_swarm_step(s, 20), SWCL_OK) << swcl_last_error();
    std::vector<int32_t> goals(30);
    EXPECT_EQ(swcl_swarm_energy_get_goals(s, goals.data(), 30), SWCL_OK);  // an energy model is attached
    swcl_scenario_destroy(sc);

    auto refused = [&](const std::string& model, const char* expect) {
        std::string t = text;
        const auto b = t.find("\"model\""), e = t.rfind('}');
        t = t.substr(0, b) + "\"model\": " + model + t.substr(e);
        swcl_scenario bad{};
        const swcl_status st = swcl_scenario_parse(t.data(), t.size(), &bad);
        EXPECT_EQ(st, SWCL_ERROR_PARSE) << model;
        EXPECT_NE(std::string(swcl_last_error()).find(expect), std::string::npos) << swcl_last_error();
        if (st == SWCL_OK) swcl_scenario_destroy(bad);
    };
    refused(R"({"type": "energy", "keypoints": [[0, 0, 0]]})", "model.keypoints");
    refused(R"({"type": "energy", "dataset": {"type": "synthetic", "k": 0}})", "model.dataset.k");
    refused(R"({"type": "energy", "weights": {"rep": -1}})", "model.weights.rep");
    refused(R"({"type": "energy", "weights": {"repulsion": 1}})", "model.weights.repulsion: unknown key");
    refused(R"({"type": "energy", "dataset": {"type": "file"}})", "model.dataset.path: missing");
    refused(R"({"type": "energy", "d_rep": 0.5, "d_att1": 0.1})", "d_att1");
    refused(R"({"type": "energy", "stimuli": [{"type": "scary", "position": [0, 0, 0]}]})", "model.stimuli[0].type");
    refused(R"({"type": "energy", "noise": {"scale": -1}})", "model.noise.scale");
    refused(R"({"type": "energy", "speed": 3})", "model.speed: unknown key");

    // A dataset file that is not there: parsing succeeds, creating the swarm says Io.
    std::string t = text;
    t.replace(t.find(R"({"type": "synthetic", "k": 120, "groups": 6})"), 44,
              R"({"type": "file", "path": "/nonexistent/d.swds"})");
    ASSERT_EQ(swcl_scenario_parse(t.data(), t.size(), &sc), SWCL_OK) << swcl_last_error();
    swcl_swarm none{};
    EXPECT_EQ(swcl_scenario_create_swarm(sc, ctx_, &none), SWCL_ERROR_IO);
    swcl_scenario_destroy(sc);
}

TEST_F(EnergyCapi, StartFromTracksContinuesThem) {
    // Track 1 has a missing frame: its last segment (after the gap) is used.
    const uint32_t counts[2] = {4, 7};
    const double t[11] = {0, 0.01, 0.02, 0.03, 0, 0.01, 0.02, 0.05, 0.06, 0.07, 0.08};
    std::vector<float> xyz;
    for (int i = 0; i < 4; ++i) xyz.insert(xyz.end(), {0.01f * i, 0, 0});
    for (int i = 0; i < 7; ++i) xyz.insert(xyz.end(), {0, 0.02f * float(t[4 + i] * 100), 0.1f});
    swcl_swarm s = make_swarm(0);
    ASSERT_EQ(swcl_swarm_start_from_tracks(s, counts, 2, t, xyz.data(), nullptr), SWCL_OK) << swcl_last_error();
    uint32_t n = 0;
    ASSERT_EQ(swcl_swarm_agent_count(s, &n), SWCL_OK);
    ASSERT_EQ(n, 2u);
    float p[6], v[6];
    ASSERT_EQ(swcl_swarm_read(s, SWCL_ATTRIBUTE_POSITION, p, 2), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(s, SWCL_ATTRIBUTE_VELOCITY, v, 2), SWCL_OK);
    EXPECT_FLOAT_EQ(p[0], 0.03f);
    EXPECT_NEAR(v[0], 1.0f, 1e-4f);
    EXPECT_FLOAT_EQ(p[4], 0.16f);
    EXPECT_NEAR(v[4], 2.0f, 1e-3f);
    swcl_energy_model_desc d = swcl_energy_model_desc_default();
    ASSERT_EQ(swcl_swarm_energy_set_model(s, data_, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(s, 10), SWCL_OK);
    // Too many tracks for the capacity; a short track.
    std::vector<uint32_t> many(300, 3);
    std::vector<double> tm(900);
    for (size_t i = 0; i < tm.size(); ++i) tm[i] = 0.01 * double(i % 3);
    std::vector<float> xm(2700, 0.0f);
    EXPECT_EQ(swcl_swarm_start_from_tracks(s, many.data(), many.size(), tm.data(), xm.data(), nullptr),
              SWCL_ERROR_INVALID_ARGUMENT);
    const uint32_t short_count[1] = {2};
    EXPECT_EQ(swcl_swarm_start_from_tracks(s, short_count, 1, t, xyz.data(), nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(swcl_swarm_agent_count(s, &n), SWCL_OK);
    EXPECT_EQ(n, 2u);  // unchanged
}

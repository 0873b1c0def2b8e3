// The Table 1 scenarios of FASTSWARM (examples/scenarios/energy_*.json, run
// through the scenario parser and the C API) and the properties a user would
// check: aggregation keeps the swarm over its centre without lasting
// collisions, males end near the female, insects keep out of a passing
// obstacle's d_danger (the keep-out rule; Eq. 11-12 alone let the nearest one
// in) and re-aggregate, and agents visit the keypoints of the heart in order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "swarmcl/swarmcl.h"

namespace {

using json = nlohmann::json;

json example(const std::string& name) {
    std::ifstream in(std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/" + name + ".json");
    std::stringstream s;
    s << in.rdbuf();
    return json::parse(s.str());
}

class EnergyScenarios : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx_), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        if (swarm_.id) swcl_swarm_destroy(swarm_);
        swcl_context_destroy(ctx_);
    }
    void start(const json& j) {
        const std::string text = j.dump();
        swcl_scenario sc{};
        ASSERT_EQ(swcl_scenario_parse(text.data(), text.size(), &sc), SWCL_OK) << swcl_last_error();
        if (swarm_.id) swcl_swarm_destroy(swarm_);
        ASSERT_EQ(swcl_scenario_create_swarm(sc, ctx_, &swarm_), SWCL_OK) << swcl_last_error();
        swcl_scenario_destroy(sc);
        ASSERT_EQ(swcl_swarm_agent_count(swarm_, &n_), SWCL_OK);
    }
    std::vector<float> step(uint32_t k) {
        EXPECT_EQ(swcl_swarm_step(swarm_, k), SWCL_OK) << swcl_last_error();
        std::vector<float> p(3 * size_t(n_));
        EXPECT_EQ(swcl_swarm_read(swarm_, SWCL_ATTRIBUTE_POSITION, p.data(), n_), SWCL_OK);
        return p;
    }
    std::array<double, 3> centre(const std::vector<float>& p) const {
        std::array<double, 3> c{0, 0, 0};
        for (uint32_t i = 0; i < n_; ++i)
            for (int a = 0; a < 3; ++a) c[a] += p[3 * i + a] / n_;
        return c;
    }
    // Distance below which 90% of the agents are from the centre.
    double r90(const std::vector<float>& p) const {
        const auto c = centre(p);
        std::vector<double> r;
        for (uint32_t i = 0; i < n_; ++i)
            r.push_back(std::hypot(p[3 * i] - c[0], p[3 * i + 1] - c[1], p[3 * i + 2] - c[2]));
        std::sort(r.begin(), r.end());
        return r[size_t(0.9 * (r.size() - 1))];
    }
    double distance(const std::vector<float>& p, uint32_t i, const double* q) const {
        return std::hypot(p[3 * i] - q[0], p[3 * i + 1] - q[1], p[3 * i + 2] - q[2]);
    }
    swcl_context ctx_{};
    swcl_swarm swarm_{};
    uint32_t n_ = 0;
};

}  // namespace

TEST_F(EnergyScenarios, AggregationKeepsTheCentreAndNoLastingCollisions) {
    json j = example("energy_aggregation_37");
    const float d_rep = 0.04f;  // the model default the file relies on
    start(j);
    const double dt = j["dt"].get<double>();
    std::vector<uint32_t> run(size_t(n_) * n_, 0);
    uint32_t longest = 0;
    const uint32_t every = 5, steps = 1500;
    double centre_max = 0, r90_max = 0;
    for (uint32_t s = 0; s < steps; s += every) {
        const auto p = step(every);
        const auto c = centre(p);
        centre_max = std::max(centre_max, std::hypot(c[0], c[1], c[2]));
        r90_max = std::max(r90_max, r90(p));
        for (uint32_t a = 0; a < n_; ++a)
            for (uint32_t b = a + 1; b < n_; ++b) {
                const double q[3] = {p[3 * b], p[3 * b + 1], p[3 * b + 2]};
                uint32_t& r = run[size_t(a) * n_ + b];
                r = distance(p, a, q) < d_rep ? r + 1 : 0;
                longest = std::max(longest, r);
            }
    }
    // The swarm stays over its fixed centre (initial ball: radius 0.3 m) ...
    EXPECT_LT(centre_max, 0.5) << "swarm centre wandered";
    EXPECT_LT(r90_max, 0.6) << "swarm dispersed";
    // ... and pairs closer than d_rep part again: Eq. 4's averaged repulsion
    // is weak against Eq. 6 (docs/energy-model.md), so encounters last, but
    // not for long.
    EXPECT_LT(longest * every * dt, 5.0) << "a pair stayed below d_rep for " << longest * every * dt << " s";
}

TEST_F(EnergyScenarios, MalesEndNearTheFemale) {
    json j = example("energy_mating");
    start(j);
    const auto& st = j["model"]["stimuli"][0];
    const double dt = j["dt"].get<double>();
    const uint32_t steps = 400;  // they reach her within 3 s
    const auto p = step(steps);
    double female[3];
    for (int a = 0; a < 3; ++a)
        female[a] = st["position"][a].get<double>() + st["velocity"][a].get<double>() * steps * dt;
    uint32_t near = 0;
    for (uint32_t i = 0; i < n_; ++i) near += distance(p, i, female) < 0.3;
    EXPECT_GE(near, n_ * 8 / 10) << near << " of " << n_ << " males within 0.3 m of the female";
}

TEST_F(EnergyScenarios, InsectsEscapeThePassingObstacleAndReaggregate) {
    // The obstacle crosses the swarm (x from -1.5 to 1.5 m at 0.5 m/s); the
    // closest approach of any insect is taken after every step.
    auto closest_approach = [&](const json& j, double* r90_before, double* r90_after) {
        start(j);
        const auto& st = j["model"]["stimuli"][0];
        const double dt = j["dt"].get<double>();
        double closest = 1e9;
        for (uint32_t s = 1; s <= 1000; ++s) {
            const auto p = step(1);
            double o[3];
            for (int a = 0; a < 3; ++a) o[a] = st["position"][a].get<double>() + st["velocity"][a].get<double>() * s * dt;
            for (uint32_t i = 0; i < n_; ++i) closest = std::min(closest, distance(p, i, o));
            if (s == 150 && r90_before) *r90_before = r90(p);
            if (s == 1000 && r90_after) *r90_after = r90(p);
        }
        return closest;
    };
    json j = example("energy_escaping");
    const double d_danger = j["model"]["stimuli"][0]["d_danger"].get<double>();
    double before = 0, after = 0;
    const double escaping = closest_approach(j, &before, &after);
    // Eq. 11-12 alone (no keep-out), and no startle response at all.
    json literal = j;
    literal["model"]["keep_out"] = false;
    const double eq12_only = closest_approach(literal, nullptr, nullptr);
    json control = literal;
    control["model"]["weights"]["env"] = 0;
    control["model"]["danger_weights"] = control["model"]["weights"];
    const double ignoring = closest_approach(control, nullptr, nullptr);
    std::printf("closest approach to the obstacle (d_danger %.2f m): %.4f m escaping, %.4f m by Eq. 11-12 alone, "
                "%.4f m without the startle response\n",
                d_danger, escaping, eq12_only, ignoring);
    // The nearest insect stays outside d_danger while the obstacle passes;
    // without the response one is hit almost head-on.
    EXPECT_GE(escaping, d_danger * (1.0 - 1e-4)) << "an insect came within d_danger (up to float rounding)";
    EXPECT_LT(ignoring, 0.5 * d_danger);
    // Re-aggregation 3 s after the obstacle has left.
    EXPECT_LT(after, 1.5 * before + 0.05) << "r90 before " << before << ", after " << after;
}

TEST_F(EnergyScenarios, AgentsVisitTheHeartKeypointsInOrder) {
    json j = example("energy_heart");
    const uint32_t n = 100;
    j["agents"]["count"] = n;
    auto& pts = j["agents"]["initial"]["positions"];
    pts.erase(pts.begin() + n, pts.end());
    start(j);
    const auto kp = j["model"]["keypoints"];
    const size_t K = kp.size();
    const double reach = j["model"]["keypoint_reach"].get<double>();
    std::vector<std::vector<int>> visits(n);
    for (int s = 0; s < 800; ++s) {  // every step: a goal is left as soon as it is reached
        const auto p = step(1);
        for (uint32_t i = 0; i < n; ++i)
            for (size_t k = 0; k < K; ++k) {
                const double q[3] = {kp[k][0].get<double>(), kp[k][1].get<double>(), kp[k][2].get<double>()};
                if (distance(p, i, q) < reach && (visits[i].empty() || visits[i].back() != int(k)))
                    visits[i].push_back(int(k));
            }
    }
    // Successive keypoints reached are neighbours on the curve, in the
    // agent's direction (odd ids backwards).
    uint32_t in_order = 0, travelled = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const int dir = (i & 1u) ? -1 : 1;
        uint32_t good = 0;
        for (size_t v = 1; v < visits[i].size(); ++v)
            good += visits[i][v] == (visits[i][v - 1] + dir + int(K)) % int(K);
        if (visits[i].size() >= 3) {
            ++travelled;
            in_order += good + 1 >= visits[i].size() * 9 / 10;
        }
    }
    EXPECT_GE(travelled, n * 3 / 4) << "agents that reached 3 keypoints or more";
    EXPECT_GE(in_order, travelled * 9 / 10);
}

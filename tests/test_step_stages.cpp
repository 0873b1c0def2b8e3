// The step pipeline (swarm/swarm.hpp, swarm/behavior.hpp): after a model's
// advance the swarm runs the stages the model's StepStages ask for (minimum
// distance enforcement, the model's after_constraints, the step statistics),
// in that order; a model gets MDE by configuration alone.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "models/field_model.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

// A model that does not move anything: only its stages act.
class StillModel : public Behavior {
public:
    explicit StillModel(StepStages stages, bool own = false) : stages_(stages) { stages_.own_min_distance = own; }
    void advance(Swarm&, uint64_t step) override { log += "advance" + std::to_string(step) + " "; }
    StepStages stages() const override { return stages_; }
    void enforce_min_distance(Swarm& swarm, DeviceBuffer<cl_uint>& moved) override {
        log += "mde ";
        // Counts every agent as moved (a model's own pass writes the counters).
        const cl_uint n = swarm.agent_count();
        moved.upload(swarm.context(), &n, 1);
    }
    void after_constraints(Swarm&, uint64_t) override { log += "after "; }

    StepStages stages_;
    std::string log;
};

std::unique_ptr<Swarm> make(const std::vector<float>& xyz) {
    auto s = std::make_unique<Swarm>(shared_context(), cube_config(64, -1.0f, 1.0f, 0.25f));
    s->write(Attribute::Position, xyz.data(), xyz.size() / 3);
    return s;
}

float distance(const std::vector<float>& p, int a, int b) {
    return std::sqrt(dist2(&p[3 * a], &p[3 * b]));
}

const std::vector<float> kClosePair{0.1f, 0.1f, 0.1f, 0.13f, 0.1f, 0.1f, -0.7f, -0.7f, -0.7f};

}  // namespace

TEST(StepStages, MinDistanceIsConfiguredByTheModel) {
    StepStages st;
    st.min_distance = 0.2f;
    st.seed = 5;
    st.stats = true;
    auto swarm = make(kClosePair);
    auto model = std::make_shared<StillModel>(st);
    swarm->set_behavior(model);
    swarm->step(1);
    std::vector<float> p(9);
    swarm->read(Attribute::Position, p.data(), 3);
    EXPECT_NEAR(distance(p, 0, 1), 0.2f, 2e-6f) << "the swarm's MDE pass separated the pair";
    const auto stats = swarm->take_step_stats();
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->steps, 1u);
    EXPECT_EQ(stats->mde_moved_last, 2u);
    EXPECT_EQ(stats->mde_moved_total, 2u);
    EXPECT_EQ(model->log, "advance0 after ");

    // Without statistics the pass still runs, and there is nothing to read.
    st.stats = false;
    auto quiet = make(kClosePair);
    quiet->set_behavior(std::make_shared<StillModel>(st));
    quiet->step(1);
    quiet->read(Attribute::Position, p.data(), 3);
    EXPECT_NEAR(distance(p, 0, 1), 0.2f, 2e-6f);
    EXPECT_FALSE(quiet->take_step_stats().has_value());
}

TEST(StepStages, ModelWithoutMinDistanceCountsStepsOnly) {
    StepStages st;
    st.stats = true;  // min_distance 0: off
    auto swarm = make(kClosePair);
    swarm->set_behavior(std::make_shared<StillModel>(st));
    swarm->step(3);
    std::vector<float> p(9);
    swarm->read(Attribute::Position, p.data(), 3);
    EXPECT_EQ(p, kClosePair) << "no stage moved anything";
    const auto stats = swarm->take_step_stats();
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->steps, 3u);
    EXPECT_EQ(stats->mde_moved_total, 0u);
}

TEST(StepStages, FieldModelMinDistanceComesFromItsConfig) {
    for (float d_min : {0.0f, 0.2f}) {
        auto swarm = make(kClosePair);
        FieldModelConfig c;
        c.noise.gain = 0.0f;  // still: only MDE moves agents
        c.min_distance = d_min;
        swarm->set_behavior(std::make_shared<FieldModel>(*swarm, c));
        swarm->step(2);
        const auto stats = swarm->take_step_stats();
        ASSERT_TRUE(stats.has_value());
        EXPECT_EQ(stats->steps, 2u);
        EXPECT_EQ(stats->mde_moved_total, d_min > 0.0f ? 2u : 0u) << "min_distance " << d_min;
        std::vector<float> p(9);
        swarm->read(Attribute::Position, p.data(), 3);
        if (d_min > 0.0f)
            EXPECT_NEAR(distance(p, 0, 1), d_min, 2e-6f);
        else
            EXPECT_NEAR(distance(p, 0, 1), 0.03f, 1e-6f);
    }
}

TEST(StepStages, OwnPassRunsBetweenAdvanceAndAfterConstraints) {
    StepStages st;
    st.min_distance = 0.1f;
    st.stats = true;
    auto swarm = make(kClosePair);
    auto model = std::make_shared<StillModel>(st, true);
    swarm->set_behavior(model);
    swarm->step(2);
    EXPECT_EQ(model->log, "advance0 mde after advance1 mde after ");
    std::vector<float> p(9);
    swarm->read(Attribute::Position, p.data(), 3);
    EXPECT_EQ(p, kClosePair) << "the swarm's own pass did not run";
    const auto stats = swarm->take_step_stats();
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->mde_moved_last, 3u);
    EXPECT_EQ(stats->steps, 2u);
}

TEST(StepStages, EmptySwarmStepsFollowTheModelsRule) {
    for (bool count_empty : {true, false}) {
        StepStages st;
        st.min_distance = 0.1f;
        st.stats = true;
        st.count_empty_steps = count_empty;
        auto swarm = make({});
        auto model = std::make_shared<StillModel>(st, true);
        swarm->set_behavior(model);
        swarm->step(2);
        EXPECT_EQ(swarm->take_step_stats()->steps, count_empty ? 2u : 0u);
        EXPECT_EQ(model->log, count_empty ? "advance0 mde after advance1 mde after " : "advance0 advance1 ");
    }
}

TEST(StepStages, StatisticsBelongToTheModelSetLast) {
    StepStages st;
    st.min_distance = 0.2f;
    st.stats = true;
    auto swarm = make(kClosePair);
    swarm->set_behavior(std::make_shared<StillModel>(st));
    swarm->step(1);
    swarm->set_behavior(std::make_shared<StillModel>(st));  // a new model starts from zero
    auto stats = swarm->take_step_stats();
    ASSERT_TRUE(stats.has_value());
    EXPECT_EQ(stats->steps, 0u);
    EXPECT_EQ(stats->mde_moved_total, 0u);
    swarm->set_behavior(nullptr);  // ballistic: none
    swarm->step(1);
    EXPECT_FALSE(swarm->take_step_stats().has_value());
}

// A context and one swarm made through the C API, released after each test:
// the set-up the C API tests of every model share.
#pragma once
#include <gtest/gtest.h>

#include <functional>

#include "swarmcl/swarmcl.h"

namespace swarmcl::test {

class CApiSwarmTest : public ::testing::Test {
protected:
    // Creates the context and a swarm from swcl_swarm_desc_default() as
    // changed by `edit`.  Call with ASSERT_NO_FATAL_FAILURE from SetUp.
    void create(const std::function<void(swcl_swarm_desc&)>& edit) {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
        swcl_swarm_desc s = swcl_swarm_desc_default();
        edit(s);
        ASSERT_EQ(swcl_swarm_create(ctx, &s, &swarm), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        swcl_swarm_destroy(swarm);
        swcl_context_destroy(ctx);
    }
    swcl_context ctx{};
    swcl_swarm swarm{};
};

}  // namespace swarmcl::test

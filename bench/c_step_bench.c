/* The C side of bench/python_step_bench.py: the same swarmcl calls as the
 * Python loop, timed the same way.  Built on the fly by the Python script
 * against the very library the Python package loads:
 *   cc -O2 -std=c99 -I capi/include bench/c_step_bench.c <libswarmcl.so.0.2> -o ...
 * Usage: c_step_bench MODE AGENTS STEPS_PER_CALL CALLS REPEATS SYNC [DEVICE]
 *   MODE ballistic|field, SYNC end|each (read positions after the last call
 *   only, or after every call).  Prints one JSON object. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <swarmcl/swarmcl.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#define CHECK(call)                                                                    \
    do {                                                                               \
        swcl_status st_ = (call);                                                      \
        if (st_ != SWCL_OK) {                                                          \
            fprintf(stderr, "%s: %s\n", swcl_status_string(st_), swcl_last_error());   \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

int main(int argc, char** argv) {
    if (argc < 7) {
        fprintf(stderr, "usage: %s ballistic|field AGENTS STEPS_PER_CALL CALLS REPEATS end|each [DEVICE]\n", argv[0]);
        return 2;
    }
    const int field = strcmp(argv[1], "field") == 0;
    const uint32_t agents = (uint32_t)strtoul(argv[2], NULL, 10);
    const uint32_t steps = (uint32_t)strtoul(argv[3], NULL, 10);
    const int calls = atoi(argv[4]);
    const int repeats = atoi(argv[5]);
    const int each = strcmp(argv[6], "each") == 0;

    swcl_context_desc cd = swcl_context_desc_default();
    if (argc > 7) cd.device = argv[7];
    swcl_context ctx;
    CHECK(swcl_context_create(&cd, &ctx));

    /* Must match python_step_bench.py: make_swarm() */
    swcl_swarm_desc sd = swcl_swarm_desc_default();
    sd.capacity = agents;
    sd.agent_count = agents;
    sd.seed = 2024;
    const float lo[3] = {-1.5f, -1.5f, 0.5f}, hi[3] = {1.5f, 1.5f, 3.5f};
    memcpy(sd.domain_min, lo, sizeof lo);
    memcpy(sd.domain_max, hi, sizeof hi);
    sd.interaction_radius = 0.05f;
    sd.dt = 1.0f / 30.0f;
    swcl_swarm swarm;
    CHECK(swcl_swarm_create(ctx, &sd, &swarm));
    if (field) {
        swcl_field_model_desc md = swcl_field_model_desc_default();
        md.noise.type = SWCL_NOISE_CURL;
        md.noise.seed = 7;
        md.noise.time_scale = 2.0f;
        md.noise.domain_walls = 1;
        md.has_goal = 1;
        md.goal[0] = 0.0f; md.goal[1] = 0.0f; md.goal[2] = 2.0f;
        md.goal_radius = 1.2f;
        md.goal_speed = 1.5f;
        md.goal_falloff = 1.0f;
        md.min_distance = 0.03f;
        CHECK(swcl_swarm_field_set_model(swarm, &md));
    }
    float* pos = (float*)malloc(sizeof(float) * 3 * (size_t)agents);
    if (!pos) return 1;

    /* warm-up: kernels built, buffers allocated */
    CHECK(swcl_swarm_step(swarm, steps));
    CHECK(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, pos, agents));

    printf("{\"per_call_s\": [");
    for (int r = 0; r < repeats; ++r) {
        const double t0 = now();
        for (int c = 0; c < calls; ++c) {
            CHECK(swcl_swarm_step(swarm, steps));
            if (each) CHECK(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, pos, agents));
        }
        if (!each) CHECK(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, pos, agents));
        const double t1 = now();
        printf("%s%.9f", r ? ", " : "", (t1 - t0) / calls);
    }
    uint64_t total = 0;
    CHECK(swcl_swarm_step_count(swarm, &total));
    printf("], \"steps\": %llu, \"checksum\": %.6f}\n", (unsigned long long)total,
           (double)pos[0] + (double)pos[3 * (agents - 1) + 2]);
    free(pos);
    CHECK(swcl_swarm_destroy(swarm));
    CHECK(swcl_context_destroy(ctx));
    return 0;
}

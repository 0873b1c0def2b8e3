/* swarmcl C example — the main job: the aggregation scenario of the
 * curl-noise paper (1000 insects as in Table 1; noise scale 0.4, gain 0.25,
 * s0 1.5 are Table 1's two-blocks/chasing values, its aggregation column
 * has 0.2, 0.7, 2.5) with the local field model: boundary-aware curl noise inside the
 * domain walls, a pull to a goal sphere, minimum distance enforcement.
 * Prints statistics every few steps.
 *
 * Usage: aggregation [agents] [steps] [device-selector] [min-distance]                     */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <swarmcl/swarmcl.h>

#define CHECK(call)                                                                     \
    do {                                                                                \
        swcl_status s_ = (call);                                                        \
        if (s_ != SWCL_OK) {                                                            \
            fprintf(stderr, "%s failed: %s: %s\n", #call, swcl_status_string(s_),       \
                    swcl_last_error());                                                 \
            return 1;                                                                   \
        }                                                                               \
    } while (0)

static int compare_floats(const void* a, const void* b) {
    const float x = *(const float*)a, y = *(const float*)b;
    return (x > y) - (x < y);
}

static float percentile(const float* sorted, uint32_t n, double q) {
    return sorted[(uint32_t)(q * (n - 1) + 0.5)];
}

int main(int argc, char** argv) {
    const uint32_t n = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 1000u;
    const uint32_t steps = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : 300u;
    const uint32_t every = steps >= 10 ? steps / 10 : 1;
    const float mde = argc > 4 ? (float)atof(argv[4]) : 0.03f; /* minimum distance between insects, m */
    swcl_context_desc cdesc = swcl_context_desc_default();
    swcl_swarm_desc sdesc = swcl_swarm_desc_default();
    swcl_field_model_desc model = swcl_field_model_desc_default();
    swcl_device_info info;
    swcl_context ctx;
    swcl_swarm swarm;
    swcl_step_stats stats;
    float *vel, *dist;
    uint32_t* close;
    uint32_t i, done = 0;

    if (n < 2) {
        fprintf(stderr, "aggregation needs at least 2 agents\n");
        return 1;
    }
    if (argc > 3) cdesc.device = argv[3];
    CHECK(swcl_context_create(&cdesc, &ctx));
    info.struct_size = sizeof(info);
    stats.struct_size = sizeof(stats);
    CHECK(swcl_context_device_info(ctx, &info));
    printf("swarmcl %s on %s / %s\n", swcl_version_string(), info.platform_name, info.device_name);

    /* A 3 m cube; as in the paper's aggregation, the insects start where they
     * gather (the goal area is the starting area). */
    sdesc.capacity = n;
    sdesc.agent_count = n;
    sdesc.seed = 2024;
    sdesc.domain_min[0] = -1.5f; sdesc.domain_max[0] = 1.5f;
    sdesc.domain_min[1] = -1.5f; sdesc.domain_max[1] = 1.5f;
    sdesc.domain_min[2] = 0.5f;  sdesc.domain_max[2] = 3.5f;
    sdesc.interaction_radius = 0.1f;
    sdesc.dt = 1.0f / 30.0f;
    CHECK(swcl_swarm_create(ctx, &sdesc, &swarm));

    /* Table 1's two-blocks/chasing noise and s0 (0.4, 0.25, 1.5); the walls keep the
     * swarm in; insects outside a 1.2 m sphere at the centre are pulled back,
     * the pull growing to s0 over 1 m. */
    model.noise.scale = 0.4f;
    model.noise.gain = 0.25f;
    model.noise.seed = 7;
    model.noise.time_scale = 2.0f;
    model.noise.domain_walls = 1;
    model.has_goal = 1;
    model.goal[0] = 0.0f; model.goal[1] = 0.0f; model.goal[2] = 2.0f;
    model.goal_radius = 1.2f;
    model.goal_speed = 1.5f;
    model.goal_falloff = 1.0f;
    model.min_distance = mde;
    CHECK(swcl_swarm_field_set_model(swarm, &model));

    vel = malloc(sizeof(float) * 3 * n);
    dist = malloc(sizeof(float) * n);
    close = malloc(sizeof(uint32_t) * n);
    if (!vel || !dist || !close) return 1;
    printf("%u insects, dt %.4f s, noise scale %.2f gain %.2f, s0 %.1f m/s, MDE %.2f m\n", n, sdesc.dt,
           model.noise.scale, model.noise.gain, model.goal_speed, mde);
    printf("%6s %8s %10s %10s %10s %10s %9s\n", "step", "speed", "nn p5", "nn p50", "nn p95", "pairs<mde",
           "MDE moved");
    while (done < steps) {
        const uint32_t k = steps - done < every ? steps - done : every;
        double speed = 0.0, pairs = 0.0;
        CHECK(swcl_swarm_step(swarm, k));
        done += k;
        CHECK(swcl_swarm_take_step_stats(swarm, &stats));
        CHECK(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, vel, n));
        CHECK(swcl_swarm_nearest_neighbor(swarm, dist, NULL, n));
        CHECK(swcl_swarm_neighbor_count(swarm, mde * 0.999f, close, n));
        for (i = 0; i < n; ++i) {
            speed += sqrt(vel[3 * i] * vel[3 * i] + vel[3 * i + 1] * vel[3 * i + 1] + vel[3 * i + 2] * vel[3 * i + 2]);
            pairs += close[i];
        }
        qsort(dist, n, sizeof(float), compare_floats);
        /* pairs<mde: fraction of all pairs closer than the MDE distance;
         * MDE moved: mean fraction of insects MDE moved per step. */
        printf("%6u %8.3f %10.4f %10.4f %10.4f %10.2e %8.3f%%\n", done, speed / n, percentile(dist, n, 0.05),
               percentile(dist, n, 0.5), percentile(dist, n, 0.95), pairs / 2.0 / (0.5 * n * (n - 1.0)),
               100.0 * (double)stats.mde_moved_total / ((double)stats.steps * n));
    }
    free(vel);
    free(dist);
    free(close);
    CHECK(swcl_swarm_destroy(swarm));
    CHECK(swcl_context_destroy(ctx));
    return 0;
}

/* swarmcl C example: a swarm of random agents on the default device, their
 * nearest-neighbour distances, and a summary.  Plain C99 against the installed
 * header:  cc nearest_neighbors.c $(pkg-config --cflags --libs swarmcl)
 *
 * Usage: nearest_neighbors [agents] [device-selector]                      */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <swarmcl/swarmcl.h>

static int check(swcl_status status, const char* what) {
    if (status == SWCL_OK) return 0;
    fprintf(stderr, "%s failed: %s: %s\n", what, swcl_status_string(status), swcl_last_error());
    return 1;
}

static int compare_floats(const void* a, const void* b) {
    const float x = *(const float*)a, y = *(const float*)b;
    return (x > y) - (x < y);
}

int main(int argc, char** argv) {
    const uint32_t n = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 10000u;
    swcl_context_desc cdesc = swcl_context_desc_default();
    swcl_context ctx;
    swcl_device_info info;
    swcl_swarm_desc sdesc = swcl_swarm_desc_default();
    swcl_swarm swarm;
    float* dist = NULL;
    uint32_t* counts = NULL;
    double sum = 0.0, neighbours = 0.0;
    uint32_t i;
    int rc = 1;

    if (argc > 2) cdesc.device = argv[2];
    if (check(swcl_context_create(&cdesc, &ctx), "swcl_context_create")) return 1;
    info.struct_size = sizeof(info);
    if (check(swcl_context_device_info(ctx, &info), "swcl_context_device_info")) goto done_ctx;
    printf("swarmcl %s on %s / %s (%s)\n", swcl_version_string(), info.platform_name, info.device_name,
           info.version);

    /* n agents uniformly at random in a 10 m cube, grid cells of 0.5 m. */
    sdesc.capacity = n > 0 ? n : 1;
    sdesc.agent_count = n;
    sdesc.seed = 42;
    for (i = 0; i < 3; ++i) {
        sdesc.domain_min[i] = 0.0f;
        sdesc.domain_max[i] = 10.0f;
    }
    sdesc.interaction_radius = 0.5f;
    if (check(swcl_swarm_create(ctx, &sdesc, &swarm), "swcl_swarm_create")) goto done_ctx;

    dist = malloc(sizeof(float) * (n ? n : 1));
    counts = malloc(sizeof(uint32_t) * (n ? n : 1));
    if (!dist || !counts) goto done_swarm;
    if (check(swcl_swarm_nearest_neighbor(swarm, dist, NULL, n), "swcl_swarm_nearest_neighbor")) goto done_swarm;
    if (check(swcl_swarm_neighbor_count(swarm, 0.5f, counts, n), "swcl_swarm_neighbor_count")) goto done_swarm;

    for (i = 0; i < n; ++i) {
        sum += dist[i];
        neighbours += counts[i];
    }
    qsort(dist, n, sizeof(float), compare_floats);
    printf("agents: %u in [0, 10]^3 m, seed %llu\n", n, (unsigned long long)sdesc.seed);
    if (n > 1) {
        printf("nearest-neighbour distance: mean %.4f m, min %.4f, median %.4f, max %.4f\n", sum / n, dist[0],
               dist[n / 2], dist[n - 1]);
        /* For a Poisson process the mean is 0.554 * density^(-1/3). */
        printf("expected mean for uniform points: %.4f m\n", 0.55396 * pow(n / 1000.0, -1.0 / 3.0));
        printf("neighbours within 0.5 m: mean %.2f per agent\n", neighbours / n);
    }
    rc = 0;
done_swarm:
    free(dist);
    free(counts);
    swcl_swarm_destroy(swarm);
done_ctx:
    swcl_context_destroy(ctx);
    return rc;
}

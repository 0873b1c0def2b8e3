/*
 * swarmcl — swarm simulation on OpenCL devices.  The stable C API.
 *
 * Conventions (docs/c-api.md):
 *  - every function that can fail returns a swcl_status; SWCL_OK is 0;
 *  - on failure swcl_last_error() (thread-local) tells what went wrong and the
 *    object involved is left as it was;
 *  - handles are small value types carrying a never-reused id: a destroyed or
 *    foreign handle gives SWCL_ERROR_INVALID_HANDLE, never a crash;
 *  - descriptor structs carry struct_size and are obtained from *_default();
 *  - units are SI (metres, seconds); vectors are packed float xyz triples;
 *  - reads and writes of agent attributes are in agent-id order.
 *
 * Threads (docs/reliability.md, tests/test_threads.cpp):
 *  - every function may be called from any thread; swcl_last_error() is
 *    thread_local, so each thread sees its own last failure;
 *  - different contexts (and everything made on them) are fully independent
 *    and may be used from different threads at once;
 *  - calls on ONE context from several threads at once are safe too: the
 *    handle registries are locked, the context's program cache is locked, its
 *    OpenCL queue is thread-safe, and every call on a swarm holds that swarm's
 *    lock, so calls on one swarm are serialised (each call is atomic; the
 *    ORDER of two threads' steps on one swarm is whatever the lock grants, so
 *    for a reproducible run drive each swarm from one thread at a time);
 *  - results do not depend on threads: a swarm stepped on another thread, or
 *    beside other swarms, gives bitwise the same state;
 *  - destroying a handle while another thread is inside a call on it is
 *    safe (the call finishes on its own reference), but the caller cannot
 *    know which of the two came first: don't.
 *
 * The header is plain C99 without function-like macros in declarations, so
 * FFI generators (cffi, bindgen, ClangSharp) read it as it is.
 */
#ifndef SWARMCL_SWARMCL_H
#define SWARMCL_SWARMCL_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32) && !defined(SWARMCL_STATIC)
#  if defined(SWARMCL_BUILDING)
#    define SWCL_API __declspec(dllexport)
#  else
#    define SWCL_API __declspec(dllimport)
#  endif
#elif defined(__GNUC__)
#  define SWCL_API __attribute__((visibility("default")))
#else
#  define SWCL_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ==== STABLE: the core ========================================================
 * Version, status codes, devices, contexts, swarms, neighbour search, scenario
 * files and recording.  Nothing here changes before 1.0 except by additions. */

/* ---- version ------------------------------------------------------------ */

#define SWCL_VERSION_MAJOR 0
#define SWCL_VERSION_MINOR 2
#define SWCL_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch */
#define SWCL_VERSION_NUMBER 200

/* The version of the library actually loaded (compare with SWCL_VERSION_NUMBER). */
SWCL_API uint32_t swcl_version(void);
SWCL_API const char* swcl_version_string(void);

/* ---- status codes (values never change) ---------------------------------- */
/* Enums: every enum ends with a *_MAX_ENUM = 0x7FFFFFFF entry (never a valid
 * value) so that its range is all of int32 in C and C++ alike: any int a
 * caller passes, wrong ones included, is a value the library can check and
 * refuse with SWCL_ERROR_INVALID_ARGUMENT, not undefined behaviour (found by
 * UBSan, scripts/asan.sh). */

typedef enum swcl_status {
    SWCL_OK = 0,
    SWCL_ERROR_INVALID_ARGUMENT = -1,
    SWCL_ERROR_INVALID_HANDLE = -2,
    SWCL_ERROR_NO_DEVICE = -3,
    SWCL_ERROR_BUILD = -4,
    SWCL_ERROR_OUT_OF_MEMORY = -5,
    SWCL_ERROR_IO = -6,
    SWCL_ERROR_PARSE = -7,
    SWCL_ERROR_OPENCL = -8,
    SWCL_ERROR_INTERNAL = -99,
    SWCL_STATUS_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_status;

/* A static name for a status, e.g. "SWCL_ERROR_INVALID_HANDLE". */
SWCL_API const char* swcl_status_string(swcl_status status);

/* Detail of the last failure on this thread (argument name, OpenCL build log).
 * Empty string after a success.  Valid until the next call on this thread. */
SWCL_API const char* swcl_last_error(void);

/* ---- model parameters ---------------------------------------------------- */

/* A model's parameters as the library declares them (one table per model,
 * docs/scenarios.md): JSON text, an array of rows {"key" (in a scenario's
 * "model" object), "c_field" (the descriptor's field), "type" (float, uint32,
 * uint64, bool, vec3, uint3, enum), "default", "min", "max" (null: none),
 * "min_exclusive", "values" (enum names), "range", "unit", "doc", "ref" (the
 * paper's section/equation), "device", "scenario", "per_world" (false: the
 * same in every world of a swarm, e.g. what selects a kernel; see
 * swcl_swarm_set_world_param)}.  `model`: "field",
 * "noise", ... (swcl_scenario_info.model's names); NULL: an object of every
 * model's array.  The text is the library's own, valid while it is loaded;
 * an unknown model is SWCL_ERROR_INVALID_ARGUMENT naming the known ones. */
SWCL_API swcl_status swcl_model_parameters(const char* model, const char** out_json);

/* ---- handles ------------------------------------------------------------- */

typedef struct swcl_context { uint64_t id; } swcl_context;
typedef struct swcl_swarm { uint64_t id; } swcl_swarm;

/* ---- devices ------------------------------------------------------------- */

typedef enum swcl_device_type {
    SWCL_DEVICE_TYPE_OTHER = 0,
    SWCL_DEVICE_TYPE_CPU = 1,
    SWCL_DEVICE_TYPE_GPU = 2,
    SWCL_DEVICE_TYPE_ACCELERATOR = 3,
    SWCL_DEVICE_TYPE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_device_type;

typedef struct swcl_device_info {
    uint32_t struct_size;
    uint32_t index;              /* global index, usable as a device selector */
    swcl_device_type type;
    uint32_t compute_units;
    uint64_t global_memory_bytes;
    char platform_name[128];
    char device_name[128];
    char version[128];           /* the device's OpenCL version string */
} swcl_device_info;

/* Number of OpenCL devices over all platforms.  With no OpenCL platform this
 * returns SWCL_ERROR_NO_DEVICE and swcl_last_error() names the fix. */
SWCL_API swcl_status swcl_device_count(uint32_t* out_count);
/* Fills *out for device `index`; out->struct_size must be set by the caller
 * (sizeof(swcl_device_info)). */
SWCL_API swcl_status swcl_device_get_info(uint32_t index, swcl_device_info* out);

/* ---- context ------------------------------------------------------------- */

typedef struct swcl_context_desc {
    uint32_t struct_size;
    /* Device selector: a global index ("0") or a case-insensitive substring of
     * the platform or device name ("pthread", "nvidia").  NULL or "": use
     * $SWARMCL_DEVICE if set, else the first GPU, else the first CPU. */
    const char* device;
    /* Extra OpenCL build options appended to swarmcl's own (NULL: none). */
    const char* build_options;
} swcl_context_desc;

SWCL_API swcl_context_desc swcl_context_desc_default(void);
SWCL_API swcl_status swcl_context_create(const swcl_context_desc* desc, swcl_context* out);
/* Swarms created on the context stay valid after it is destroyed. */
SWCL_API swcl_status swcl_context_destroy(swcl_context context);
/* The device the context runs on. */
SWCL_API swcl_status swcl_context_device_info(swcl_context context, swcl_device_info* out);

/* ---- swarm --------------------------------------------------------------- */

typedef enum swcl_attribute {
    SWCL_ATTRIBUTE_POSITION = 0,   /* metres, float xyz */
    SWCL_ATTRIBUTE_VELOCITY = 1,   /* metres per second, float xyz */
    SWCL_ATTRIBUTE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_attribute;

typedef struct swcl_swarm_desc {
    uint32_t struct_size;
    uint32_t capacity;             /* maximum number of agents (> 0) */
    uint32_t agent_count;          /* agents placed uniformly at random in the
                                      domain at creation (<= capacity) */
    uint64_t seed;                 /* seeds every random choice of the swarm */
    float domain_min[3];           /* domain bounds in metres; agents may leave */
    float domain_max[3];           /* them, the grid only covers them */
    float interaction_radius;      /* neighbour-grid cell size, metres (> 0) */
    float dt;                      /* time step, seconds (> 0) */
    /* Worlds (added in 0.x; older struct sizes mean 1): independent swarms of
     * capacity / agent_count agents each, stepped by the same launches.  World
     * k is seeded with world_seeds[k] (NULL: seed + k) and runs bitwise as a
     * swarm alone with that seed, its own model parameters
     * (swcl_swarm_set_world_param) and its domain (world_domains).  All
     * worlds share the model's kernel; each has the grid of its domain.  Reads and writes hold every world, world
     * by world (count = worlds x agents a world).  The field model, the
     * force model, the energy model, the path model (its goals per world by
     * the keys "groups.G.goals.I.center" / ".radius" / ".half_extents";
     * moving goals and chasing targets one for every world, not with a
     * baked noise), the policy model (a leader a world, all alike: the
     * leader's parameters and u_max are not set per world) and ballistic
     * motion run worlds (and are saved with them), and attached metrics
     * measure each world (swcl_metrics_world); recorders refuse worlds > 1
     * with SWCL_ERROR_INVALID_ARGUMENT for now. */
    uint32_t worlds;               /* >= 1 */
    const uint64_t* world_seeds;   /* NULL or `worlds` seeds (copied) */
    /* Domains per world (added after world_seeds; older struct sizes mean
     * NULL): NULL, every world in domain_min..domain_max; else 6 x `worlds`
     * floats (copied), world k's min xyz then max xyz, which replace
     * domain_min/max (the swarm's domain is then world 0's).  Each world is
     * placed in, and its grid and noise walls (without a noise region)
     * cover, its own domain.  The path model needs one domain for every
     * world (SWCL_ERROR_INVALID_ARGUMENT otherwise); so does a baked noise
     * without a region (one grid for every world). */
    const float* world_domains;
} swcl_swarm_desc;

SWCL_API swcl_swarm_desc swcl_swarm_desc_default(void);
SWCL_API swcl_status swcl_swarm_create(swcl_context context, const swcl_swarm_desc* desc,
                                       swcl_swarm* out);
SWCL_API swcl_status swcl_swarm_destroy(swcl_swarm swarm);
/* Agents of each world (of the swarm, with one world). */
SWCL_API swcl_status swcl_swarm_agent_count(swcl_swarm swarm, uint32_t* out_count);
SWCL_API swcl_status swcl_swarm_worlds(swcl_swarm swarm, uint32_t* out_worlds);
/* Every world's domain: out[6 k .. 6 k + 5] = world k's min xyz, max xyz;
 * count = worlds (swcl_swarm_desc.world_domains, or domain_min/max for all). */
SWCL_API swcl_status swcl_swarm_world_domains(swcl_swarm swarm, float* out, size_t count);
/* Steps simulated so far. */
SWCL_API swcl_status swcl_swarm_step_count(swcl_swarm swarm, uint64_t* out_steps);

/* Writes `count` agents' attribute from `src` (3 * count floats, agent-id
 * order).  Writing positions sets the agent count to `count` (<= capacity);
 * agents beyond the previous count start with zero velocity.  Writing
 * velocities needs count == the agent count.  NaN or Inf values are refused. */
SWCL_API swcl_status swcl_swarm_write(swcl_swarm swarm, swcl_attribute attribute,
                                      const float* src, size_t count);
/* Reads the attribute into `dst` (3 * count floats); count must equal the
 * agent count. */
SWCL_API swcl_status swcl_swarm_read(swcl_swarm swarm, swcl_attribute attribute,
                                     float* dst, size_t count);
/* Advances the swarm by `steps` time steps of desc.dt.  Without a behaviour
 * model agents move ballistically (p += v dt). */
SWCL_API swcl_status swcl_swarm_step(swcl_swarm swarm, uint32_t steps);
/* Advances the swarm by frames x every steps and writes its positions after
 * each `every` steps into dst: frame after frame, each as swcl_swarm_read
 * gives it (3 floats an agent, agent-id order, world by world); count =
 * frames x worlds x agents a world.  Gathered on the device and read back a
 * few frames at a time: the same frames as swcl_swarm_step(every) then
 * swcl_swarm_read, without waiting for the device after each. */
SWCL_API swcl_status swcl_swarm_step_frames(swcl_swarm swarm, uint32_t frames, uint32_t every, float* dst,
                                            size_t count);

/* Back to ballistic motion. */
SWCL_API swcl_status swcl_swarm_clear_model(swcl_swarm swarm);

typedef struct swcl_step_stats {
    uint32_t struct_size;
    uint32_t agents;
    uint32_t mde_moved_last;       /* agents moved by MDE in the last step */
    uint64_t mde_moved_total;      /* agents moved, summed over the steps since the last call */
    uint64_t steps;                /* steps since the last call */
} swcl_step_stats;

/* Statistics of the swarm's minimum distance enforcement stage since the
 * last call (waits for the device); zeros where the model runs none. */
SWCL_API swcl_status swcl_swarm_take_step_stats(swcl_swarm swarm, swcl_step_stats* out);
/* The same per world (summed above): out[k] for world k, count = worlds;
 * each out[k].struct_size set by the caller. */
SWCL_API swcl_status swcl_swarm_take_world_step_stats(swcl_swarm swarm, swcl_step_stats* out, size_t count);

/* Worlds: parameter `name` of the swarm's model in every world, values[k] for
 * world k (3 values per world, x y z, for a 3-vector); count = worlds x
 * components.  `name` is a key of the model's table (swcl_model_parameters:
 * "noise.scale", "goal.speed", "min_distance", ...) or its descriptor field.
 * Every value is checked before any is set: a value outside its range, NaN,
 * a wrong count or an unknown name give SWCL_ERROR_INVALID_ARGUMENT naming
 * the parameter, the world and the valid range, and nothing changes.  A
 * parameter whose row says "per_world": false must have one value in every
 * world (the policy model refuses its leader's parameters and u_max per
 * world outright); values that switch a kernel (a noise time scale of 0
 * beside one above 0, ...) are refused the same way, naming why.  A
 * model set later starts every world from its descriptor again. */
SWCL_API swcl_status swcl_swarm_set_world_param(swcl_swarm swarm, const char* name, const double* values,
                                                size_t count);
/* Reads it back: *out_count (if not NULL) = worlds x components; with
 * out_values NULL and count 0 only the count is asked for. */
SWCL_API swcl_status swcl_swarm_get_world_param(swcl_swarm swarm, const char* name, double* out_values,
                                                size_t count, size_t* out_count);

/* ---- neighbour search ----------------------------------------------------
 * Queries run on the device over the swarm's uniform grid (cell size =
 * interaction_radius) at the swarm's current positions.  Results are per agent
 * in agent-id order; `count` must equal the agent count.  Any radius > 0 works
 * (radii above the cell size search more cells).  An agent is never its own
 * neighbour; agents at the same position are neighbours at distance 0. */

/* Number of other agents within `radius` (distance <= radius) of each agent. */
SWCL_API swcl_status swcl_swarm_neighbor_count(swcl_swarm swarm, float radius,
                                               uint32_t* out_counts, size_t count);

/* Distance to, and id of, each agent's nearest other agent (ties: lowest id).
 * With a single agent the distance is +INFINITY and the id SWCL_NO_AGENT.
 * out_ids may be NULL. */
#define SWCL_NO_AGENT 0xFFFFFFFFu
SWCL_API swcl_status swcl_swarm_nearest_neighbor(swcl_swarm swarm, float* out_distances,
                                                 uint32_t* out_ids, size_t count);

/* Up to `max_neighbors` neighbour ids within `radius` per agent, nearest
 * first (ties: lowest id), into out_ids[agent * max_neighbors + k]; unused
 * entries are SWCL_NO_AGENT.  out_counts[agent] receives the full number of
 * neighbours, which exceeds max_neighbors where the list was truncated;
 * *out_truncated (may be NULL) the number of truncated agents. */
SWCL_API swcl_status swcl_swarm_neighbor_lists(swcl_swarm swarm, float radius,
                                               uint32_t max_neighbors, uint32_t* out_ids,
                                               uint32_t* out_counts, size_t count,
                                               uint32_t* out_truncated);


/* ---- scenario files --------------------------------------------------------
 * A JSON description of a run (docs/scenarios.md): model and parameters, agents
 * and their initial distribution, domain, obstacles, goal, steps, dt, seed and
 * outputs.  Loading validates everything; an error names the line and column
 * of malformed JSON, or the key path of a bad value
 * ("model.noise.scale: expected a number > 0"), with SWCL_ERROR_PARSE
 * (SWCL_ERROR_IO when the file cannot be read). */

typedef struct swcl_scenario { uint64_t id; } swcl_scenario;

SWCL_API swcl_status swcl_scenario_load(const char* path, swcl_scenario* out);
/* The same from JSON text of `length` bytes. */
SWCL_API swcl_status swcl_scenario_parse(const char* text, size_t length, swcl_scenario* out);
SWCL_API swcl_status swcl_scenario_destroy(swcl_scenario scenario);

typedef enum swcl_export_format {
    SWCL_EXPORT_CSV = 1,   /* <base>.csv: id,frame,P.x,P.y,P.z,v.x,v.y,v.z */
    SWCL_EXPORT_NPY = 2,   /* <base>_positions.npy, <base>_velocities.npy: float32 (frames, N, 3) */
    SWCL_EXPORT_VTP = 4,   /* <base>_<frame>.vtp per frame and <base>.pvd for ParaView */
    SWCL_EXPORT_FORMAT_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_export_format;

typedef struct swcl_scenario_info {
    uint32_t struct_size;
    uint32_t agents;
    uint32_t steps;
    uint32_t output_every;     /* record every k-th step */
    uint32_t output_formats;   /* swcl_export_format bits */
    float dt;
    uint64_t seed;
    char name[128];
    char output_dir[1024];
    char model[32];            /* "field", "path", "force", "energy" or "ballistic" */
    float min_distance;        /* the field model's MDE distance (0: none) */
} swcl_scenario_info;

/* out->struct_size must be set by the caller. */
SWCL_API swcl_status swcl_scenario_get_info(swcl_scenario scenario, swcl_scenario_info* out);
/* A swarm as the scenario describes it: agents placed, velocities set, model
 * attached. */
SWCL_API swcl_status swcl_scenario_create_swarm(swcl_scenario scenario, swcl_context context,
                                                swcl_swarm* out);
/* The same as `worlds` worlds (swcl_swarm_desc.worlds): world k placed and
 * seeded as the scenario alone with seed world_seeds[k] (NULL: the
 * scenario's seed + k), each with the scenario's model; then
 * swcl_swarm_set_world_param varies its parameters per world.  Models that
 * do not run worlds refuse worlds > 1 (SWCL_ERROR_INVALID_ARGUMENT). */
SWCL_API swcl_status swcl_scenario_create_world_swarm(swcl_scenario scenario, swcl_context context,
                                                      uint32_t worlds, const uint64_t* world_seeds,
                                                      swcl_swarm* out);
/* The same with world k in a domain of its own: world_domains holds 6 x
 * worlds floats (world k's min x, y, z, then max x, y, z; NULL: the
 * scenario's domain for every world), world k being the scenario alone with
 * that domain (placed in it; its grid and noise walls its own; as
 * swcl_swarm_desc.world_domains).  A bad domain names the world and axis;
 * a model that needs one domain for every world (the path model) refuses
 * differing ones; nothing is created then. */
SWCL_API swcl_status swcl_scenario_create_world_swarm_in_domains(swcl_scenario scenario, swcl_context context,
                                                                 uint32_t worlds, const uint64_t* world_seeds,
                                                                 const float* world_domains, swcl_swarm* out);

/* ---- recording trajectories -------------------------------------------------
 * Writes frames of a swarm to `dir` (created if missing) in the chosen formats.
 * Every file is written to a temporary name and renamed when complete, so an
 * interrupted run never leaves a truncated file behind; without
 * swcl_recorder_finish the CSV, .npy and .pvd files are discarded. */

typedef struct swcl_recorder { uint64_t id; } swcl_recorder;

SWCL_API swcl_status swcl_recorder_create(const char* dir, const char* basename, uint32_t formats,
                                          swcl_recorder* out);
/* Reads the swarm's positions and velocities and appends them as `frame` at
 * simulation time `time` (s). */
SWCL_API swcl_status swcl_recorder_add_frame(swcl_recorder recorder, swcl_swarm swarm, uint32_t frame,
                                             double time);
SWCL_API swcl_status swcl_recorder_finish(swcl_recorder recorder);
SWCL_API swcl_status swcl_recorder_destroy(swcl_recorder recorder);

/* The export formats by name, as scenario files ("output.formats") and
 * `swarmcl run --format` name them.  The name of one format's bit ("csv",
 * "npy", "vtp"); NULL for 0, several bits or a bit no format has. */
SWCL_API const char* swcl_export_format_name(uint32_t format);
/* "csv,npy" -> SWCL_EXPORT_CSV | SWCL_EXPORT_NPY in *out.
 * SWCL_ERROR_INVALID_ARGUMENT for an unknown name (swcl_last_error names it
 * and the known ones), an empty name or an empty list; *out is unchanged. */
SWCL_API swcl_status swcl_export_formats_parse(const char* list, uint32_t* out);

/* ==== EXPERIMENTAL: the models ================================================
 * Obstacles, noise fields and the four models of the papers.  Their functions
 * and descriptors may still change between 0.x minor versions (a descriptor
 * only grows at its end, read through struct_size); everything above this line
 * is the stable core, which does not change before 1.0 except by additions.
 * docs/c-api.md says which is which and why. */

/* ---- obstacles ---------------------------------------------------------------
 * One obstacle type for every model.  Where a model takes a shape analytically
 * (the noise field's boundaries of the curl-noise paper's Eq. 2, the force
 * model's obstacle ramp, Eq. 8-9) it takes SPHERE, BOX and PLANE; where it
 * builds a signed distance grid (the path model, the force model's
 * mesh_obstacles) it takes MESH, OBJ, BOX, SPHERE and CYLINDER as triangle
 * meshes.  Arrays and the path are copied by the call.  Degenerate triangles
 * are skipped; NaN coordinates and out-of-range indices are errors. */

typedef enum swcl_obstacle_type {
    SWCL_OBSTACLE_MESH = 0,      /* vertices (packed xyz), indices (3 per triangle) */
    SWCL_OBSTACLE_OBJ = 1,       /* path of a Wavefront OBJ file */
    SWCL_OBSTACLE_BOX = 2,       /* center, half_extents; radius = edge rounding where the
                                    box is analytic (0: a small default, the noise field
                                    needs rounded edges), unused where it is meshed */
    SWCL_OBSTACLE_SPHERE = 3,    /* center, radius */
    SWCL_OBSTACLE_CYLINDER = 4,  /* center = centre of the bottom cap, radius, height (along +z) */
    SWCL_OBSTACLE_PLANE = 5,     /* half space dot(normal, x) >= offset is free (analytic only) */
    SWCL_OBSTACLE_TYPE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_obstacle_type;

typedef struct swcl_obstacle {
    swcl_obstacle_type type;
    const float* vertices;
    uint32_t vertex_count;
    const uint32_t* indices;
    uint32_t triangle_count;
    const char* path;
    float center[3];
    float half_extents[3];
    float radius;
    float height;
    float normal[3];
    float offset;
} swcl_obstacle;

/* ---- noise fields ---------------------------------------------------------
 * The four noise functions of the data-driven noise paper (§4.2.1) and the
 * boundary-aware curl noise of the curl-noise paper (§4, Eq. 1-3):
 *   CURL      V = scale * curl N(x),  N = Eq. 2 applied to gain * (P1,P2,P3)(x/scale)
 *             (divergence-free; its normal part fades to 0 at boundaries)
 *   PERLIN    V = gain * (P1,P2,P3)(x/scale)
 *   WHITE     V = gain * U(-1, 1)^3, new for every agent and step
 *   GAUSSIAN  V = gain * N(0, 1)^3 (Box-Muller), new for every agent and step
 * Random draws are keyed by (seed, agent id, step) with Philox4x32-10, so they
 * do not depend on agent order or device.  docs/noise.md has the details. */

typedef enum swcl_noise_type {
    SWCL_NOISE_CURL = 0,
    SWCL_NOISE_PERLIN = 1,
    SWCL_NOISE_WHITE = 2,
    SWCL_NOISE_GAUSSIAN = 3,
    SWCL_NOISE_TYPE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_noise_type;

typedef struct swcl_noise_desc {
    uint32_t struct_size;
    swcl_noise_type type;          /* default CURL */
    float scale;                   /* feature size, m (default 0.4, curl-noise paper Table 1) */
    float gain;                    /* speed, m/s (default 0.25, Table 1) */
    uint64_t seed;                 /* seeds the three potentials and the random draws */
    float time_scale;              /* > 0: the field varies in time (4D noise), seconds
                                      per noise unit; 0: a static field (default) */
    float boundary_distance;       /* d0 of Eq. 3, m (default 0.4 = scale) */
    int32_t domain_walls;          /* 1: the region box keeps insects in ("extended
                                      boundaries", §4); default 0 */
    float region_min[3];           /* walls and bake region; all zero: the swarm's */
    float region_max[3];           /* domain (required without a swarm) */
    const swcl_obstacle* boundaries;  /* SPHERE, BOX and PLANE obstacles of Eq. 2, copied */
    uint32_t boundary_count;
    int32_t baked;                 /* 1: bake onto a grid over the region, then
                                      sample trilinearly (CURL and PERLIN, static) */
    uint32_t bake_resolution[3];   /* grid nodes per axis (default 64) */
    int32_t finite_difference;     /* 1: curl by central differences (for checking) */
    float fd_step;                 /* m; 0: scale / 100 */
} swcl_noise_desc;

SWCL_API swcl_noise_desc swcl_noise_desc_default(void);

/* Samples a noise field at `count` packed xyz points into out_xyz (3 * count
 * floats) at time `time` (s) and step `step`; point i counts as agent i for
 * WHITE and GAUSSIAN.  Bad parameters or a NaN point change nothing. */
SWCL_API swcl_status swcl_noise_sample(swcl_context context, const swcl_noise_desc* desc,
                                       const float* points, size_t count, float time,
                                       uint32_t step, float* out_xyz);

/* ---- the field model ------------------------------------------------------
 * The local behaviour of the curl-noise paper (§4, §6): each step every agent
 * takes the noise velocity at its position plus, outside the goal sphere, a
 * pull to the goal at speed goal_speed (s0); moves by v dt; then pairs closer
 * than min_distance are pushed apart (minimum distance enforcement, MDE). */

typedef struct swcl_field_model_desc {
    uint32_t struct_size;
    swcl_noise_desc noise;
    int32_t has_goal;              /* default 0 */
    float goal[3];
    float goal_radius;             /* no pull inside, m (default 0) */
    float goal_speed;              /* s0, m/s (default 1.5, Table 1) */
    float goal_falloff;            /* m over which the pull grows from 0 at the goal
                                      sphere to s0 (default 0: at once, as the paper) */
    float min_distance;            /* MDE threshold, m; 0: off (default 0) */
    float max_speed;               /* m/s: a faster agent's velocity is scaled down
                                      to this speed; 0: no limit (default) */
} swcl_field_model_desc;

SWCL_API swcl_field_model_desc swcl_field_model_desc_default(void);
/* Makes the field model move the swarm from the next step on (a baked noise
 * is baked here).  On failure the swarm keeps its previous model. */
SWCL_API swcl_status swcl_swarm_field_set_model(swcl_swarm swarm, const swcl_field_model_desc* desc);
/* ---- the path model ---------------------------------------------------------
 * The curl-noise paper's full model (§5-6, Eq. 9; docs/path-field.md): obstacle
 * meshes -> signed distance grid (Eq. 5) -> repulsion (Eq. 6) -> minimum cost
 * field C by fast marching (|grad C| = A + B g, Eq. 4/7) towards the goals ->
 * global velocity -grad C/|grad C| * s0 (Eq. 8), added to the curl noise whose
 * boundaries now include the meshes; position update; MDE.  Agents form
 * groups (consecutive agent ids), each with its own goals and cost field.
 * Preprocessing happens in swcl_swarm_path_set_model. */

typedef enum swcl_goal_type {
    SWCL_GOAL_POINT = 0,   /* center */
    SWCL_GOAL_SPHERE = 1,  /* center, radius */
    SWCL_GOAL_BOX = 2,     /* center, half_extents */
    SWCL_GOAL_TYPE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_goal_type;

typedef struct swcl_goal {
    swcl_goal_type type;
    float center[3];
    float radius;
    float half_extents[3];
} swcl_goal;

typedef struct swcl_path_group {
    uint32_t agents;               /* consecutive agent ids; the last group takes the rest */
    const swcl_goal* goals;
    uint32_t goal_count;
} swcl_path_group;

typedef struct swcl_path_model_desc {
    uint32_t struct_size;
    swcl_noise_desc noise;         /* V_l; default curl, scale 0.4, gain 0.25 (Table 1) */
    const swcl_obstacle* obstacles;
    uint32_t obstacle_count;
    float grid_min[3];             /* the path grid; all zero: the swarm's domain */
    float grid_max[3];
    uint32_t resolution[3];        /* cells per axis at most, cubic cells (default 64) */
    float cost_a;                  /* A of Eq. 4 (default 0.6, §5) */
    float cost_b;                  /* B of Eq. 4 (default 0.4) */
    int32_t second_order;          /* 1: second-order fast marching (default 0) */
    float speed;                   /* s0 of Eq. 8, m/s (default 1.5, Table 1) */
    float goal_falloff;            /* m of path over which V_g grows from 0 at a goal to s0
                                      (default 0: at once, as the paper) */
    float min_distance;            /* MDE threshold, m; 0: off (default 0) */
    const swcl_goal* goals;        /* one group: every agent, these goals */
    uint32_t goal_count;
    const swcl_path_group* groups; /* or several groups (group_count > 0 replaces goals) */
    uint32_t group_count;
} swcl_path_model_desc;

SWCL_API swcl_path_model_desc swcl_path_model_desc_default(void);
/* Preprocesses and makes the path model move the swarm.  Bad meshes, goals
 * outside the grid or inside an obstacle, grids of 0 or too many cells: an
 * error status, and the swarm keeps its previous model. */
SWCL_API swcl_status swcl_swarm_path_set_model(swcl_swarm swarm, const swcl_path_model_desc* desc);
/* Moves a group's goals (chasing, §7): its cost field is recomputed;
 * out_seconds (may be NULL) receives the time it took. */
SWCL_API swcl_status swcl_swarm_path_set_goals(swcl_swarm swarm, uint32_t group, const swcl_goal* goals,
                                               uint32_t goal_count, double* out_seconds);

typedef struct swcl_path_info {
    uint32_t struct_size;
    uint32_t grid[3];              /* cells per axis */
    float cell;                    /* cell edge, m */
    float grid_min[3];
    double preprocess_seconds;     /* signed distance + cost fields + uploads */
    uint32_t groups;
    uint32_t recomputes;           /* cost fields recomputed after a goal moved */
    double recompute_seconds;      /* their total time */
} swcl_path_info;

/* out->struct_size must be set by the caller; SWCL_ERROR_INVALID_ARGUMENT when
 * the swarm has no path model. */
SWCL_API swcl_status swcl_swarm_path_get_info(swcl_swarm swarm, swcl_path_info* out);

/* ---- the path model: chasing targets and the lamp (seed 004 §7) -----------
 * Chasing: a target ball is a goal of its group and a boundary of Eq. 2 (the
 * curl noise goes round it).  Set its centre each step, as a user drags it:
 * the group's cost field and the noise boundaries (rebaked when baked) are
 * recomputed only when it moved.  Phototaxis: each step each insect, with
 * `probability`, gets `speed` m/s towards the lamp, turned by `angle` about
 * the vertical axis (docs/path-field.md, "Chasing and phototaxis").  A centre
 * outside the path grid or inside an obstacle, a lamp with no free space
 * around it: SWCL_ERROR_INVALID_ARGUMENT and nothing changes. */

typedef struct swcl_path_target {
    uint32_t group;                /* the group that chases it */
    float center[3];
    float radius;                  /* the ball, m (> 0) */
} swcl_path_target;

/* Adds a target (its group's field and the noise are recomputed); out_index
 * (may be NULL) receives its index, 0, 1, ... in the order added. */
SWCL_API swcl_status swcl_swarm_path_add_target(swcl_swarm swarm, const swcl_path_target* target,
                                                uint32_t* out_index);
/* Moves target `index`; out_seconds (may be NULL) receives the time the
 * recomputation took (0 when the centre did not change). */
SWCL_API swcl_status swcl_swarm_path_set_target(swcl_swarm swarm, uint32_t index, const float center[3],
                                                double* out_seconds);
SWCL_API swcl_status swcl_swarm_path_get_target(swcl_swarm swarm, uint32_t index, swcl_path_target* out);
SWCL_API swcl_status swcl_swarm_path_target_count(swcl_swarm swarm, uint32_t* out_count);

typedef struct swcl_path_lamp {
    uint32_t struct_size;
    int32_t enabled;               /* 0: no lamp (default) */
    float center[3];
    float radius;                  /* the bulb, m (default 0.1) */
    float probability;             /* of a pull per insect per step (default 0.5) */
    float speed;                   /* m/s of a pull (default 1) */
    float angle;                   /* rad in [0, pi/2] off the line of sight, counter-clockwise
                                      about +z (default 0: straight at the lamp) */
    float keep_out;                /* m: the radial pull fades to 0 at the bulb over this (default 0.2) */
} swcl_path_lamp;

SWCL_API swcl_path_lamp swcl_path_lamp_default(void);
SWCL_API swcl_status swcl_swarm_path_set_lamp(swcl_swarm swarm, const swcl_path_lamp* lamp);


/* ---- FASTSWARM: data-driven energy model ---------------------------------
 * Xiang et al., "FASTSWARM" (docs/energy-model.md).  A reference dataset D of
 * (velocity, acceleration) samples is built from real 3D tracks (forward
 * differences, §3), subsampled to k samples, sorted by speed and split into
 * speed groups (§5.2.1).  Each step every agent picks the sample velocity of
 * its own and the neighbouring speed groups that minimises
 *   E = E_rep + E_oa + E_cos + E_dir + E_acc + E_env + E_n + E_user  (Eq. 2-14)
 * (ties: the lowest sample index) and moves p += v dt. */
typedef struct swcl_dataset { uint64_t id; } swcl_dataset;

typedef enum swcl_time_format {
    SWCL_TIME_AUTO = 0,      /* a number: seconds; else "YYYY-MM-DD HH:MM:SS[.f]" */
    SWCL_TIME_SECONDS = 1,
    SWCL_TIME_FRAME = 2,     /* integer frame numbers times frame_time */
    SWCL_TIME_DATETIME = 3,
    SWCL_TIME_FORMAT_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_time_format;

typedef struct swcl_dataset_desc {
    uint32_t struct_size;
    /* Track CSV columns: header names, or 0-based indices written in digits.
     * NULL: "id", "time", "x", "y", "z". */
    const char* column_id;
    const char* column_time;
    const char* column_x;
    const char* column_y;
    const char* column_z;
    swcl_time_format time_format;  /* default AUTO */
    double frame_time;             /* s; 0: the median step of the data (default) */
    double unit_scale;             /* position unit in metres (default 1; 0.01 for cm) */
    double gap_factor;             /* steps above gap_factor * frame_time split a track (1.5) */
    uint32_t smoothing;            /* half-width of a moving average of positions (0: none) */
    uint32_t k;                    /* samples kept (default 300, §5.2.1) */
    uint32_t groups;               /* speed groups (default 10) */
    uint64_t seed;                 /* the subsampling draw */
    float synthetic_mean_speed;    /* swcl_dataset_synthetic only: m/s (default 0.5) */
    /* Added at the end (read only when struct_size covers it; else ','): */
    char delimiter;                /* the CSV's field separator: ',' (default), ';', '\t', ... */
} swcl_dataset_desc;
SWCL_API swcl_dataset_desc swcl_dataset_desc_default(void);
/* From a track CSV file (errors name the line and column). */
SWCL_API swcl_status swcl_dataset_from_csv(const char* path, const swcl_dataset_desc* desc, swcl_dataset* out);
/* From tracks as arrays: track k has counts[k] (>= 3) samples; times (s) and
 * packed xyz positions (in unit_scale units) run over all tracks in order. */
SWCL_API swcl_status swcl_dataset_from_tracks(const uint32_t* counts, size_t track_count, const double* times,
                                              const float* xyz, const swcl_dataset_desc* desc, swcl_dataset* out);
/* From deterministic synthetic tracks (tests and examples without data;
 * frame_time 0 means 0.01 s). */
SWCL_API swcl_status swcl_dataset_synthetic(const swcl_dataset_desc* desc, swcl_dataset* out);
/* Dataset files (a small checked binary format, docs/energy-model.md). */
SWCL_API swcl_status swcl_dataset_load(const char* path, swcl_dataset* out);
SWCL_API swcl_status swcl_dataset_save(swcl_dataset dataset, const char* path);
SWCL_API swcl_status swcl_dataset_destroy(swcl_dataset dataset);
typedef struct swcl_dataset_info {
    uint32_t struct_size;
    uint32_t samples;
    uint32_t groups;
    double frame_time;             /* s, of the source data */
} swcl_dataset_info;
SWCL_API swcl_status swcl_dataset_get_info(swcl_dataset dataset, swcl_dataset_info* out);
/* The samples sorted by speed: velocities (m/s) and accelerations (m/s^2),
 * packed xyz, `count` = samples; either pointer may be NULL. */
SWCL_API swcl_status swcl_dataset_read(swcl_dataset dataset, float* out_velocities, float* out_accelerations,
                                       size_t count);

typedef struct swcl_energy_weights {
    float rep, oa, cos, dir, acc, env, noise, user;   /* Table 1 columns, >= 0 */
} swcl_energy_weights;
typedef enum swcl_stimulus_kind {
    SWCL_STIMULUS_ATTRACT = 0,     /* a female, a light: Psi = |v^ - v^_sti| (Eq. 12) */
    SWCL_STIMULUS_STARTLE = 1,     /* a danger: Psi = 1 - |p' - p_sti| / d_danger within d_danger */
    SWCL_STIMULUS_KIND_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_stimulus_kind;
typedef struct swcl_stimulus {
    swcl_stimulus_kind kind;
    float position[3];             /* at time 0, m */
    float velocity[3];             /* m/s: the stimulus moves as position + velocity * t */
    float d_danger;                /* m, > 0 (STARTLE) */
} swcl_stimulus;
typedef struct swcl_energy_model_desc {
    uint32_t struct_size;
    swcl_energy_weights weights;         /* default: Table 1 aggregation (1 1 0.05 1 1 0 0.2 0) */
    swcl_energy_weights danger_weights;  /* within d_danger of a STARTLE stimulus
                                            (default Table 1 escaping, in danger: 1 0 0 1 1 2 0.3 0) */
    float rho;                     /* 2.5 (§5) */
    float d_rep;                   /* repulsion radius, m (default 0.04) */
    float d_att1, d_att2;          /* attraction between these, m (0.1, 0.4) */
    int32_t has_fixed_centre;      /* 1: E_cos pulls towards fixed_centre; 0 (default): */
    float fixed_centre[3];         /* towards the swarm centre (mean position) */
    uint32_t span;                 /* neighbouring speed groups searched per side (1) */
    float accel_time;              /* s scaling |a'| - |a| (Eq. 10); 0: the dataset's frame time */
    float danger_horizon;          /* s of look-ahead for the startled term (1) */
    swcl_noise_desc noise;         /* f_N (default curl, scale 0.2 m, time_scale 1 s) */
    const swcl_stimulus* stimuli;  /* copied by the call */
    uint32_t stimulus_count;
    const float* keypoints;        /* packed xyz, >= 2 points or none: f_CD of Eq. 15 */
    uint32_t keypoint_count;
    int32_t keypoints_closed;      /* 1: the curve is a loop (default 1) */
    int32_t bidirectional;         /* 1: odd agent ids traverse it backwards (default 1) */
    float keypoint_reach;          /* m within which a keypoint counts as reached (0.05) */
    int32_t keep_out;              /* 1 (default): a velocity whose predicted closest approach to a
                                      STARTLE stimulus (within danger_horizon) is inside its d_danger
                                      is chosen only when every candidate's is (the least entering
                                      one); 0: Eq. 11-12 alone */
} swcl_energy_model_desc;
SWCL_API swcl_energy_model_desc swcl_energy_model_desc_default(void);
/* Makes the energy model with `dataset` move the swarm from the next step on
 * (the dataset is kept alive by the model).  On failure the swarm keeps its
 * previous model. */
SWCL_API swcl_status swcl_swarm_energy_set_model(swcl_swarm swarm, swcl_dataset dataset,
                                                 const swcl_energy_model_desc* desc);
/* Replace the stimuli or keypoints of the swarm's energy model (new keypoints
 * restart every agent's traversal).  SWCL_ERROR_INVALID_ARGUMENT if the swarm
 * has no energy model. */
SWCL_API swcl_status swcl_swarm_energy_set_stimuli(swcl_swarm swarm, const swcl_stimulus* stimuli, uint32_t count);
SWCL_API swcl_status swcl_swarm_energy_set_keypoints(swcl_swarm swarm, const float* xyz, uint32_t count,
                                                     int32_t closed);
/* Per agent (id order; world by world on a swarm of worlds, count = worlds x
 * agents a world): the goal keypoint index, -1 before the first step. */
SWCL_API swcl_status swcl_swarm_energy_get_goals(swcl_swarm swarm, int32_t* out_goals, size_t count);
/* Trajectory synthesis (§5.2.3): one agent per track (arrays as in
 * swcl_dataset_from_tracks; desc: unit_scale, gaps, smoothing; NULL: defaults)
 * placed at the last sample of the track's last gap-free segment with its last
 * forward-difference velocity; sets the agent count.  Step on to continue the
 * tracks. */
SWCL_API swcl_status swcl_swarm_start_from_tracks(swcl_swarm swarm, const uint32_t* counts, size_t track_count,
                                                  const double* times, const float* xyz,
                                                  const swcl_dataset_desc* desc);

/* ---- the force model ------------------------------------------------------
 * The shape-constrained flying insects paper (Chen et al. 2019): each step
 *   F = alpha F_internal + (1 - alpha) F_external                     (Eq. 1)
 *   F_internal = three-zone interaction (Eq. 2-3) + curl noise (Eq. 4)
 *   F_external = shape-constrained force (Eq. 5) + distance force (Eq. 6-7)
 * towards target points sampled on the current keyframe's mesh (one per
 * agent), then (with speed_relaxation) the speed relaxed towards
 * preferred_speed, u += F dt with |u| <= max_speed (and >= cruise_speed), the
 * obstacle ramp (Eq. 8-9), r += u dt, and optional MDE.  The shape's frame
 * can follow a B-spline path.  Defaults are Table 1's values;
 * docs/force-model.md lists where the paper was vague and what was chosen. */

typedef enum swcl_assignment {
    SWCL_ASSIGN_NEAREST = 0,  /* each agent (in id order) takes the nearest free target */
    SWCL_ASSIGN_CURVE = 1,    /* both sets ordered along a Hilbert curve, matched by rank */
    SWCL_ASSIGNMENT_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_assignment;

/* A target mesh from `frame` on: a generated shape by name ("sphere", "torus",
 * "moon", "star", "heart", "mammoth", "shark", "horse", "horse:<phase>") or,
 * with shape NULL, packed xyz vertices and triangle indices (copied).  The
 * mesh is then scaled by `scale` (0: 1) and moved by `offset`. */
typedef struct swcl_keyframe {
    uint32_t frame;
    const char* shape;
    const float* vertices;
    uint32_t vertex_count;
    const uint32_t* triangles;
    uint32_t triangle_count;
    float scale;
    float offset[3];
} swcl_keyframe;

typedef struct swcl_force_model_desc {
    uint32_t struct_size;
    float r_rep, r_ali, r_att;     /* zone radii, m (Table 1: 0.3, 10, 30) */
    float w_rep, w_ali, w_att;     /* Eq. 2 weights (Table 1: 0.2, 3, 13) */
    float w_dis;                   /* Eq. 6 weight (Table 1: 4) */
    float w_con;                   /* Eq. 5 weight (1) */
    float omega;                   /* Eq. 5: sigma = omega sqrt(A/N) (0.9) */
    float neighbor_k;              /* Eq. 5 neighbours within k sqrt(A/N), Manhattan (2) */
    float distance_scale;          /* m normalising d in Eq. 6; 0: 2 sqrt(A/N) (default 0) */
    uint32_t neighbor_sample;      /* > 0: alignment and attraction sample this many
                                      agents of the swarm per agent and step (not in
                                      the paper; docs/force-model.md); 0: every agent
                                      within r_att, exact (default) */
    float eta, rho;                /* Eq. 4 curl noise magnitude and feature size, m
                                      (Table 1: 0.125, 0.32) */
    uint64_t noise_seed;
    float alpha;                   /* Eq. 1, in [0, 1] (Table 1: 0.7) */
    float max_speed;               /* m/s (Table 1: 0.75) */
    float cruise_speed;            /* m/s, slower agents are sped up to it (0.375;
                                      0: off, as the paper) */
    float min_distance;            /* MDE threshold, m; 0: off (default 0) */
    float min_spacing;             /* meshes scaled so sqrt(A/N) >= this, m (0.3 = r_rep;
                                      0: meshes as given) */
    swcl_assignment assignment;    /* default NEAREST */
    uint64_t sample_seed;          /* stratified sampling */
    const swcl_keyframe* keyframes;  /* strictly increasing frames (copied) */
    uint32_t keyframe_count;
    uint32_t keyframe_period;      /* > 0: the keyframes repeat every this many steps */
    const float* path;             /* B-spline control points, packed xyz (>= 4), copied */
    uint32_t path_point_count;     /* 0: no path */
    float path_speed;              /* m/s along the path */
    const swcl_obstacle* obstacles;  /* SPHERE and BOX obstacles (Eq. 8-9), copied */
    uint32_t obstacle_count;
    float obstacle_range;          /* L of Eq. 9, m (default 1) */
    /* Added after the first version (a struct_size that ends before it reads
     * as the default): */
    uint32_t path_orient;          /* 1 (default): the shape's frame turns with the path,
                                      its forward axis +x along the tangent and its +z
                                      up along a rotation-minimising frame; 0: the
                                      frame is translated only */
    /* Added with mesh obstacles (a struct_size that ends before them reads as
     * none; docs/force-model.md): */
    const swcl_obstacle* mesh_obstacles;  /* triangle meshes, OBJ files and box, sphere and
                                             cylinder meshes (the path section's type),
                                             avoided like `obstacles` through a signed
                                             distance grid built once here (copied) */
    uint32_t mesh_obstacle_count;
    float mesh_cell;               /* cell edge of that grid, m; 0 (default):
                                      obstacle_range / 4.  At most 2^24 cells over the
                                      meshes' bounds grown by obstacle_range + 2 cells,
                                      else SWCL_ERROR_INVALID_ARGUMENT */
    /* Added with the speed relaxation (a struct_size that ends before them
     * reads as off; not in the paper, docs/force-model.md): */
    float speed_relaxation;        /* 1/s, in [0, 1000]: before each Newton step the
                                      speed s relaxes towards preferred_speed s0,
                                      s <- s0 + (s - s0) exp(-speed_relaxation dt),
                                      the heading kept; 0: off (default) */
    float preferred_speed;         /* m/s, s0 (default 0: with a rate, a linear drag) */
    /* Added with the insects' own paces (a struct_size that ends before it
     * reads as 0; not in the paper, docs/force-model.md): */
    float speed_spread;            /* in [0, 3]: insect i's forces and speeds (max, cruise,
                                      preferred) are scaled by f_i = exp(s z_i - s^2/2),
                                      z_i ~ N(0, 1) drawn once per insect (by noise_seed
                                      and id); 0: insects alike (default) */
} swcl_force_model_desc;

SWCL_API swcl_force_model_desc swcl_force_model_desc_default(void);
/* Makes the force model move the swarm from the next step on (target meshes
 * are sampled here).  On failure the swarm keeps its previous model. */
SWCL_API swcl_status swcl_swarm_force_set_model(swcl_swarm swarm, const swcl_force_model_desc* desc);
/* Replace the keyframes or the path of the swarm's force model (the rest of
 * its parameters stay); SWCL_ERROR_INVALID_ARGUMENT if the swarm has none. */
SWCL_API swcl_status swcl_swarm_force_set_keyframes(swcl_swarm swarm, const swcl_keyframe* keyframes,
                                                    uint32_t count, uint32_t period);
SWCL_API swcl_status swcl_swarm_force_set_path(swcl_swarm swarm, const float* points, uint32_t count,
                                               float speed);
/* The target points of the current keyframe (packed xyz, the shape frame
 * placed on the path at the swarm's current step: moved, and turned with it
 * unless path_orient is 0) for agent ids 0..count-1 (world by world on a
 * swarm of worlds): where each agent is heading. */
SWCL_API swcl_status swcl_swarm_force_get_targets(swcl_swarm swarm, float* out_xyz, size_t count);

/* ---- Deep-RL swarms: the batched leader-following environment (issue 15) ----
 * W independent worlds of N followers and one leader each (paper
 * drl-swarm-animation-rule-based-action-generator, §III; docs/rl-swarm.md).
 * Every array is whole and in slot order, slot = world * N + agent:
 * actions W*N*4 {Δu, Δq.xyz}, observations W*N*obs_dim (54; 51 without EFS),
 * rewards W*N, terminated / truncated flags W.  No call is per agent. */
typedef struct swcl_rl_env { uint64_t id; } swcl_rl_env;

typedef struct swcl_rl_env_desc {
    uint32_t struct_size;
    uint32_t worlds, agents;       /* W >= 1, N >= 1, W*N <= 2^24 */
    const char* scenario;          /* "roaming" (joystick leader, default),
                                      "quadrilateral", "stairway", "maze" */
    const float* waypoints;        /* optional: packed (x, y, z, target speed), >= 2;
                                      replaces the scenario's path (navigation leader) */
    uint32_t waypoint_count;
    const float* obstacles;        /* optional boxes (cx, cy, cz, hx, hy, hz): added to
                                      the scenario's */
    uint32_t obstacle_count;
    uint32_t max_steps;            /* M, truncation (Table 1: 1200) */
    int32_t efs;                   /* 1: embedded swarm features (54 obs); 0: ablation (51) */
    float dt, du_max, dq_max_deg;  /* Table 1: 0.1, 0.1, 4 */
    float r_sep, r_ali, r_coh;     /* Table 1: 1, 9, 18 */
    float u_max;                   /* speed ceiling (3) */
    float body_radius;             /* agents' sphere for the rays (0.5) */
    float neighbor_radius;         /* EFS / reward neighbours; 0: r_coh */
    float rag_w_sep, rag_w_ali, rag_w_coh;  /* Eq. 8 weights (4, 2, 2) */
    float w_spd, w_dir, w_leader, w_obs, w_dist;  /* Table 1: 1.3, 1, 4.9, 16, 9.5 */
    float l_spd, l_dir, l_leader, l_obs;          /* λ (ours: 2, 1, 0.1, 0.5) */
    float dist_target;             /* Eq. 19's neighbour distance; 0: (r_ali - r_sep) / 2 */
    /* The RAG's leader coupling (ours; docs/rl-swarm.md).  Callers built
     * before these fields pass the smaller struct and get the defaults. */
    int32_t rag_leader_pd;         /* 1: a PD pull of its own (default); 0: the leader is
                                      one more Eq. 8 term in its zone */
    float rag_leader_kp, rag_leader_kd;  /* k_p (|p_L - p| - r_ali)+ toward the leader
                                            + k_d (v_L - v): 0.25, 1 */
} swcl_rl_env_desc;

SWCL_API swcl_rl_env_desc swcl_rl_env_desc_default(void);
SWCL_API swcl_status swcl_rl_env_create(swcl_context context, const swcl_rl_env_desc* desc, swcl_rl_env* out);
SWCL_API swcl_status swcl_rl_env_destroy(swcl_rl_env env);
/* out_obs_dim: 54, or 51 without EFS. */
SWCL_API swcl_status swcl_rl_env_get_info(swcl_rl_env env, uint32_t* out_worlds, uint32_t* out_agents,
                                          uint32_t* out_obs_dim);
/* The layout every world shares, as the scenario and desc made it: the
 * navigation leader's waypoints (x, y, z, target speed; none for a joystick
 * leader) and the box obstacles (centre xyz, half extents xyz).  The counts
 * go to out_*_count (may be NULL); an array may be NULL (only its count is
 * wanted), else its capacity, in rows of 4 (6) floats, must hold them all:
 * SWCL_ERROR_INVALID_ARGUMENT naming the rows needed otherwise, nothing
 * written.  For drawing the scenario or meshing its obstacles. */
SWCL_API swcl_status swcl_rl_env_get_layout(swcl_rl_env env, float* out_waypoints, size_t waypoint_capacity,
                                            uint32_t* out_waypoint_count, float* out_obstacles,
                                            size_t obstacle_capacity, uint32_t* out_obstacle_count);
/* Every world to its start (same seed: the same bits); out_obs may be NULL. */
SWCL_API swcl_status swcl_rl_env_reset(swcl_rl_env env, uint64_t seed, float* out_obs, size_t obs_count);
/* Every world to its start with its own seed: world w gets the bits it gets
 * from swcl_rl_env_reset(seeds[w]) (seed_count = W entries); out_obs may be NULL. */
SWCL_API swcl_status swcl_rl_env_reset_seeds(swcl_rl_env env, const uint64_t* seeds, size_t seed_count,
                                             float* out_obs, size_t obs_count);
/* Only the worlds with mask[w] != 0 (W entries), each to its next episode's
 * start; out_obs (all worlds) may be NULL. */
SWCL_API swcl_status swcl_rl_env_reset_worlds(swcl_rl_env env, const uint8_t* mask, size_t mask_count,
                                              float* out_obs, size_t obs_count);
/* One step of every world.  Actions must be finite (else nothing moves).
 * Any output pointer may be NULL (its count is then ignored). */
SWCL_API swcl_status swcl_rl_env_step(swcl_rl_env env, const float* actions, size_t action_count,
                                      float* out_obs, size_t obs_count, float* out_rewards, size_t reward_count,
                                      uint8_t* out_terminated, uint8_t* out_truncated, size_t world_count);
/* The rule-based action generator's actions (Eq. 8-10) for the current
 * state, W*N*4: pass them to step for the rule-based baseline. */
SWCL_API swcl_status swcl_rl_env_rag_actions(swcl_rl_env env, float* out_actions, size_t action_count);
/* Joystick leaders: W*4 {Δu, Δq.xyz} per step, kept until changed. */
SWCL_API swcl_status swcl_rl_env_set_leader_controls(swcl_rl_env env, const float* controls, size_t count);
/* State, any pointer NULL to skip: follower positions (x, y, z, 0) and
 * velocities (q.xyz, u), W*N*4 each; leaders' the same, W*4 each. */
SWCL_API swcl_status swcl_rl_env_read_state(swcl_rl_env env, float* out_pos, size_t pos_count, float* out_vel,
                                            size_t vel_count, float* out_leader_pos, float* out_leader_vel,
                                            size_t leader_count);

/* ---- the policy model (issue 15 item 7) -------------------------------------
 * A trained actor (an MLP in a safetensors file: docs/rl-swarm.md, "Policy
 * model") drives the swarm's agents as followers of one leader: each step
 * the observations of Eq. 11-13 (the environment's, over the swarm's
 * neighbour grid), the MLP batched over agents on the device, Eq. 2's
 * kinematics with the swarm's dt (Table 1: 0.1 s).  Velocities read from
 * the swarm are u q.  Bad weights (truncated, wrong shapes or dtype, corrupt
 * header) give SWCL_ERROR_PARSE naming the problem; the swarm keeps its
 * previous model.  models/policy_roaming.safetensors is a shipped policy. */
typedef enum swcl_policy_leader_mode {
    SWCL_POLICY_LEADER_JOYSTICK = 0,    /* controls through swcl_swarm_policy_set_leader_controls */
    SWCL_POLICY_LEADER_NAVIGATION = 1,  /* through the waypoints, stops after the last */
    SWCL_POLICY_LEADER_TOUR = 2,        /* through the waypoints, over and over */
    SWCL_POLICY_LEADER_MODE_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_policy_leader_mode;

typedef struct swcl_policy_model_desc {
    uint32_t struct_size;
    const char* weights_path;      /* a safetensors file, or NULL with weights_data */
    const void* weights_data;      /* the file's bytes in memory (used when weights_path is NULL) */
    size_t weights_size;
    swcl_policy_leader_mode leader_mode;  /* default JOYSTICK */
    const float* waypoints;        /* packed (x, y, z, target speed), >= 2 for NAVIGATION / TOUR */
    uint32_t waypoint_count;
    float leader_position[3];      /* default origin */
    float leader_heading[3];       /* default +x (normalised) */
    float leader_speed;            /* default 0.5 */
    float leader_du_max, leader_dq_max_deg, reach_radius;  /* 0.1, 4, 2 */
    float r_sep, r_ali, r_coh;     /* Table 1: 1, 9, 18 */
    float neighbor_radius;         /* EFS neighbours; 0: r_coh */
    float body_radius;             /* agents' sphere for the rays (0.5) */
    float du_max, dq_max_deg, u_max;  /* Table 1: 0.1, 4; u_max 3 */
    const float* obstacles;        /* boxes (cx, cy, cz, hx, hy, hz) */
    uint32_t obstacle_count;
} swcl_policy_model_desc;

SWCL_API swcl_policy_model_desc swcl_policy_model_desc_default(void);
SWCL_API swcl_status swcl_swarm_policy_set_model(swcl_swarm swarm, const swcl_policy_model_desc* desc);
/* Joystick leader: {du, dq.xyz} applied every step (Eq. 1 with h = one step),
 * kept until changed. */
SWCL_API swcl_status swcl_swarm_policy_set_leader_controls(swcl_swarm swarm, const float controls[4]);
/* The leader now: position xyz and (q.xyz, u); either pointer may be NULL.
 * A swarm of worlds has a leader a world, all alike at the start and driven
 * alike: these are world 0's. */
SWCL_API swcl_status swcl_swarm_policy_get_leader(swcl_swarm swarm, float out_position[3], float out_heading_speed[4]);
/* The loaded policy: observation size (54 or 51), layer count, widths of
 * its layers' outputs (up to 8 written to out_widths, may be NULL). */
SWCL_API swcl_status swcl_swarm_policy_get_info(swcl_swarm swarm, uint32_t* out_obs_dim, uint32_t* out_layers,
                                                uint32_t* out_widths);
/* The observations of the current state (count * obs_dim floats) and the
 * policy's actions on them (count * 4), agent-id order (world by world:
 * count is every world's agents); either may be NULL. */
SWCL_API swcl_status swcl_swarm_policy_observe(swcl_swarm swarm, float* out_obs, float* out_actions, size_t count);
/* The policy's MLP alone on `count` given observations (count * obs_dim
 * floats, any source: recorded, synthetic) into count * 4 actions, on the
 * device as a step runs it (the same actions policy_observe gives for the
 * same observations).  Non-finite observations are
 * SWCL_ERROR_INVALID_ARGUMENT and nothing is written. */
SWCL_API swcl_status swcl_swarm_policy_infer(swcl_swarm swarm, const float* obs, size_t count, float* out_actions);

/* ---- evaluation against real insects -----------------------------------------
 * The data-driven evaluation of the noise paper (§3, docs/evaluation.md):
 * seven time-varying metrics (speed, acceleration, angular velocity, angular
 * acceleration, Cartesian jerk, nearest-neighbour distance, velocity
 * difference) sampled from real tracks or simulated frames, compared as
 * z-scored discrete PDFs (Eq. 2-3) and scored E = 1 - sum w E_phi (Eq. 1),
 * with entropy weights over several models (Eq. 4). */
typedef struct swcl_metrics { uint64_t id; } swcl_metrics;

typedef enum swcl_metric {
    SWCL_METRIC_SPEED = 0,                 /* |v| */
    SWCL_METRIC_ACCELERATION = 1,          /* |dv| / dt */
    SWCL_METRIC_ANGULAR_VELOCITY = 2,      /* arccos(v1^ . v2^) / dt */
    SWCL_METRIC_ANGULAR_ACCELERATION = 3,  /* d omega / dt (signed) */
    SWCL_METRIC_JERK = 4,                  /* |dv1 - dv2| / dt^2 */
    SWCL_METRIC_NEAREST_DISTANCE = 5,      /* to the nearest insect in view on the same frame */
    SWCL_METRIC_VELOCITY_DIFFERENCE = 6,   /* ||v_nei| - |v|| / d */
    SWCL_METRIC_COUNT = 7,
    SWCL_METRIC_MAX_ENUM = 0x7FFFFFFF  /* 32-bit range (see "Enums" above) */
} swcl_metric;
/* The metric's short lower-case name ("speed", "acceleration",
 * "angular_velocity", ..., "velocity_difference"; JSON keys, the CLI's table
 * and Python's swarmcl.METRICS use it), a static string; NULL for a value
 * that is not a swcl_metric. */
SWCL_API const char* swcl_metric_name(swcl_metric metric);

/* Metrics of tracks from a CSV file (columns, time format, unit and gap
 * splitting from `tracks`, as for swcl_dataset_from_csv; NULL: defaults),
 * keeping only the samples in a time window [window_from, window_to) given
 * as fractions of all samples ordered by time (0 and 1: all of it; 0 and
 * 0.5: up to the median sample time, the first half of the data by time;
 * a segment crossing a cut is cut there).  No difference crosses a gap; d and eta are taken among
 * the insects in view on the same frame. */
SWCL_API swcl_status swcl_metrics_from_csv(const char* path, const swcl_dataset_desc* tracks, double window_from,
                                           double window_to, swcl_metrics* out);
/* The tracks of a CSV file as the metrics see them (swcl_metrics_from_csv:
 * split at gaps, smoothed, in seconds and metres, cut to the window):
 * segment k has counts[k] samples, its times and packed xyz follow segment
 * after segment, and insects[k] numbers the insect it belongs to (segments
 * of one source track share it; from 0, in order of first appearance).
 * Call with counts, insects, times and xyz NULL (capacities 0) for
 * *out_segments and *out_samples, then with arrays of those sizes; a
 * capacity too small: SWCL_ERROR_INVALID_ARGUMENT, the arrays untouched.
 * *out_frame_time (may be NULL): the frame time, given or the median step.
 * Lay them out again (e.g. resampled) for swcl_metrics_from_tracks with
 * unit_scale 1, smoothing 0 and this frame time. */
SWCL_API swcl_status swcl_tracks_read_csv(const char* path, const swcl_dataset_desc* tracks, double window_from,
                                          double window_to, uint32_t* counts, uint32_t* insects,
                                          size_t segment_capacity, double* times, float* xyz,
                                          size_t sample_capacity, size_t* out_segments, size_t* out_samples,
                                          double* out_frame_time);
/* The same from tracks as arrays (laid out as for swcl_dataset_from_tracks). */
SWCL_API swcl_status swcl_metrics_from_tracks(const uint32_t* counts, size_t track_count, const double* times,
                                              const float* xyz, const swcl_dataset_desc* tracks, double window_from,
                                              double window_to, swcl_metrics* out);
/* Metrics of simulated frames: `frames` frames of `agents` agents, packed
 * xyz frame after frame, dt seconds apart (every agent in view on every
 * frame). */
SWCL_API swcl_status swcl_metrics_from_frames(const float* xyz, size_t frames, size_t agents, double dt,
                                              swcl_metrics* out);
/* The same with frame f's agents at xyz + f * frame_stride (floats; >= 3 *
 * agents): one world's frames read in place from a swarm of worlds' frames
 * (frame_stride = 3 * agents * worlds, xyz offset to the world).  The same
 * samples as the packed frames.  frame_stride below 3 * agents:
 * SWCL_ERROR_INVALID_ARGUMENT. */
SWCL_API swcl_status swcl_metrics_from_frames_strided(const float* xyz, size_t frames, size_t agents,
                                                      size_t frame_stride, double dt, swcl_metrics* out);
/* Metrics of a running swarm (any model), computed on the device and
 * streamed into fixed-size histograms and moments: memory does not grow with
 * the number of frames.  Step the swarm K steps, swcl_metrics_sample, repeat;
 * sample_dt is the time between samples (K times the swarm's dt).  The
 * metrics keep the swarm alive until they are destroyed; the swarm's agent
 * count must not change.  Read them like any other metrics (the PDFs come
 * from fine histograms, close to the samples' exact PDFs: docs/evaluation.md).
 * A swarm of several worlds gets each world's metrics from the same launches
 * (its own agents, nearest neighbours within the world): read them with
 * swcl_metrics_world; these metrics themselves then only sample.
 * SWCL_ERROR_INVALID_ARGUMENT for fewer than 2 agents (a world) or
 * sample_dt <= 0. */
SWCL_API swcl_status swcl_metrics_attach(swcl_swarm swarm, double sample_dt, swcl_metrics* out);
/* World `world`'s metrics sampled so far by metrics made with
 * swcl_metrics_attach, as new metrics of their own (destroy them; they do not
 * change when sampling goes on): bitwise what attached metrics of the world's
 * swarm alone give.  SWCL_ERROR_INVALID_ARGUMENT for world >= the swarm's
 * worlds or metrics from tracks or frames; out untouched. */
SWCL_API swcl_status swcl_metrics_world(swcl_metrics metrics, uint32_t world, swcl_metrics* out);
/* Several metrics pooled as one sample set (e.g. the runs of one model under
 * different seeds, scored as one distribution; the halves of a recording
 * put together again): every metric's samples are parts[0]'s, then
 * parts[1]'s, and so on (d and eta stay as each part took them: nearest
 * neighbours never cross parts).  Exact samples where every part holds
 * samples (tracks, frames, merges of them); else the parts' fine histograms
 * and moments summed (streamed metrics: one world's, swcl_metrics_world).
 * The parts are unchanged; destroy the result.  SWCL_ERROR_INVALID_ARGUMENT
 * for parts NULL or count 0, a part with another frame time than parts[0]'s
 * (relative difference above 1e-9; both named), or attached metrics of
 * several worlds; out untouched. */
SWCL_API swcl_status swcl_metrics_merge(const swcl_metrics* parts, size_t count, swcl_metrics* out);
/* Samples the swarm's positions now (enqueued on the device).
 * SWCL_ERROR_INVALID_ARGUMENT for metrics not made by swcl_metrics_attach. */
SWCL_API swcl_status swcl_metrics_sample(swcl_metrics metrics);
SWCL_API swcl_status swcl_metrics_destroy(swcl_metrics metrics);
/* Seconds between the frames the samples came from: the tracks' frame time
 * (given, or the median step of the data), or dt of simulated frames. */
SWCL_API swcl_status swcl_metrics_frame_time(swcl_metrics metrics, double* out_seconds);

typedef struct swcl_metric_info {
    uint32_t struct_size;
    uint64_t count;   /* samples */
    double mean;      /* of the samples (the z-score's shift) */
    double sigma;     /* their standard deviation (the z-score's scale) */
    /* Added at the end (written only when out->struct_size covers them): */
    double median;    /* in the metric's unit (swcl_metric_unit) */
    double mad;       /* median absolute deviation about the median (unscaled) */
} swcl_metric_info;
/* The metric's SI unit ("m/s", "m/s^2", "rad/s", "rad/s^2", "m/s^3", "m",
 * "1/s"), a static string; NULL for a value that is not a swcl_metric. */
SWCL_API const char* swcl_metric_unit(swcl_metric metric);
SWCL_API swcl_status swcl_metrics_get_info(swcl_metrics metrics, swcl_metric metric, swcl_metric_info* out);

/* The discrete PDF of Step 3: samples z-scored with their own mean and
 * sigma, binned into `bins` equal bins over [-half_width, half_width] sigma
 * (samples beyond go to the end bins), Q_i = S_i M / (S (u2 - u1)).
 * standardise = SWCL_STANDARDISE_MEDIAN_MAD z-scores with the median and
 * 1.4826 MAD instead (ours: robust to a few tracking glitches, which can
 * triple sigma; 1.4826 MAD is sigma for normal data). */
typedef enum swcl_standardise {
    SWCL_STANDARDISE_MEAN_SIGMA = 0,  /* the paper's z-score (default) */
    SWCL_STANDARDISE_MEDIAN_MAD = 1,
    SWCL_STANDARDISE_MAX_ENUM = 0x7FFFFFFF
} swcl_standardise;
typedef struct swcl_pdf_options {
    uint32_t struct_size;
    uint32_t bins;       /* M (default 50) */
    double half_width;   /* u2 = -u1, in sigma (default 4) */
    /* Added at the end (read only when struct_size covers it; else mean and sigma): */
    swcl_standardise standardise;
} swcl_pdf_options;
SWCL_API swcl_pdf_options swcl_pdf_options_default(void);
/* `count` must equal options->bins (NULL options: the defaults). */
SWCL_API swcl_status swcl_metrics_pdf(swcl_metrics metrics, swcl_metric metric, const swcl_pdf_options* options,
                                      double* out, size_t count);
/* E_phi = sum_i |Q_real,i - Q_sim,i| of every metric (Eq. 2), into
 * out[SWCL_METRIC_COUNT].  A metric with no samples on either side gets the
 * largest distance, 2 M / (u2 - u1). */
SWCL_API swcl_status swcl_metrics_distances(swcl_metrics real, swcl_metrics sim, const swcl_pdf_options* options,
                                            double* out, size_t count);

/* The Wasserstein-1 (earth mover's) distance between real's and sim's
 * samples of `metric`, in the metric's own unit (swcl_metric_unit): the
 * integral of |F_real - F_sim| over their CDFs.  Ours, beside the z-scored
 * E_phi, which ignores scale (a swarm ten times too fast can match every
 * z-scored PDF).  Exact for samples from tracks or frames; from a swarm's
 * streamed histograms, within their bins' relative width (0.2%).
 * SWCL_ERROR_INVALID_ARGUMENT naming the metric and the side when a side
 * has no samples of it (e.g. nearest distances of one insect in view). */
SWCL_API swcl_status swcl_metrics_wasserstein(swcl_metrics real, swcl_metrics sim, swcl_metric metric,
                                              double* out_distance);

/* Weights w and normalisation parameters p1, p2 of Eq. 1 and 3 (defaults:
 * w = 1/7, p1 = 0, p2 = 1). */
typedef struct swcl_score_weights {
    uint32_t struct_size;
    double w[SWCL_METRIC_COUNT];
    double p1[SWCL_METRIC_COUNT];
    double p2[SWCL_METRIC_COUNT];
} swcl_score_weights;
SWCL_API swcl_score_weights swcl_score_weights_default(void);
/* E = 1 - sum_phi w_phi (E_phi - p1_phi) / p2_phi (Eq. 3, then Eq. 1). */
SWCL_API swcl_status swcl_score(const double* distances, size_t count, const swcl_score_weights* weights,
                                double* out_score);
/* Entropy weights (Eq. 4) of the energy terms x (row-major: `models` rows,
 * >= 2, by `terms` columns): out_w, out_p1, out_p2 each get `terms` values
 * (out_p1 / out_p2 may be NULL).  A column equal for every model gets weight
 * 0; if every column is, the weights are equal. */
SWCL_API swcl_status swcl_entropy_weights(const double* x, size_t models, size_t terms, double* out_w,
                                          double* out_p1, double* out_p2);

/* ---- checkpoints -------------------------------------------------------------
 * A swarm with its model saved to one file and loaded back (in any context on
 * the same kind of device): a run of N steps equals, bit for bit, k steps +
 * save + load + N - k steps.  The file holds the swarm's settings, its agents
 * (positions, velocities, ids, in the device's order), the step counter (with
 * the seeds, all of the random state), the step statistics, the model's full
 * descriptor as it is now (moved goals, replaced stimuli and keypoints, the
 * energy model's dataset itself) and the model's state over steps; fields are
 * rebuilt from the descriptor.  Versioned, CRC-32 checked
 * (docs/checkpoint-format.md); written atomically, so a failed save leaves an
 * earlier file at `path` as it was. */

SWCL_API swcl_status swcl_swarm_save(swcl_swarm swarm, const char* path);
/* A new swarm in `context`.  A truncated, corrupted or foreign file, another
 * format version, or values that make no valid swarm give SWCL_ERROR_PARSE
 * (SWCL_ERROR_IO: cannot be read) with the reason in swcl_last_error, and no
 * swarm (*out is left as it was). */
SWCL_API swcl_status swcl_swarm_load(swcl_context context, const char* path, swcl_swarm* out);

/* ---- deprecated names (removed at 1.0) --------------------------------------
 * Version 0.2 named every model function swcl_swarm_<model>_<verb>.  The old
 * names still work and call the new ones; compilers warn where they are used. */

#if defined(__GNUC__) || defined(__clang__)
#  define SWCL_DEPRECATED __attribute__((deprecated))
#elif defined(_MSC_VER)
#  define SWCL_DEPRECATED __declspec(deprecated)
#else
#  define SWCL_DEPRECATED
#endif

/* Use swcl_swarm_field_set_model. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_field_model(swcl_swarm swarm, const swcl_field_model_desc* desc);
/* Use swcl_swarm_path_set_model. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_path_model(swcl_swarm swarm, const swcl_path_model_desc* desc);
/* Use swcl_swarm_path_set_goals. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_path_goals(swcl_swarm swarm, uint32_t group, const swcl_goal* goals, uint32_t goal_count, double* out_seconds);
/* Use swcl_swarm_path_get_info. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_get_path_info(swcl_swarm swarm, swcl_path_info* out);
/* Use swcl_swarm_energy_set_model. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_energy_model(swcl_swarm swarm, swcl_dataset dataset, const swcl_energy_model_desc* desc);
/* Use swcl_swarm_energy_get_goals. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_energy_goals(swcl_swarm swarm, int32_t* out_goals, size_t count);
/* Use swcl_swarm_force_set_model. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_force_model(swcl_swarm swarm, const swcl_force_model_desc* desc);
/* Use swcl_swarm_force_set_keyframes. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_force_keyframes(swcl_swarm swarm, const swcl_keyframe* keyframes, uint32_t count, uint32_t period);
/* Use swcl_swarm_force_set_path. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_set_force_path(swcl_swarm swarm, const float* points, uint32_t count, float speed);
/* Use swcl_swarm_force_get_targets. */
SWCL_DEPRECATED SWCL_API swcl_status swcl_swarm_get_force_targets(swcl_swarm swarm, float* out_xyz, size_t count);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* SWARMCL_SWARMCL_H */

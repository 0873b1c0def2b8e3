// The metrics of the data-driven evaluation (noise paper
// data-driven-noise-model-and-evaluation, §3.2; docs/evaluation.md), one row
// each: the one list every other place takes them from — the enum Metric
// and kMetricCount, the names (metric_name(), JSON keys, the CLI's table,
// swcl_metric_name() and so Python's swarmcl.METRICS), and the index macros
// of kernels/metrics.cl (M_<kernel>, build defines from
// metric_kernel_defines()).  A row's position is its value, which is also
// the C API's swcl_metric value (a stable ABI: rows are only ever appended;
// tests/test_eval_capi.cpp holds swarmcl.h's enum to this table).
//
// A new metric: a row here, its host function (eval/metrics.cpp, the
// reference), its value in the sampling kernel (kernels/metrics.cl, by its
// M_<kernel> index), its SWCL_METRIC_<NAME> enumerator in swarmcl.h, and its
// line in docs/evaluation.md's table (docs/architecture.md, "How to add a
// metric").
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace swarmcl {

// X(Id, name, symbol, kernel, unit, definition)
//   Id:         the Metric enumerator
//   name:       short lower-case name; swcl_metric's SWCL_METRIC_<NAME>
//   symbol:     the paper's symbol (§3.2)
//   kernel:     kernels/metrics.cl's index macro, M_<kernel>
//   unit:       with positions in metres and times in seconds
//   definition: what is computed (forward differences; docs/evaluation.md)
#define SWARMCL_METRICS(X)                                                                                        \
    X(Speed, "speed", "v", SPEED, "m/s", "|v_k|, v_k = (p_{k+1} - p_k) / dt")                                     \
    X(Acceleration, "acceleration", "a", ACCEL, "m/s^2", "|v_{k+1} - v_k| / dt")                                  \
    X(AngularVelocity, "angular_velocity", "omega", OMEGA, "rad/s", "arccos(v^_k . v^_{k+1}) / dt")               \
    X(AngularAcceleration, "angular_acceleration", "alpha", ALPHA, "rad/s^2", "(omega_{k+1} - omega_k) / dt, signed") \
    X(Jerk, "jerk", "mu", JERK, "m/s^3", "|dv_{k+1} - dv_k| / dt^2")                                              \
    X(NearestDistance, "nearest_distance", "d", DIST, "m", "min |p_k - p_m| over the others in view on the frame") \
    X(VelocityDifference, "velocity_difference", "eta", ETA, "1/s", "| |v_nei| - |v| | / d")

enum class Metric : uint32_t {
#define SWARMCL_METRIC_ENUM_(id, name, symbol, kernel, unit, definition) id,
    SWARMCL_METRICS(SWARMCL_METRIC_ENUM_)
#undef SWARMCL_METRIC_ENUM_
};

#define SWARMCL_METRIC_ONE_(...) +1
constexpr size_t kMetricCount = 0 SWARMCL_METRICS(SWARMCL_METRIC_ONE_);
#undef SWARMCL_METRIC_ONE_

struct MetricInfo {
    Metric id;
    const char* name;
    const char* symbol;
    const char* kernel;  // M_<kernel> in kernels/metrics.cl
    const char* unit;
    const char* definition;
};

inline constexpr std::array<MetricInfo, kMetricCount> kMetrics = {{
#define SWARMCL_METRIC_ROW_(id, name, symbol, kernel, unit, definition) \
    {Metric::id, name, symbol, #kernel, unit, definition},
    SWARMCL_METRICS(SWARMCL_METRIC_ROW_)
#undef SWARMCL_METRIC_ROW_
}};

// The row of m (Error(InvalidArgument) for a value past the table).
const MetricInfo& metric_info(Metric m);
// The short lower-case name ("speed", ..., "velocity_difference"), "unknown"
// for a value past the table.
const char* metric_name(Metric m);
// Build defines for kernels/metrics.cl: -DM_<kernel>=<index> per row and
// -DM_COUNT=<rows>.
std::string metric_kernel_defines();

}  // namespace swarmcl

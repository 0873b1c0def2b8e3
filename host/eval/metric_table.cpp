#include "eval/metric_table.hpp"

#include "core/error.hpp"

namespace swarmcl {

// The rows are in enum order (the enum is made from the same rows).
static_assert([] {
    for (size_t k = 0; k < kMetricCount; ++k)
        if (size_t(kMetrics[k].id) != k) return false;
    return true;
}(), "kMetrics rows must be in Metric order");

const MetricInfo& metric_info(Metric m) {
    require(size_t(m) < kMetricCount, "metrics: unknown metric " + std::to_string(uint32_t(m)));
    return kMetrics[size_t(m)];
}

const char* metric_name(Metric m) { return size_t(m) < kMetricCount ? kMetrics[size_t(m)].name : "unknown"; }

std::string metric_kernel_defines() {
    std::string d;
    for (size_t k = 0; k < kMetricCount; ++k)
        d += " -DM_" + std::string(kMetrics[k].kernel) + "=" + std::to_string(k);
    return d + " -DM_COUNT=" + std::to_string(kMetricCount);
}

}  // namespace swarmcl

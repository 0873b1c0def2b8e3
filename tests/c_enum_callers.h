// tests/c_enum_callers.c: C API calls with enum values only C can pass.
#pragma once
#include <cstdint>

#include "swarmcl/swarmcl.h"

extern "C" {
const char* c_metric_name_of(int value);
swcl_status c_swarm_read_attribute(swcl_swarm swarm, int attribute, float* dst, size_t count);
swcl_status c_metrics_pdf_of(swcl_metrics metrics, int metric, const swcl_pdf_options* options, double* out,
                             size_t count);
}

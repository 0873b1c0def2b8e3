/* C API calls made as a C program makes them.  C lets a caller pass any value
 * of an enum's integer type (C11 6.7.2.2 and 6.3.1.3: -1 becomes UINT_MAX for
 * an enum compatible with unsigned int), which C++ test code cannot construct
 * without undefined behaviour; the library must refuse such a value. */
#include "swarmcl/swarmcl.h"

const char* c_metric_name_of(int value) { return swcl_metric_name((swcl_metric)value); }

swcl_status c_swarm_read_attribute(swcl_swarm swarm, int attribute, float* dst, size_t count) {
    return swcl_swarm_read(swarm, (swcl_attribute)attribute, dst, count);
}

swcl_status c_metrics_pdf_of(swcl_metrics metrics, int metric, const swcl_pdf_options* options, double* out,
                             size_t count) {
    return swcl_metrics_pdf(metrics, (swcl_metric)metric, options, out, count);
}

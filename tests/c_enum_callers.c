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

/* Enum fields of descriptors set as a C caller may set them. */
void c_noise_desc_type(swcl_noise_desc* d, int type) { d->type = (swcl_noise_type)type; }
void c_obstacle_type(swcl_obstacle* o, int type) { o->type = (swcl_obstacle_type)type; }
void c_goal_type(swcl_goal* g, int type) { g->type = (swcl_goal_type)type; }
void c_stimulus_kind(swcl_stimulus* s, int kind) { s->kind = (swcl_stimulus_kind)kind; }
void c_dataset_time_format(swcl_dataset_desc* d, int format) { d->time_format = (swcl_time_format)format; }
void c_pdf_standardise(swcl_pdf_options* o, int standardise) { o->standardise = (swcl_standardise)standardise; }
void c_force_assignment(swcl_force_model_desc* d, int assignment) { d->assignment = (swcl_assignment)assignment; }
void c_policy_leader_mode(swcl_policy_model_desc* d, int mode) { d->leader_mode = (swcl_policy_leader_mode)mode; }

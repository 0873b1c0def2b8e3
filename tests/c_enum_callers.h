// tests/c_enum_callers.c: C API calls with enum values only C can pass.
#pragma once
#include <cstdint>

#include "swarmcl/swarmcl.h"

extern "C" {
const char* c_metric_name_of(int value);
swcl_status c_swarm_read_attribute(swcl_swarm swarm, int attribute, float* dst, size_t count);
swcl_status c_metrics_pdf_of(swcl_metrics metrics, int metric, const swcl_pdf_options* options, double* out,
                             size_t count);
void c_noise_desc_type(swcl_noise_desc* d, int type);
void c_obstacle_type(swcl_obstacle* o, int type);
void c_goal_type(swcl_goal* g, int type);
void c_stimulus_kind(swcl_stimulus* s, int kind);
void c_dataset_time_format(swcl_dataset_desc* d, int format);
void c_pdf_standardise(swcl_pdf_options* o, int standardise);
void c_force_assignment(swcl_force_model_desc* d, int assignment);
void c_policy_leader_mode(swcl_policy_model_desc* d, int mode);
}

// The MODL section's writers, one per model (model_checkpoint.cpp): what a
// model's save_checkpoint calls.  The configs are only declared here, so a
// model's .cpp includes its own header and not every other model's
// (model_checkpoint.hpp, which holds a whole ModelSpec, does).
#pragma once
#include <string>

#include "io/checkpoint.hpp"

namespace swarmcl {

struct FieldModelConfig;
struct PathModelConfig;
struct ForceModelConfig;
struct EnergyModelConfig;
struct PolicyModelConfig;
struct Dataset;

void write_model_descriptor(ByteWriter& out, const FieldModelConfig& config);
void write_model_descriptor(ByteWriter& out, const PathModelConfig& config);
void write_model_descriptor(ByteWriter& out, const ForceModelConfig& config);
void write_model_descriptor(ByteWriter& out, const EnergyModelConfig& config, const Dataset& dataset);
// The policy model: its config and the weights file's bytes.
void write_model_descriptor(ByteWriter& out, const PolicyModelConfig& config, const std::string& weights);
void write_ballistic_descriptor(ByteWriter& out);

}  // namespace swarmcl

// A model in a checkpoint (docs/checkpoint-format.md, sections MODL and
// MDST): its name (ModelTraits<Config>::name) and its full descriptor, every
// field of the ModelSpec alternative as the model holds it now (moved goals,
// replaced stimuli included); the energy model's dataset itself rather than
// where it came from.  What a model rebuilds from its descriptor (noise
// bakes, signed distances, cost fields, sampled targets) is not stored: it
// is recomputed by the same code from the same inputs, so bit for bit the
// same (tests/test_checkpoint.cpp checks the runs).  What changes over steps
// and is not in the descriptor is each model's Behavior::save_checkpoint /
// restore_checkpoint (section MDST).
#pragma once
#include <memory>

#include "io/checkpoint.hpp"
#include "models/model_descriptor.hpp"
#include "models/model_spec.hpp"

namespace swarmcl {

// Version of the MODL section this code writes (and the newest it reads).
// 2: a model with a parameter table writes its rows by key, then its
// structured fields (the field model); 3: the force and path models too;
// 1 (still read): every field in fields() order.
constexpr uint32_t kModelSectionVersion = 3;

// A decoded model section: the spec, and for the energy model its dataset
// (the spec's source fields are not used).
struct CheckpointModel {
    ModelSpec spec;
    std::shared_ptr<const Dataset> dataset;
};

// The MODL section of each model (called by the models' save_checkpoint):
// model_descriptor.hpp.

// Error(Parse) for an unknown model name, a bad enum value, a short section,
// an absurd count or a mesh index out of range.  The values are validated
// again by the model's constructor (InvalidArgument there becomes Parse in
// the loader).
CheckpointModel read_model_descriptor(ByteReader& in, uint32_t version = kModelSectionVersion);

// The model's Behavior (nullptr: ballistic), built as make_behavior does.
std::shared_ptr<Behavior> behavior_from_checkpoint(Swarm& swarm, const CheckpointModel& model);

}  // namespace swarmcl

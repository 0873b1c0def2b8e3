// The noise descriptor's conversion, shared by the models that take a noise
// field (field, path, energy; capi_noise.cpp defines it).
#pragma once
#include "fields/noise_field.hpp"
#include "swarmcl/swarmcl.h"

namespace swarmcl::capi {

NoiseConfig noise_config_from(const swcl_noise_desc& d);

}  // namespace swarmcl::capi

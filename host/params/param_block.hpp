// A model's parameter block on the device: the rows of its table marked
// on_device(), laid out by the table (ParamTable::device_defines names the
// slots for the kernels), one block per swarm (per world, once worlds come).
#pragma once
#include <vector>

#include "device/buffer.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

inline DeviceBuffer<cl_float> upload_param_block(Context& ctx, const ParamTable& table, const void* config) {
    std::vector<cl_float> block(table.device_floats() ? table.device_floats() : 1, 0.0f);
    table.write_device_block(const_cast<void*>(config), block.data());
    DeviceBuffer<cl_float> buf(ctx, block.size(), "model parameter block");
    buf.upload(ctx, block.data(), block.size());
    return buf;
}

}  // namespace swarmcl

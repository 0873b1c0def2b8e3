// OpenCL platforms and devices, numbered globally (platform by platform), and
// the choice of one device from a selector string.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/opencl.hpp"

namespace swarmcl {

struct DeviceEntry {
    uint32_t index = 0;
    cl::Platform platform;
    cl::Device device;
    std::string platform_name;
    std::string device_name;
    std::string version;
    cl_device_type type = 0;
    uint32_t compute_units = 0;
    size_t max_work_group_size = 1;
    uint64_t global_memory = 0;
    uint64_t max_allocation = 0;
    uint64_t local_memory = 0;
    std::string opencl_c_version;  // CL_DEVICE_OPENCL_C_VERSION, e.g. "OpenCL C 1.2 pocl"
    std::string extensions;        // CL_DEVICE_EXTENSIONS
    uint32_t preferred_float_width = 1;  // CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT (PoCL: 8 with AVX2, 16 with AVX-512)
    // The code paths the library takes on the device (docs/architecture.md,
    // "Device profiles"): true on CPU devices: explicit-width kernels, the
    // CPU launch policy, x86 prefetch; false elsewhere: one agent per
    // work-item, gpu_local_size().  $SWARMCL_DEVICE_PROFILE ("cpu" or
    // "gpu") overrides it per context, so the GPU path is tested on PoCL.
    bool cpu_profile = false;

    bool has_extension(const std::string& name) const;
};

// "OpenCL C 1.2 ..." -> 120; 0 when the string does not parse.
int opencl_c_version_number(const std::string& version);

// Every device of every platform.  Throws Error(NoDevice) naming the fix when
// there is no OpenCL platform at all.
std::vector<DeviceEntry> list_devices();

// selector: an index ("1") or a case-insensitive substring of "platform
// device"; empty means $SWARMCL_DEVICE, else the first GPU, else the first CPU,
// else the first device.  Throws Error(NoDevice) listing the devices when
// nothing matches.
DeviceEntry select_device(const std::string& selector);

}  // namespace swarmcl

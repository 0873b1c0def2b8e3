#include "capi_common.hpp"

namespace swarmcl::capi {
namespace {
thread_local std::string g_last_error;
}

void set_last_error(const std::string& message) { g_last_error = message; }
void clear_last_error() { g_last_error.clear(); }
const std::string& last_error() { return g_last_error; }

// The tables are never destroyed: objects a program did not destroy must not
// be released by static destructors after the OpenCL runtime has shut down.
HandleRegistry<Context>& contexts() {
    static auto* registry = new HandleRegistry<Context>(0xC1, "context");
    return *registry;
}

HandleRegistry<Swarm>& swarms() {
    static auto* registry = new HandleRegistry<Swarm>(0x5A, "swarm");
    return *registry;
}

swcl_status status_from_opencl(int err) {
    switch (err) {
        case CL_MEM_OBJECT_ALLOCATION_FAILURE:
        case CL_OUT_OF_RESOURCES:
        case CL_OUT_OF_HOST_MEMORY:
        case CL_INVALID_BUFFER_SIZE: return SWCL_ERROR_OUT_OF_MEMORY;
        case CL_BUILD_PROGRAM_FAILURE: return SWCL_ERROR_BUILD;
        case CL_DEVICE_NOT_FOUND:
        case CL_DEVICE_NOT_AVAILABLE:
        case -1001: /* CL_PLATFORM_NOT_FOUND_KHR */ return SWCL_ERROR_NO_DEVICE;
        default: return SWCL_ERROR_OPENCL;
    }
}

const char* opencl_error_name(int err) {
    switch (err) {
        case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
        case CL_DEVICE_NOT_AVAILABLE: return "CL_DEVICE_NOT_AVAILABLE";
        case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
        case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
        case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
        case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
        case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
        case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE";
        case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
        case CL_INVALID_ARG_INDEX: return "CL_INVALID_ARG_INDEX";
        case CL_INVALID_ARG_VALUE: return "CL_INVALID_ARG_VALUE";
        case CL_INVALID_ARG_SIZE: return "CL_INVALID_ARG_SIZE";
        case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
        case CL_INVALID_KERNEL_NAME: return "CL_INVALID_KERNEL_NAME";
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "OpenCL error";
    }
}

}  // namespace swarmcl::capi

using namespace swarmcl::capi;

extern "C" {

uint32_t swcl_version(void) { return SWCL_VERSION_NUMBER; }

#define SWCL_STR2(x) #x
#define SWCL_STR(x) SWCL_STR2(x)
static_assert(SWCL_VERSION_MAJOR == SWARMCL_PROJECT_VERSION_MAJOR && SWCL_VERSION_MINOR == SWARMCL_PROJECT_VERSION_MINOR &&
                  SWCL_VERSION_PATCH == SWARMCL_PROJECT_VERSION_PATCH,
              "swarmcl.h's SWCL_VERSION_* must match project(VERSION) in CMakeLists.txt");
static_assert(SWCL_VERSION_NUMBER == SWCL_VERSION_MAJOR * 10000 + SWCL_VERSION_MINOR * 100 + SWCL_VERSION_PATCH,
              "SWCL_VERSION_NUMBER out of step");

const char* swcl_version_string(void) {
    return SWCL_STR(SWCL_VERSION_MAJOR) "." SWCL_STR(SWCL_VERSION_MINOR) "." SWCL_STR(SWCL_VERSION_PATCH);
}

const char* swcl_status_string(swcl_status status) {
    switch (status) {
        case SWCL_OK: return "SWCL_OK";
        case SWCL_ERROR_INVALID_ARGUMENT: return "SWCL_ERROR_INVALID_ARGUMENT";
        case SWCL_ERROR_INVALID_HANDLE: return "SWCL_ERROR_INVALID_HANDLE";
        case SWCL_ERROR_NO_DEVICE: return "SWCL_ERROR_NO_DEVICE";
        case SWCL_ERROR_BUILD: return "SWCL_ERROR_BUILD";
        case SWCL_ERROR_OUT_OF_MEMORY: return "SWCL_ERROR_OUT_OF_MEMORY";
        case SWCL_ERROR_IO: return "SWCL_ERROR_IO";
        case SWCL_ERROR_PARSE: return "SWCL_ERROR_PARSE";
        case SWCL_ERROR_OPENCL: return "SWCL_ERROR_OPENCL";
        case SWCL_ERROR_INTERNAL: return "SWCL_ERROR_INTERNAL";
        case SWCL_STATUS_MAX_ENUM: break;  // not a status
    }
    return "SWCL_UNKNOWN_STATUS";
}

const char* swcl_last_error(void) { return last_error().c_str(); }

}  // extern "C"

// Devices and contexts.
#include <cstring>

#include "capi_common.hpp"
#include "device/device_list.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

void copy_name(char (&dst)[128], const std::string& src) {
    const size_t n = std::min(src.size(), sizeof(dst) - 1);
    std::memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

swcl_device_type type_of(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return SWCL_DEVICE_TYPE_GPU;
    if (t & CL_DEVICE_TYPE_CPU) return SWCL_DEVICE_TYPE_CPU;
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return SWCL_DEVICE_TYPE_ACCELERATOR;
    return SWCL_DEVICE_TYPE_OTHER;
}

void fill_info(const DeviceEntry& d, swcl_device_info* out) {
    check_struct_size(out, sizeof(swcl_device_info), "out");
    swcl_device_info info;
    std::memset(&info, 0, sizeof(info));
    info.struct_size = sizeof(info);
    info.index = d.index;
    info.type = type_of(d.type);
    info.compute_units = d.compute_units;
    info.global_memory_bytes = d.global_memory;
    copy_name(info.platform_name, d.platform_name);
    copy_name(info.device_name, d.device_name);
    copy_name(info.version, d.version);
    *out = info;
}

}  // namespace

extern "C" {

swcl_status swcl_device_count(uint32_t* out_count) {
    return guarded(__func__, [&] {
        check_out(out_count, "out_count");
        *out_count = uint32_t(list_devices().size());
    });
}

swcl_status swcl_device_get_info(uint32_t index, swcl_device_info* out) {
    return guarded(__func__, [&] {
        check_struct_size(out, sizeof(swcl_device_info), "out");
        const auto devices = list_devices();
        require(index < devices.size(), "device index " + std::to_string(index) + " out of range (" +
                                            std::to_string(devices.size()) + " devices)");
        fill_info(devices[index], out);
    });
}

swcl_context_desc swcl_context_desc_default(void) {
    swcl_context_desc d;
    std::memset(&d, 0, sizeof(d));
    d.struct_size = sizeof(d);
    d.device = nullptr;
    d.build_options = nullptr;
    return d;
}

swcl_status swcl_context_create(const swcl_context_desc* desc, swcl_context* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, sizeof(swcl_context_desc), "desc");
        check_out(out, "out");
        auto ctx = std::make_shared<Context>(desc->device ? desc->device : "",
                                             desc->build_options ? desc->build_options : "");
        out->id = contexts().add(std::move(ctx));
    });
}

swcl_status swcl_context_destroy(swcl_context context) {
    return guarded(__func__, [&] { contexts().remove(context.id); });
}

swcl_status swcl_context_device_info(swcl_context context, swcl_device_info* out) {
    return guarded(__func__, [&] {
        auto ctx = contexts().get(context.id);
        fill_info(ctx->device(), out);
    });
}

}  // extern "C"

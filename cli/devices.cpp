// `swarmcl devices`: the OpenCL devices, numbered as --device and
// $SWARMCL_DEVICE take them.
#include <cstdio>

#include <CLI/CLI.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_support.hpp"
#include "commands.hpp"

namespace swarmcl_cli {
namespace {

int list_devices() {
    uint32_t n = 0;
    check(swcl_device_count(&n), "listing devices");
    for (uint32_t i = 0; i < n; ++i) {
        swcl_device_info info;
        info.struct_size = sizeof(info);
        check(swcl_device_get_info(i, &info), "reading device info");
        const char* type = info.type == SWCL_DEVICE_TYPE_GPU   ? "GPU"
                           : info.type == SWCL_DEVICE_TYPE_CPU ? "CPU"
                                                               : "other";
        std::printf("%u  %-5s %s / %s  (%u compute units, %.1f GiB, %s)\n", i, type, info.platform_name,
                    info.device_name, info.compute_units, double(info.global_memory_bytes) / (1u << 30), info.version);
    }
    return 0;
}

}  // namespace

Command add_devices(CLI::App& program) {
    CLI::App* app = program.add_subcommand("devices", "List the OpenCL devices (index, type, platform / device)");
    app->footer("--device D and $SWARMCL_DEVICE take the index or a case-insensitive part of\n"
                "the platform or device name; without either, the first GPU, else the first CPU.");
    return {app, list_devices};
}

}  // namespace swarmcl_cli

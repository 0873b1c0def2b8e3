#include "device/device_list.hpp"

#include <cstdio>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "core/error.hpp"

namespace swarmcl {
namespace {

const char* kInstallHint =
    "install an OpenCL driver (ICD); for the CPU on Debian/Ubuntu: "
    "sudo apt-get install pocl-opencl-icd ocl-icd-libopencl1";

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
    return s;
}

std::string describe(const std::vector<DeviceEntry>& devices) {
    std::string text;
    for (const auto& d : devices)
        text += "\n  " + std::to_string(d.index) + ": " + d.platform_name + " / " + d.device_name;
    return text;
}

}  // namespace

std::vector<DeviceEntry> list_devices() {
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        platforms.clear();  // CL_PLATFORM_NOT_FOUND_KHR: no ICD installed
    }
    if (platforms.empty()) fail(Status::NoDevice, std::string("no OpenCL platform found: ") + kInstallHint);
    std::vector<DeviceEntry> out;
    for (auto& platform : platforms) {
        std::vector<cl::Device> devices;
        try {
            platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue;  // a platform without devices
        }
        for (auto& device : devices) {
            DeviceEntry e;
            e.index = uint32_t(out.size());
            e.platform = platform;
            e.device = device;
            e.platform_name = trim(platform.getInfo<CL_PLATFORM_NAME>());
            e.device_name = trim(device.getInfo<CL_DEVICE_NAME>());
            e.version = trim(device.getInfo<CL_DEVICE_VERSION>());
            e.type = device.getInfo<CL_DEVICE_TYPE>();
            e.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
            e.max_work_group_size = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
            e.global_memory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            e.max_allocation = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
            e.local_memory = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
            e.opencl_c_version = trim(device.getInfo<CL_DEVICE_OPENCL_C_VERSION>());
            e.extensions = device.getInfo<CL_DEVICE_EXTENSIONS>();
            e.preferred_float_width = device.getInfo<CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT>();
            e.cpu_profile = (e.type & CL_DEVICE_TYPE_CPU) != 0;
            out.push_back(std::move(e));
        }
    }
    if (out.empty()) fail(Status::NoDevice, std::string("OpenCL platforms found but no device: ") + kInstallHint);
    return out;
}

bool DeviceEntry::has_extension(const std::string& name) const {
    size_t at = 0;
    while ((at = extensions.find(name, at)) != std::string::npos) {
        const size_t end = at + name.size();
        if ((at == 0 || extensions[at - 1] == ' ') && (end == extensions.size() || extensions[end] == ' ')) return true;
        at = end;
    }
    return false;
}

int opencl_c_version_number(const std::string& version) {
    int major = 0, minor = 0;
    if (std::sscanf(version.c_str(), "OpenCL C %d.%d", &major, &minor) != 2) return 0;
    return major * 100 + minor * 10;
}

DeviceEntry select_device(const std::string& selector_in) {
    const auto devices = list_devices();
    std::string selector = selector_in;
    std::string origin = "device selector";
    if (selector.empty()) {
        if (const char* env = std::getenv("SWARMCL_DEVICE"); env && *env) {
            selector = env;
            origin = "$SWARMCL_DEVICE";
        }
    }
    if (selector.empty()) {
        for (cl_device_type want : {cl_device_type(CL_DEVICE_TYPE_GPU), cl_device_type(CL_DEVICE_TYPE_CPU)})
            for (const auto& d : devices)
                if (d.type & want) return d;
        return devices.front();
    }
    if (std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); })) {
        const unsigned long index = selector.size() > 9 ? ~0ul : std::stoul(selector);
        if (index < devices.size()) return devices[index];
        fail(Status::NoDevice, origin + " '" + selector + "': no device with that index; devices:" + describe(devices));
    }
    const std::string needle = lower(selector);
    for (const auto& d : devices)
        if (lower(d.platform_name + " " + d.device_name).find(needle) != std::string::npos) return d;
    fail(Status::NoDevice, origin + " '" + selector + "' matches no device; devices:" + describe(devices));
}

}  // namespace swarmcl

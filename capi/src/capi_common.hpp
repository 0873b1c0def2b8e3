// What every C entry point shares: the thread-local last error, the handle
// tables, and guarded() which turns any C++ exception into a status so none
// crosses the C boundary.
#pragma once
#include <cstdint>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <type_traits>

#include "core/error.hpp"
#include "core/handle_registry.hpp"
#include "device/context.hpp"
#include "fields/noise_field.hpp"
#include "swarm/swarm.hpp"
#include "swarmcl/swarmcl.h"

// guarded() converts a swarmcl::Status by value: the two enums must agree
// value for value (swcl_status values never change).
#define SWCL_SAME_STATUS(c, cpp) static_assert(int(c) == int(swarmcl::Status::cpp), #c " != Status::" #cpp)
SWCL_SAME_STATUS(SWCL_OK, Ok);
SWCL_SAME_STATUS(SWCL_ERROR_INVALID_ARGUMENT, InvalidArgument);
SWCL_SAME_STATUS(SWCL_ERROR_INVALID_HANDLE, InvalidHandle);
SWCL_SAME_STATUS(SWCL_ERROR_NO_DEVICE, NoDevice);
SWCL_SAME_STATUS(SWCL_ERROR_BUILD, Build);
SWCL_SAME_STATUS(SWCL_ERROR_OUT_OF_MEMORY, OutOfMemory);
SWCL_SAME_STATUS(SWCL_ERROR_IO, Io);
SWCL_SAME_STATUS(SWCL_ERROR_PARSE, Parse);
SWCL_SAME_STATUS(SWCL_ERROR_OPENCL, OpenCL);
SWCL_SAME_STATUS(SWCL_ERROR_INTERNAL, Internal);
#undef SWCL_SAME_STATUS

namespace swarmcl::capi {

// The bits of an enum argument.  C lets a caller pass any value of an enum's
// integer type (C11 6.7.2.2), e.g. (swcl_metric)-1; in C++ loading a value
// outside the enumerators' range is undefined (clang's -fsanitize=enum
// reports it), so entry points that range-check an enum read its bits.
template <typename E>
uint32_t enum_bits(const E& value) {
    static_assert(std::is_enum_v<E> && sizeof(E) == sizeof(uint32_t), "a 32-bit C enum");
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
}

// Those bits as the C caller wrote them (an int: -1, not 4294967295), for
// the error that refuses them.
inline std::string c_enum_text(uint32_t bits) { return std::to_string(int32_t(bits)); }

void set_last_error(const std::string& message);
void clear_last_error();
const std::string& last_error();
swcl_status status_from_opencl(int err);
const char* opencl_error_name(int err);

HandleRegistry<Context>& contexts();
HandleRegistry<Swarm>& swarms();

template <typename F>
swcl_status guarded(const char* function, F&& body) noexcept {
    try {
        clear_last_error();
        body();
        return SWCL_OK;
    } catch (const Error& e) {
        set_last_error(std::string(function) + ": " + e.what());
        return static_cast<swcl_status>(e.status());
    } catch (const cl::Error& e) {
        set_last_error(std::string(function) + ": OpenCL call " + e.what() + " failed with " +
                       opencl_error_name(e.err()) + " (" + std::to_string(e.err()) + ")");
        return status_from_opencl(e.err());
    } catch (const std::bad_alloc&) {
        set_last_error(std::string(function) + ": out of host memory");
        return SWCL_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        set_last_error(std::string(function) + ": internal error: " + e.what());
        return SWCL_ERROR_INTERNAL;
    } catch (...) {
        set_last_error(std::string(function) + ": unknown internal error");
        return SWCL_ERROR_INTERNAL;
    }
}

// Looks up a swarm and runs body(swarm) under the swarm's mutex: each
// swarm's calls are serialised (the host objects are not thread-safe).
template <typename F>
swcl_status with_swarm(const char* function, swcl_swarm handle, F&& body) noexcept {
    return guarded(function, [&] {
        auto swarm = swarms().get(handle.id);
        std::lock_guard<std::mutex> lock(swarm->mutex());
        body(*swarm);
    });
}

// Checks a descriptor's struct_size: callers built against an older header
// pass a smaller struct; anything smaller than the first version is refused.
template <typename T>
void check_struct_size(const T* desc, size_t first_version_size, const char* name) {
    require(desc != nullptr, std::string(name) + " is NULL");
    require(desc->struct_size >= first_version_size && desc->struct_size <= 65536,
            std::string(name) + "->struct_size is " + std::to_string(desc->struct_size) +
                " (set it with the *_default() function)");
}

template <typename T>
void check_out(T* out, const char* name) {
    require(out != nullptr, std::string(name) + " is NULL");
}

}  // namespace swarmcl::capi

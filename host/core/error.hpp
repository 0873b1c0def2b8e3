// Errors inside the host code: thrown as swarmcl::Error with a status that
// maps one to one onto the C API's swcl_status (capi/ catches and converts).
#pragma once
#include <stdexcept>
#include <string>

namespace swarmcl {

enum class Status : int {
    Ok = 0,
    InvalidArgument = -1,
    InvalidHandle = -2,
    NoDevice = -3,
    Build = -4,
    OutOfMemory = -5,
    Io = -6,
    Parse = -7,
    OpenCL = -8,
    Internal = -99,
};

class Error : public std::runtime_error {
public:
    Error(Status status, const std::string& message) : std::runtime_error(message), status_(status) {}
    Status status() const noexcept { return status_; }

private:
    Status status_;
};

[[noreturn]] inline void fail(Status status, const std::string& message) { throw Error(status, message); }

inline void require(bool ok, const std::string& message) {
    if (!ok) fail(Status::InvalidArgument, message);
}
// A literal message builds no std::string unless the check fails (the
// std::string overload would construct one on every call, even in hot loops).
inline void require(bool ok, const char* message) {
    if (!ok) fail(Status::InvalidArgument, message);
}

}  // namespace swarmcl

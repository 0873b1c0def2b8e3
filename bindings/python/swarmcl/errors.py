"""Exceptions: one per swcl_status, all carrying swcl_last_error()."""

from __future__ import annotations

from ._native import ffi, lib

__all__ = [
    "SwarmclError", "InvalidArgumentError", "InvalidHandleError", "NoDeviceError",
    "BuildError", "OutOfMemoryError", "IOError_", "ParseError", "OpenCLError",
    "InternalError", "check",
]


class SwarmclError(Exception):
    """A swarmcl call failed.  ``status`` is the swcl_status value,
    ``status_name`` its name, and the message is swcl_last_error()."""

    status: int = 0

    def __init__(self, status: int, message: str = ""):
        self.status = int(status)
        self.status_name = ffi.string(lib.swcl_status_string(self.status)).decode()
        self.message = message or self.status_name
        super().__init__(self.message)

    def __str__(self) -> str:
        return self.message

    def __reduce__(self):
        return (type(self), (self.status, self.message))


class InvalidArgumentError(SwarmclError, ValueError):
    """SWCL_ERROR_INVALID_ARGUMENT: a bad value (NaN, count above capacity, ...)."""


class InvalidHandleError(SwarmclError):
    """SWCL_ERROR_INVALID_HANDLE: a closed, collected or foreign handle."""


class NoDeviceError(SwarmclError):
    """SWCL_ERROR_NO_DEVICE: no OpenCL platform or no device matches."""


class BuildError(SwarmclError):
    """SWCL_ERROR_BUILD: an OpenCL kernel did not compile (the log is in the message)."""


class OutOfMemoryError(SwarmclError, MemoryError):
    """SWCL_ERROR_OUT_OF_MEMORY: host or device memory ran out."""


class IOError_(SwarmclError):  # noqa: N801 - the trailing underscore avoids shadowing the builtin IOError
    """SWCL_ERROR_IO: a file could not be read or written."""


class ParseError(SwarmclError, ValueError):
    """SWCL_ERROR_PARSE: a file (a scenario) is malformed."""


class OpenCLError(SwarmclError):
    """SWCL_ERROR_OPENCL: the OpenCL runtime failed."""


class InternalError(SwarmclError):
    """SWCL_ERROR_INTERNAL: a bug in swarmcl."""


_BY_STATUS = {
    int(lib.SWCL_ERROR_INVALID_ARGUMENT): InvalidArgumentError,
    int(lib.SWCL_ERROR_INVALID_HANDLE): InvalidHandleError,
    int(lib.SWCL_ERROR_NO_DEVICE): NoDeviceError,
    int(lib.SWCL_ERROR_BUILD): BuildError,
    int(lib.SWCL_ERROR_OUT_OF_MEMORY): OutOfMemoryError,
    int(lib.SWCL_ERROR_IO): IOError_,
    int(lib.SWCL_ERROR_PARSE): ParseError,
    int(lib.SWCL_ERROR_OPENCL): OpenCLError,
    int(lib.SWCL_ERROR_INTERNAL): InternalError,
}


def error_for(status: int) -> SwarmclError:
    """The exception for a failed call; reads swcl_last_error() (thread-local,
    so call it on the thread that made the failing call, right after it)."""
    message = ffi.string(lib.swcl_last_error()).decode("utf-8", "replace")
    return _BY_STATUS.get(int(status), SwarmclError)(status, message)


def check(status: int) -> None:
    """Raises the matching SwarmclError when status is not SWCL_OK."""
    if status:
        raise error_for(status)

#include "io/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

#include "core/error.hpp"

namespace swarmcl {
namespace {
std::atomic<long long> g_fail_after{-1};
std::atomic<long long> g_written{0};
}  // namespace

void AtomicFile::fail_after_bytes_for_testing(long long bytes) {
    g_written = 0;
    g_fail_after = bytes;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    // open(O_EXCL, 0666) rather than mkstemp: the file gets the permissions
    // the user's umask gives any new file (mkstemp would make it 0600).
    static std::atomic<unsigned> counter{0};
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        temp_ = path_ + ".partial-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
        fd = open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0) {
        const int err = errno;
        temp_.clear();
        fail("cannot create a file beside", err);
    }
    file_ = fdopen(fd, "wb");
    if (!file_) {
        const int err = errno;
        close(fd);
        fail("cannot open", err);
    }
}

AtomicFile::~AtomicFile() {
    if (file_) std::fclose(file_);
    if (!committed_ && !temp_.empty()) std::remove(temp_.c_str());
}

void AtomicFile::fail(const char* what, int err) {
    if (file_) {
        std::fclose(file_);
        file_ = nullptr;
    }
    if (!temp_.empty()) std::remove(temp_.c_str());
    temp_.clear();
    swarmcl::fail(Status::Io, std::string(what) + " '" + path_ + "': " + std::strerror(err));
}

void AtomicFile::write(const void* data, size_t bytes) {
    if (!file_) swarmcl::fail(Status::Io, "writing '" + path_ + "' after it was closed");
    const long long limit = g_fail_after.load();
    if (limit >= 0 && (g_written += (long long)bytes) > limit) fail("writing", ENOSPC);
    if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) fail("writing", errno ? errno : EIO);
}

void AtomicFile::write_at(long offset, const void* data, size_t bytes) {
    if (!file_) swarmcl::fail(Status::Io, "writing '" + path_ + "' after it was closed");
    const long end = std::ftell(file_);
    if (end < 0 || std::fseek(file_, offset, SEEK_SET) != 0) fail("seeking in", errno);
    if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) fail("writing", errno ? errno : EIO);
    if (std::fseek(file_, end, SEEK_SET) != 0) fail("seeking in", errno);
}

void AtomicFile::commit() {
    if (!file_) swarmcl::fail(Status::Io, "committing '" + path_ + "' twice");
    if (std::fflush(file_) != 0 || fsync(fileno(file_)) != 0) fail("flushing", errno);
    if (std::fclose(file_) != 0) {
        file_ = nullptr;
        fail("closing", errno);
    }
    file_ = nullptr;
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail("renaming the finished file to", errno);
    committed_ = true;
}

}  // namespace swarmcl

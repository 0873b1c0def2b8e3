// A file that appears complete or not at all: bytes go to a temporary file
// beside the target, which is renamed over it on commit().  A failed or
// abandoned write removes the temporary file, so an interrupted run never
// leaves a truncated file that looks finished.
#pragma once
#include <cstdio>
#include <string>

namespace swarmcl {

class AtomicFile {
public:
    // Creates the temporary file; Error(Io) naming the path and the reason.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    void write(const void* data, size_t bytes);
    void write(const std::string& text) { write(text.data(), text.size()); }
    // Overwrites bytes already written at `offset` (e.g. a header whose size
    // is known only at the end).
    void write_at(long offset, const void* data, size_t bytes);
    // Flushes, syncs and renames onto the target path.
    void commit();

    const std::string& path() const { return path_; }

    // Tests: every AtomicFile fails with ENOSPC once this many bytes have been
    // written in the process (negative: never).  Simulates a full disk.
    static void fail_after_bytes_for_testing(long long bytes);

private:
    [[noreturn]] void fail(const char* what, int err);

    std::string path_, temp_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
};

}  // namespace swarmcl

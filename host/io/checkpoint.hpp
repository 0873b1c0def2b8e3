// The checkpoint container (docs/checkpoint-format.md): a versioned file of
// tagged sections, one per concern (the swarm, its agent state, the step
// statistics, the model), each with its own version, closed by a CRC-32 of
// every byte before it.  This file knows the container and the little-endian
// byte codec only; what goes into the sections is written by
// host/models/swarm_checkpoint.cpp and the models.  Parsing works on a byte
// buffer (fuzzing: parse_checkpoint on any bytes either returns or throws
// Error(Parse)); every count read is checked against the bytes left before
// anything is allocated.
#pragma once
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.hpp"

namespace swarmcl {

// "SWCLCKPT", then the container version.  A reader refuses other versions.
constexpr char kCheckpointMagic[8] = {'S', 'W', 'C', 'L', 'C', 'K', 'P', 'T'};
constexpr uint32_t kCheckpointVersion = 1;
// At most this many sections (a guard against absurd counts; version 1 has 4).
constexpr uint32_t kCheckpointMaxSections = 64;

// Appends little-endian values.
class ByteWriter {
public:
    void u8(uint8_t v) { out_.push_back(char(v)); }
    void u32(uint32_t v) { put(v); }
    void u64(uint64_t v) { put(v); }
    void i32(int32_t v) { put(uint32_t(v)); }
    void f32(float v) {
        uint32_t b;
        std::memcpy(&b, &v, 4);
        put(b);
    }
    void f64(double v) {
        uint64_t b;
        std::memcpy(&b, &v, 8);
        put(b);
    }
    void boolean(bool v) { u8(v ? 1 : 0); }
    void bytes(const void* data, size_t n) { out_.append(static_cast<const char*>(data), n); }
    // u64 length, then the bytes.
    void string(const std::string& s) {
        u64(s.size());
        out_ += s;
    }
    const std::string& data() const { return out_; }
    std::string take() { return std::move(out_); }

private:
    template <typename T>
    void put(T v) {
        for (size_t i = 0; i < sizeof(T); ++i) out_.push_back(char(uint8_t(v >> (8 * i))));
    }
    std::string out_;
};

// Reads what ByteWriter wrote; any read past the end, or a count that the
// bytes left cannot hold, is Error(Parse) naming `what` (the section).
class ByteReader {
public:
    ByteReader(const char* data, size_t size, std::string what) : p_(data), end_(data + size), what_(std::move(what)) {}
    explicit ByteReader(const std::string& s, std::string what) : ByteReader(s.data(), s.size(), std::move(what)) {}

    uint8_t u8() { return uint8_t(get<uint8_t>()); }
    uint32_t u32() { return get<uint32_t>(); }
    uint64_t u64() { return get<uint64_t>(); }
    int32_t i32() { return int32_t(get<uint32_t>()); }
    float f32() {
        const uint32_t b = get<uint32_t>();
        float v;
        std::memcpy(&v, &b, 4);
        return v;
    }
    double f64() {
        const uint64_t b = get<uint64_t>();
        double v;
        std::memcpy(&v, &b, 8);
        return v;
    }
    bool boolean() {
        const uint8_t v = u8();
        if (v > 1) bad("a boolean is " + std::to_string(v));
        return v != 0;
    }
    std::string string() {
        const uint64_t n = count(1);
        std::string s(p_, size_t(n));
        p_ += n;
        return s;
    }
    void bytes(void* out, size_t n) {
        need(n);
        std::memcpy(out, p_, n);
        p_ += n;
    }
    // A count of items at least `item_bytes` each: refused when the bytes
    // left cannot hold that many (so no allocation follows from a bad count).
    uint64_t count(size_t item_bytes) {
        const uint64_t n = u64();
        if (item_bytes > 0 && n > remaining() / item_bytes)
            bad("a count of " + std::to_string(n) + " items does not fit in the " + std::to_string(remaining()) +
                " bytes left");
        return n;
    }
    size_t remaining() const { return size_t(end_ - p_); }
    // The section must be used up (a longer one is not what this version wrote).
    void expect_end() const {
        if (p_ != end_) bad(std::to_string(remaining()) + " unexpected bytes at its end");
    }
    [[noreturn]] void bad(const std::string& why) const { fail(Status::Parse, "checkpoint " + what_ + ": " + why); }
    const std::string& what() const { return what_; }

private:
    void need(size_t n) const {
        if (n > remaining()) bad("ends early (truncated or corrupted)");
    }
    template <typename T>
    T get() {
        need(sizeof(T));
        T v = 0;
        for (size_t i = 0; i < sizeof(T); ++i) v |= T(T(uint8_t(p_[i])) << (8 * i));
        p_ += sizeof(T);
        return v;
    }
    const char* p_;
    const char* end_;
    std::string what_;
};

// One section: a four-letter tag ("SWRM"), its own version, its bytes.
struct CheckpointSection {
    std::array<char, 4> tag{};
    uint32_t version = 1;
    std::string bytes;

    std::string tag_name() const { return std::string(tag.data(), 4); }
};

std::array<char, 4> section_tag(const char (&name)[5]);

// The whole file: magic, version, section count, the sections (tag, version,
// u64 length, bytes), CRC-32 (zlib) of everything before it.
std::string checkpoint_to_bytes(const std::vector<CheckpointSection>& sections);
// Error(Parse) for anything that is not such a file: wrong magic, another
// container version, a short file, a checksum mismatch, absurd counts or
// lengths, a tag twice.  verify_checksum false: for fuzzing only, so that
// mutated inputs reach the section parsers instead of stopping at the CRC.
std::vector<CheckpointSection> parse_checkpoint(const std::string& bytes, bool verify_checksum = true);

// The section with `tag` (Error(Parse) when missing), and a check of its
// version against the ones this reader knows (1..max_version).
const CheckpointSection& find_section(const std::vector<CheckpointSection>& sections, const char (&tag)[5],
                                      uint32_t max_version);

// Written atomically (io/atomic_file); Error(Io) naming the path.
void write_checkpoint_file(const std::string& path, const std::string& bytes);
// Error(Io) when it cannot be read; at most 4 GiB (Error(Parse) beyond).
std::string read_checkpoint_file(const std::string& path);

uint32_t crc32_of(const char* data, size_t size);

}  // namespace swarmcl

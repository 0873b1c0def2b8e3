#include "io/checkpoint.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <zlib.h>

#include "io/atomic_file.hpp"

namespace swarmcl {

uint32_t crc32_of(const char* data, size_t size) {
    // zlib's crc32 takes a uInt length: feed it in chunks.
    uLong crc = crc32(0L, Z_NULL, 0);
    const auto* p = reinterpret_cast<const Bytef*>(data);
    while (size > 0) {
        const uInt chunk = uInt(std::min<size_t>(size, 1u << 30));
        crc = crc32(crc, p, chunk);
        p += chunk;
        size -= chunk;
    }
    return uint32_t(crc);
}

std::array<char, 4> section_tag(const char (&name)[5]) { return {name[0], name[1], name[2], name[3]}; }

std::string checkpoint_to_bytes(const std::vector<CheckpointSection>& sections) {
    ByteWriter w;
    w.bytes(kCheckpointMagic, sizeof kCheckpointMagic);
    w.u32(kCheckpointVersion);
    w.u32(uint32_t(sections.size()));
    for (const CheckpointSection& s : sections) {
        w.bytes(s.tag.data(), 4);
        w.u32(s.version);
        w.u64(s.bytes.size());
        w.bytes(s.bytes.data(), s.bytes.size());
    }
    std::string out = w.take();
    ByteWriter crc;
    crc.u32(crc32_of(out.data(), out.size()));
    return out + crc.data();
}

std::vector<CheckpointSection> parse_checkpoint(const std::string& bytes, bool verify_checksum) {
    const size_t header = sizeof kCheckpointMagic + 8;
    if (bytes.size() < header + 4)
        fail(Status::Parse, "checkpoint: the file is " + std::to_string(bytes.size()) +
                                " bytes, shorter than a header (truncated or not a checkpoint)");
    if (std::memcmp(bytes.data(), kCheckpointMagic, sizeof kCheckpointMagic) != 0)
        fail(Status::Parse, "checkpoint: bad magic (not a swarmcl checkpoint)");
    ByteReader head(bytes.data() + sizeof kCheckpointMagic, 8, "header");
    const uint32_t version = head.u32();
    if (version != kCheckpointVersion)
        fail(Status::Parse, "checkpoint: container version " + std::to_string(version) + " (this reader knows " +
                                std::to_string(kCheckpointVersion) + ")");
    // The checksum before anything else is believed: a flipped bit anywhere
    // is reported as such, not as whatever it made a field say.
    ByteReader tail(bytes.data() + bytes.size() - 4, 4, "checksum");
    const uint32_t stored = tail.u32();
    const uint32_t actual = crc32_of(bytes.data(), bytes.size() - 4);
    if (verify_checksum && stored != actual)
        fail(Status::Parse, "checkpoint: checksum mismatch (the file is truncated or corrupted)");
    const uint32_t count = head.u32();
    if (count > kCheckpointMaxSections)
        fail(Status::Parse, "checkpoint: " + std::to_string(count) + " sections (at most " +
                                std::to_string(kCheckpointMaxSections) + ")");
    ByteReader r(bytes.data() + header, bytes.size() - header - 4, "section table");
    std::vector<CheckpointSection> sections;
    for (uint32_t i = 0; i < count; ++i) {
        CheckpointSection s;
        r.bytes(s.tag.data(), 4);
        for (const CheckpointSection& o : sections)
            if (o.tag == s.tag) r.bad("section " + s.tag_name() + " appears twice");
        s.version = r.u32();
        const uint64_t n = r.count(1);
        s.bytes.resize(size_t(n));
        r.bytes(s.bytes.data(), size_t(n));
        sections.push_back(std::move(s));
    }
    r.expect_end();
    return sections;
}

const CheckpointSection& find_section(const std::vector<CheckpointSection>& sections, const char (&tag)[5],
                                      uint32_t max_version) {
    for (const CheckpointSection& s : sections) {
        if (s.tag != section_tag(tag)) continue;
        if (s.version < 1 || s.version > max_version)
            fail(Status::Parse, std::string("checkpoint: section ") + tag + " has version " +
                                    std::to_string(s.version) + " (this reader knows 1 to " +
                                    std::to_string(max_version) + ")");
        return s;
    }
    fail(Status::Parse, std::string("checkpoint: section ") + tag + " is missing");
}

void write_checkpoint_file(const std::string& path, const std::string& bytes) {
    AtomicFile f(path);
    f.write(bytes.data(), bytes.size());
    f.commit();
}

std::string read_checkpoint_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(Status::Io, "checkpoint '" + path + "' cannot be opened");
    const std::streamoff size = in.tellg();
    if (size < 0) fail(Status::Io, "checkpoint '" + path + "' cannot be read");
    if (uint64_t(size) > (uint64_t(1) << 32))
        fail(Status::Parse, "checkpoint '" + path + "' is " + std::to_string(size) + " bytes (at most 4 GiB)");
    std::string bytes(size_t(size), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), size)) fail(Status::Io, "checkpoint '" + path + "' cannot be read");
    return bytes;
}

}  // namespace swarmcl

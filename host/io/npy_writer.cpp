// The "npy" export: <base>_positions.npy and <base>_velocities.npy, NumPy
// float32 arrays of shape (frames, N, 3).  The header has a fixed size, so
// finish() rewrites it in place once the frame count is known; N must stay
// the same in every frame.
#include <memory>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/export_format.hpp"

namespace swarmcl {
namespace {

// .npy v1.0 header for float32 (frames, n, 3), padded to a fixed 128 bytes so
// it can be rewritten in place once the frame count is known.
std::string npy_header(uint32_t frames, uint32_t n) {
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(frames) + ", " +
                       std::to_string(n) + ", 3), }";
    const size_t total = 128, prefix = 10;
    dict.append(total - prefix - dict.size() - 1, ' ');
    dict += '\n';
    std::string h = "\x93NUMPY";
    h += char(1);
    h += char(0);
    const uint16_t len = uint16_t(dict.size());
    h += char(len & 0xFF);
    h += char(len >> 8);
    return h + dict;
}

class NpyWriter : public FrameWriter {
public:
    NpyWriter(const std::string& dir, const std::string& base)
        : pos_(dir + "/" + base + "_positions.npy"), vel_(dir + "/" + base + "_velocities.npy") {
        pos_.write(npy_header(0, 0));
        vel_.write(npy_header(0, 0));
    }

    void check_frame(uint32_t n) const override {
        if (frames_ > 0 && n != agents_)
            fail(Status::InvalidArgument, "recorder: .npy needs the same agent count in every frame (" +
                                              std::to_string(agents_) + ", now " + std::to_string(n) + ")");
    }

    void add_frame(uint32_t, double, const float* pos, const float* vel, uint32_t n,
                   std::vector<std::string>&) override {
        if (frames_ == 0) agents_ = n;
        pos_.write(pos, sizeof(float) * 3 * size_t(n));
        vel_.write(vel, sizeof(float) * 3 * size_t(n));
        ++frames_;
    }

    void finish(std::vector<std::string>& committed) override {
        for (AtomicFile* f : {&pos_, &vel_}) {
            const std::string h = npy_header(frames_, agents_);
            f->write_at(0, h.data(), h.size());
            f->commit();
            committed.push_back(f->path());
        }
    }

private:
    AtomicFile pos_, vel_;
    uint32_t frames_ = 0, agents_ = 0;
};

}  // namespace

std::unique_ptr<FrameWriter> make_npy_writer(const std::string& dir, const std::string& base) {
    return std::make_unique<NpyWriter>(dir, base);
}

}  // namespace swarmcl

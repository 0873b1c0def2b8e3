#include "io/recorder.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"

namespace swarmcl {
namespace fs = std::filesystem;
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

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

}  // namespace

uint32_t parse_export_formats(const std::string& list) {
    uint32_t mask = 0;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        if (item == "csv") mask |= kExportCsv;
        else if (item == "npy") mask |= kExportNpy;
        else if (item == "vtp") mask |= kExportVtp;
        else if (!item.empty())
            fail(Status::InvalidArgument, "unknown export format '" + item + "' (expected csv, npy or vtp)");
    }
    return mask;
}

Recorder::Recorder(std::string dir, std::string basename, uint32_t formats)
    : dir_(std::move(dir)), base_(std::move(basename)), formats_(formats) {
    require((formats_ & ~uint32_t(kExportAll)) == 0, "export formats: unknown bits in the mask");
    require(!base_.empty() && base_.find('/') == std::string::npos, "export basename must be a plain file name");
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_))
        fail(Status::Io, "output folder '" + dir_ + "' cannot be created: " + (ec ? ec.message() : "not a folder"));
    if (formats_ & kExportCsv) {
        csv_ = std::make_unique<AtomicFile>(dir_ + "/" + base_ + ".csv");
        csv_->write("id,frame,P.x,P.y,P.z,v.x,v.y,v.z\n");
    }
    if (formats_ & kExportNpy) {
        npy_pos_ = std::make_unique<AtomicFile>(dir_ + "/" + base_ + "_positions.npy");
        npy_vel_ = std::make_unique<AtomicFile>(dir_ + "/" + base_ + "_velocities.npy");
        npy_pos_->write(npy_header(0, 0));
        npy_vel_->write(npy_header(0, 0));
    }
}

Recorder::~Recorder() {
    if (!finished_)
        for (const auto& f : files_) std::remove(f.c_str());
}

void Recorder::add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n) {
    require(!finished_, "recorder: add_frame after finish");
    require((pos && vel) || n == 0, "recorder: positions or velocities are NULL");
    if (frames_ == 0) agents_ = n;
    if ((formats_ & kExportNpy) && n != agents_)
        fail(Status::InvalidArgument, "recorder: .npy needs the same agent count in every frame (" +
                                          std::to_string(agents_) + ", now " + std::to_string(n) + ")");
    if (csv_) {
        std::string rows;
        rows.reserve(size_t(n) * 96);
        const std::string f = std::to_string(frame);
        for (uint32_t i = 0; i < n; ++i) {
            rows += std::to_string(i);
            rows += ',';
            rows += f;
            for (const float* v : {pos + 3 * size_t(i), vel + 3 * size_t(i)})
                for (int a = 0; a < 3; ++a) {
                    rows += ',';
                    rows += fmt(v[a]);
                }
            rows += '\n';
        }
        csv_->write(rows);
    }
    if (npy_pos_) {
        npy_pos_->write(pos, sizeof(float) * 3 * size_t(n));
        npy_vel_->write(vel, sizeof(float) * 3 * size_t(n));
    }
    if (formats_ & kExportVtp) {
        write_vtp(frame, pos, vel, n);
        char name[64];
        std::snprintf(name, sizeof name, "_%06u.vtp", frame);
        pvd_entries_ += "    <DataSet timestep=\"" + fmt(time) + "\" group=\"\" part=\"0\" file=\"" + base_ + name + "\"/>\n";
    }
    ++frames_;
}

// VTK XML PolyData with raw appended binary data (UInt64 block headers):
// Points, one vertex cell per point (so ParaView draws them), and point data
// "v" (velocity) and "id".
void Recorder::write_vtp(uint32_t frame, const float* pos, const float* vel, uint32_t n) {
    char name[64];
    std::snprintf(name, sizeof name, "_%06u.vtp", frame);
    const std::string path = dir_ + "/" + base_ + name;
    const uint64_t vec_bytes = uint64_t(n) * 12, int_bytes = uint64_t(n) * 4;
    // Appended blocks in order: points, velocity, id, connectivity, offsets.
    const uint64_t sizes[5] = {vec_bytes, vec_bytes, int_bytes, int_bytes, int_bytes};
    uint64_t offsets[5], at = 0;
    for (int b = 0; b < 5; ++b) {
        offsets[b] = at;
        at += 8 + sizes[b];
    }
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        << "  <PolyData>\n    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"" << n
        << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
        << "      <PointData Vectors=\"v\" Scalars=\"id\">\n"
        << "        <DataArray type=\"Float32\" Name=\"v\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" << offsets[1] << "\"/>\n"
        << "        <DataArray type=\"UInt32\" Name=\"id\" format=\"appended\" offset=\"" << offsets[2] << "\"/>\n"
        << "      </PointData>\n      <Points>\n"
        << "        <DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" << offsets[0] << "\"/>\n"
        << "      </Points>\n      <Verts>\n"
        << "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"" << offsets[3] << "\"/>\n"
        << "        <DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"" << offsets[4] << "\"/>\n"
        << "      </Verts>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
    AtomicFile out(path);
    out.write(xml.str());
    std::vector<int32_t> ints(n);
    auto block = [&](const void* data, uint64_t bytes) {
        out.write(&bytes, sizeof bytes);
        out.write(data, size_t(bytes));
    };
    block(pos, vec_bytes);
    block(vel, vec_bytes);
    for (uint32_t i = 0; i < n; ++i) ints[i] = int32_t(i);
    block(ints.data(), int_bytes);  // ids
    block(ints.data(), int_bytes);  // connectivity: vertex i is point i
    for (uint32_t i = 0; i < n; ++i) ints[i] = int32_t(i + 1);
    block(ints.data(), int_bytes);  // offsets
    out.write("\n  </AppendedData>\n</VTKFile>\n");
    out.commit();
    files_.push_back(path);
}

void Recorder::finish() {
    require(!finished_, "recorder: finish called twice");
    if (csv_) {
        csv_->commit();
        files_.push_back(csv_->path());
    }
    if (npy_pos_) {
        for (auto* f : {npy_pos_.get(), npy_vel_.get()}) {
            const std::string h = npy_header(frames_, agents_);
            f->write_at(0, h.data(), h.size());
            f->commit();
            files_.push_back(f->path());
        }
    }
    if (formats_ & kExportVtp) {
        AtomicFile pvd(dir_ + "/" + base_ + ".pvd");
        pvd.write("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                  "  <Collection>\n" + pvd_entries_ + "  </Collection>\n</VTKFile>\n");
        pvd.commit();
        files_.push_back(pvd.path());
    }
    finished_ = true;
}

}  // namespace swarmcl

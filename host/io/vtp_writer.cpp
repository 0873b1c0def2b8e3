// The "vtp" export: one VTK XML PolyData file per frame, <base>_<frame>.vtp
// (committed as it comes), and the <base>.pvd series that ParaView opens
// (committed by finish()).
#include <cstdio>
#include <memory>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/export_format.hpp"

namespace swarmcl {
namespace {

class VtpWriter : public FrameWriter {
public:
    VtpWriter(const std::string& dir, const std::string& base) : dir_(dir), base_(base) {}

    void add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n,
                   std::vector<std::string>& committed) override {
        char name[64];
        std::snprintf(name, sizeof name, "_%06u.vtp", frame);
        write_vtp(dir_ + "/" + base_ + name, pos, vel, n);
        committed.push_back(dir_ + "/" + base_ + name);
        pvd_entries_ += "    <DataSet timestep=\"" + format_g9(time) + "\" group=\"\" part=\"0\" file=\"" + base_ +
                        name + "\"/>\n";
    }

    void finish(std::vector<std::string>& committed) override {
        AtomicFile pvd(dir_ + "/" + base_ + ".pvd");
        pvd.write("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                  "  <Collection>\n" + pvd_entries_ + "  </Collection>\n</VTKFile>\n");
        pvd.commit();
        committed.push_back(pvd.path());
    }

private:
    // VTK XML PolyData with raw appended binary data (UInt64 block headers):
    // Points, one vertex cell per point (so ParaView draws them), and point
    // data "v" (velocity) and "id".
    static void write_vtp(const std::string& path, const float* pos, const float* vel, uint32_t n) {
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
    }

    std::string dir_, base_;
    std::string pvd_entries_;
};

}  // namespace

std::unique_ptr<FrameWriter> make_vtp_writer(const std::string& dir, const std::string& base) {
    return std::make_unique<VtpWriter>(dir, base);
}

}  // namespace swarmcl

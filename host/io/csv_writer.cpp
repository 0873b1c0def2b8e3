// The "csv" export: <base>.csv, one row per agent and frame with Houdini's
// and Blender's attribute names (id,frame,P.x,P.y,P.z,v.x,v.y,v.z), floats
// as "%.9g" (every float32 exactly).  Committed by finish().
#include <memory>

#include "io/atomic_file.hpp"
#include "io/export_format.hpp"

namespace swarmcl {
namespace {

class CsvWriter : public FrameWriter {
public:
    CsvWriter(const std::string& dir, const std::string& base) : file_(dir + "/" + base + ".csv") {
        file_.write("id,frame,P.x,P.y,P.z,v.x,v.y,v.z\n");
    }

    void add_frame(uint32_t frame, double, const float* pos, const float* vel, uint32_t n,
                   std::vector<std::string>&) override {
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
                    rows += format_g9(v[a]);
                }
            rows += '\n';
        }
        file_.write(rows);
    }

    void finish(std::vector<std::string>& committed) override {
        file_.commit();
        committed.push_back(file_.path());
    }

private:
    AtomicFile file_;
};

}  // namespace

std::unique_ptr<FrameWriter> make_csv_writer(const std::string& dir, const std::string& base) {
    return std::make_unique<CsvWriter>(dir, base);
}

}  // namespace swarmcl

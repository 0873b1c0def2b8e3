#include "io/export_format.hpp"

#include <cstdio>
#include <sstream>

#include "core/error.hpp"

namespace swarmcl {

// The writers, one file each (io/<name>_writer.cpp).
std::unique_ptr<FrameWriter> make_csv_writer(const std::string& dir, const std::string& base);
std::unique_ptr<FrameWriter> make_npy_writer(const std::string& dir, const std::string& base);
std::unique_ptr<FrameWriter> make_vtp_writer(const std::string& dir, const std::string& base);

const std::vector<ExportFormatInfo>& export_formats() {
    static const std::vector<ExportFormatInfo> table = {
        {"csv", kExportCsv, "<base>.csv: id,frame,P.x,P.y,P.z,v.x,v.y,v.z", make_csv_writer},
        {"npy", kExportNpy, "<base>_positions.npy, <base>_velocities.npy: float32 (frames, N, 3)", make_npy_writer},
        {"vtp", kExportVtp, "<base>_<frame>.vtp per frame and <base>.pvd for ParaView", make_vtp_writer},
    };
    return table;
}

uint32_t all_export_formats() {
    uint32_t mask = 0;
    for (const auto& f : export_formats()) mask |= f.bit;
    return mask;
}

const ExportFormatInfo* find_export_format(const std::string& name) {
    for (const auto& f : export_formats())
        if (name == f.name) return &f;
    return nullptr;
}

std::string export_format_choices(const std::string& quote) {
    const auto& table = export_formats();
    std::string s;
    for (size_t i = 0; i < table.size(); ++i) {
        if (i) s += i + 1 == table.size() ? " or " : ", ";
        s += quote + table[i].name + quote;
    }
    return s;
}

uint32_t parse_export_formats(const std::string& list) {
    if (list.empty()) fail(Status::InvalidArgument, "no export format given (expected " + export_format_choices() + ")");
    uint32_t mask = 0;
    std::stringstream in(list + ",");  // so that a trailing comma gives an empty name
    std::string item;
    while (std::getline(in, item, ',')) {
        const ExportFormatInfo* f = find_export_format(item);
        if (!f)
            fail(Status::InvalidArgument, (item.empty() ? std::string("empty export format name")
                                                        : "unknown export format '" + item + "'") +
                                              " (expected " + export_format_choices() + ")");
        mask |= f->bit;
    }
    return mask;
}

std::vector<std::string> export_format_names(uint32_t mask) {
    if (mask & ~all_export_formats())
        fail(Status::InvalidArgument, "export formats: unknown bits in the mask " + std::to_string(mask));
    std::vector<std::string> names;
    for (const auto& f : export_formats())
        if (mask & f.bit) names.emplace_back(f.name);
    return names;
}

std::string format_g9(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

}  // namespace swarmcl

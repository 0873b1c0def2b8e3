// Recording trajectories (host/io/recorder: CSV, .npy, VTK) and the export
// formats by name (host/io/export_format).
#include <mutex>
#include <vector>

#include "capi_common.hpp"
#include "io/recorder.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

// The header's bits are the table's.
static_assert(uint32_t(SWCL_EXPORT_CSV) == kExportCsv && uint32_t(SWCL_EXPORT_NPY) == kExportNpy &&
                  uint32_t(SWCL_EXPORT_VTP) == kExportVtp,
              "swcl_export_format and io/export_format.hpp disagree");

namespace {

// A recorder with its own lock (frames may come from several threads).
struct RecorderHandle {
    std::mutex mutex;
    Recorder recorder;
    std::vector<float> pos, vel;
    RecorderHandle(std::string dir, std::string base, uint32_t formats)
        : recorder(std::move(dir), std::move(base), formats) {}
};

HandleRegistry<RecorderHandle>& recorders() {
    static auto* registry = new HandleRegistry<RecorderHandle>(0x9E, "recorder");
    return *registry;
}

}  // namespace

extern "C" {

swcl_status swcl_recorder_create(const char* dir, const char* basename, uint32_t formats, swcl_recorder* out) {
    return guarded(__func__, [&] {
        require(dir != nullptr && *dir, "dir is NULL or empty");
        require(basename != nullptr && *basename, "basename is NULL or empty");
        require(formats != 0, "formats is 0: choose SWCL_EXPORT_CSV, _NPY and/or _VTP");
        check_out(out, "out");
        out->id = recorders().add(std::make_shared<RecorderHandle>(dir, basename, formats));
    });
}

swcl_status swcl_recorder_add_frame(swcl_recorder recorder, swcl_swarm swarm, uint32_t frame, double time) {
    return guarded(__func__, [&] {
        auto r = recorders().get(recorder.id);
        auto s = swarms().get(swarm.id);
        std::lock_guard<std::mutex> lock(r->mutex);
        {
            std::lock_guard<std::mutex> swarm_lock(s->mutex());
            s->require_one_world("a recorder");
            const uint32_t n = s->agent_count();
            r->pos.resize(size_t(n) * 3);
            r->vel.resize(size_t(n) * 3);
            s->read(Attribute::Position, r->pos.data(), n);
            s->read(Attribute::Velocity, r->vel.data(), n);
        }
        r->recorder.add_frame(frame, time, r->pos.data(), r->vel.data(), uint32_t(r->pos.size() / 3));
    });
}

swcl_status swcl_recorder_finish(swcl_recorder recorder) {
    return guarded(__func__, [&] {
        auto r = recorders().get(recorder.id);
        std::lock_guard<std::mutex> lock(r->mutex);
        r->recorder.finish();
    });
}

swcl_status swcl_recorder_destroy(swcl_recorder recorder) {
    return guarded(__func__, [&] { recorders().remove(recorder.id); });
}

const char* swcl_export_format_name(uint32_t format) {
    for (const ExportFormatInfo& f : export_formats())
        if (f.bit == format) return f.name;
    return nullptr;
}

swcl_status swcl_export_formats_parse(const char* list, uint32_t* out) {
    return guarded(__func__, [&] {
        require(list != nullptr, "list is NULL");
        check_out(out, "out");
        *out = parse_export_formats(list);
    });
}

}  // extern "C"

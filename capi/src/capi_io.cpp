// Scenario files and trajectory recording.
#include <cstring>
#include <mutex>
#include <vector>

#include "capi_common.hpp"
#include "io/recorder.hpp"
#include "models/model_spec.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/scenario.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

// A recorder with its own lock (frames may come from several threads).
struct RecorderHandle {
    std::mutex mutex;
    Recorder recorder;
    std::vector<float> pos, vel;
    RecorderHandle(std::string dir, std::string base, uint32_t formats)
        : recorder(std::move(dir), std::move(base), formats) {}
};

HandleRegistry<Scenario>& scenarios() {
    static auto* registry = new HandleRegistry<Scenario>(0x5C, "scenario");
    return *registry;
}

HandleRegistry<RecorderHandle>& recorders() {
    static auto* registry = new HandleRegistry<RecorderHandle>(0x9E, "recorder");
    return *registry;
}

template <size_t N>
void copy_text(char (&dst)[N], const std::string& src) {
    const size_t n = std::min(src.size(), N - 1);
    std::memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

}  // namespace

extern "C" {

swcl_status swcl_scenario_load(const char* path, swcl_scenario* out) {
    return guarded(__func__, [&] {
        require(path != nullptr, "path is NULL");
        check_out(out, "out");
        out->id = scenarios().add(std::make_shared<Scenario>(load_scenario(path)));
    });
}

swcl_status swcl_scenario_parse(const char* text, size_t length, swcl_scenario* out) {
    return guarded(__func__, [&] {
        require(text != nullptr || length == 0, "text is NULL");
        check_out(out, "out");
        out->id = scenarios().add(std::make_shared<Scenario>(parse_scenario(std::string(text ? text : "", length))));
    });
}

swcl_status swcl_scenario_destroy(swcl_scenario scenario) {
    return guarded(__func__, [&] { scenarios().remove(scenario.id); });
}

swcl_status swcl_scenario_get_info(swcl_scenario scenario, swcl_scenario_info* out) {
    return guarded(__func__, [&] {
        check_struct_size(out, sizeof(swcl_scenario_info), "out");
        auto s = scenarios().get(scenario.id);
        swcl_scenario_info info;
        std::memset(&info, 0, sizeof(info));
        info.struct_size = sizeof(info);
        info.agents = s->swarm.agent_count;
        info.steps = s->steps;
        info.output_every = s->output_every;
        info.output_formats = s->output_formats;
        info.dt = s->swarm.dt;
        info.seed = s->swarm.seed;
        copy_text(info.name, s->name);
        copy_text(info.output_dir, s->output_dir);
        copy_text(info.model, model_name(s->model));
        info.min_distance = model_min_distance(s->model);
        *out = info;
    });
}

swcl_status swcl_scenario_create_swarm(swcl_scenario scenario, swcl_context context, swcl_swarm* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        auto s = scenarios().get(scenario.id);
        auto ctx = contexts().get(context.id);
        auto swarm = make_swarm(ctx, *s);
        out->id = swarms().add(std::move(swarm));
    });
}

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

}  // extern "C"

// FASTSWARM through the C API: reference datasets (tracks in, files) and the
// energy model on a swarm.
#include <cmath>
#include <cstddef>
#include <cstring>

#include "capi_common.hpp"
#include "capi_noise.hpp"
#include "capi_tracks.hpp"
#include "data/dataset.hpp"
#include "scenario/synthesis.hpp"
#include "data/tracks.hpp"
#include "models/energy_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

HandleRegistry<const Dataset>& datasets() {
    static auto* registry = new HandleRegistry<const Dataset>(0xD5, "dataset");
    return *registry;
}

DatasetOptions dataset_options(const swcl_dataset_desc& d) {
    DatasetOptions o;
    o.k = d.k;
    o.groups = d.groups;
    o.seed = d.seed;
    return o;
}

EnergyWeights weights_from(const swcl_energy_weights& w) {
    return {w.rep, w.oa, w.cos, w.dir, w.acc, w.env, w.noise, w.user};
}

swcl_energy_weights weights_to(const EnergyWeights& w) {
    return {w.rep, w.oa, w.cos, w.dir, w.acc, w.env, w.n, w.user};
}

std::vector<Stimulus> stimuli_from(const swcl_stimulus* s, uint32_t count) {
    require(s != nullptr || count == 0, "stimuli is NULL but the count is " + std::to_string(count));
    std::vector<Stimulus> out;
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t kind = enum_bits(s[i].kind);  // a C caller's value may be any int
        require(kind == SWCL_STIMULUS_ATTRACT || kind == SWCL_STIMULUS_STARTLE,
                "stimuli[" + std::to_string(i) + "].kind (" + c_enum_text(kind) +
                    ") is not a swcl_stimulus_kind");
        Stimulus st;
        st.kind = kind == SWCL_STIMULUS_ATTRACT ? Stimulus::Kind::Attract : Stimulus::Kind::Startle;
        for (int a = 0; a < 3; ++a) {
            st.position[a] = s[i].position[a];
            st.velocity[a] = s[i].velocity[a];
        }
        st.d_danger = s[i].d_danger;
        out.push_back(st);
    }
    return out;
}

std::vector<std::array<float, 3>> keypoints_from(const float* xyz, uint32_t count) {
    require(xyz != nullptr || count == 0, "keypoints is NULL but the count is " + std::to_string(count));
    std::vector<std::array<float, 3>> out(count);
    for (uint32_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a) out[i][a] = xyz[3 * size_t(i) + a];
    return out;
}

EnergyModel& energy_model_of(Swarm& s) {
    auto* m = dynamic_cast<EnergyModel*>(s.behavior());
    if (!m) fail(Status::InvalidArgument, "the swarm has no energy model (swcl_swarm_energy_set_model)");
    return *m;
}

template <typename F>
void add_dataset(swcl_dataset* out, F&& build) {
    check_out(out, "out");
    out->id = datasets().add(std::make_shared<const Dataset>(build()));
}

}  // namespace

namespace swarmcl::capi {

TrackLoadOptions track_options(const swcl_dataset_desc& d) {
    TrackLoadOptions o;
    if (d.column_id) o.columns.id = d.column_id;
    if (d.column_time) o.columns.time = d.column_time;
    if (d.column_x) o.columns.x = d.column_x;
    if (d.column_y) o.columns.y = d.column_y;
    if (d.column_z) o.columns.z = d.column_z;
    const uint32_t time_format = enum_bits(d.time_format);
    require(time_format <= SWCL_TIME_DATETIME,
            "desc->time_format (" + c_enum_text(time_format) + ") is not a swcl_time_format");
    o.time_format = TimeFormat(time_format);
    o.frame_time = d.frame_time;
    o.unit_scale = d.unit_scale;
    o.gap_factor = d.gap_factor;
    o.smoothing = d.smoothing;
    if (d.struct_size >= offsetof(swcl_dataset_desc, delimiter) + sizeof(d.delimiter)) {
        require(d.delimiter != '\n' && d.delimiter != '\r' && d.delimiter != '\0',
                "desc->delimiter must be a field separator such as ',', ';' or '\\t' (not a line end or NUL)");
        o.delimiter = d.delimiter;
    }
    return o;
}

}  // namespace swarmcl::capi

extern "C" {

swcl_dataset_desc swcl_dataset_desc_default(void) {
    swcl_dataset_desc d;
    std::memset(&d, 0, sizeof(d));
    const TrackLoadOptions t;
    const DatasetOptions o;
    d.struct_size = sizeof(d);
    d.time_format = SWCL_TIME_AUTO;
    d.frame_time = t.frame_time;
    d.unit_scale = t.unit_scale;
    d.gap_factor = t.gap_factor;
    d.smoothing = t.smoothing;
    d.delimiter = t.delimiter;
    d.k = o.k;
    d.groups = o.groups;
    d.seed = o.seed;
    d.synthetic_mean_speed = 0.5f;
    return d;
}

swcl_status swcl_dataset_from_csv(const char* path, const swcl_dataset_desc* desc, swcl_dataset* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, offsetof(swcl_dataset_desc, delimiter), "desc");
        require(path != nullptr && *path, "path is NULL or empty");
        add_dataset(out, [&] {
            const TrackSet set = load_tracks_csv(path, track_options(*desc));
            return build_dataset(track_kinematics(set), dataset_options(*desc), set.frame_time);
        });
    });
}

swcl_status swcl_dataset_from_tracks(const uint32_t* counts, size_t track_count, const double* times,
                                     const float* xyz, const swcl_dataset_desc* desc, swcl_dataset* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, offsetof(swcl_dataset_desc, delimiter), "desc");
        add_dataset(out, [&] {
            const TrackSet set = tracks_from_arrays(counts, track_count, times, xyz, track_options(*desc));
            return build_dataset(track_kinematics(set), dataset_options(*desc), set.frame_time);
        });
    });
}

swcl_status swcl_dataset_synthetic(const swcl_dataset_desc* desc, swcl_dataset* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, offsetof(swcl_dataset_desc, delimiter), "desc");
        const double ft = desc->frame_time > 0.0 ? desc->frame_time : 0.01;
        require(std::isfinite(ft), "desc->frame_time must be finite");
        add_dataset(out, [&] { return synthetic_dataset(dataset_options(*desc), ft, desc->synthetic_mean_speed); });
    });
}

swcl_status swcl_dataset_load(const char* path, swcl_dataset* out) {
    return guarded(__func__, [&] {
        require(path != nullptr && *path, "path is NULL or empty");
        add_dataset(out, [&] { return load_dataset(path); });
    });
}

swcl_status swcl_dataset_save(swcl_dataset dataset, const char* path) {
    return guarded(__func__, [&] {
        require(path != nullptr && *path, "path is NULL or empty");
        save_dataset(*datasets().get(dataset.id), path);
    });
}

swcl_status swcl_dataset_destroy(swcl_dataset dataset) {
    return guarded(__func__, [&] { datasets().remove(dataset.id); });
}

swcl_status swcl_dataset_get_info(swcl_dataset dataset, swcl_dataset_info* out) {
    return guarded(__func__, [&] {
        check_struct_size(out, sizeof(swcl_dataset_info), "out");
        auto d = datasets().get(dataset.id);
        swcl_dataset_info info;
        std::memset(&info, 0, sizeof(info));
        info.struct_size = sizeof(info);
        info.samples = d->size();
        info.groups = d->groups();
        info.frame_time = d->frame_time;
        *out = info;
    });
}

swcl_status swcl_dataset_read(swcl_dataset dataset, float* out_v, float* out_a, size_t count) {
    return guarded(__func__, [&] {
        auto d = datasets().get(dataset.id);
        require(count == d->size(), "count is " + std::to_string(count) + " but the dataset has " +
                                        std::to_string(d->size()) + " samples");
        for (size_t i = 0; i < count; ++i)
            for (int a = 0; a < 3; ++a) {
                if (out_v) out_v[3 * i + a] = d->v[i][a];
                if (out_a) out_a[3 * i + a] = d->a[i][a];
            }
    });
}

swcl_energy_model_desc swcl_energy_model_desc_default(void) {
    swcl_energy_model_desc d;
    std::memset(&d, 0, sizeof(d));
    const EnergyModelConfig c;
    d.struct_size = sizeof(d);
    d.weights = weights_to(c.weights);
    d.danger_weights = weights_to(c.danger_weights);
    d.rho = c.rho;
    d.d_rep = c.d_rep;
    d.d_att1 = c.d_att1;
    d.d_att2 = c.d_att2;
    d.span = c.span;
    d.accel_time = c.accel_time;
    d.danger_horizon = c.danger_horizon;
    d.noise = swcl_noise_desc_default();
    d.noise.scale = c.noise.scale;
    d.noise.time_scale = c.noise.time_scale;
    d.keypoints_closed = c.keypoints_closed ? 1 : 0;
    d.bidirectional = c.bidirectional ? 1 : 0;
    d.keypoint_reach = c.keypoint_reach;
    d.keep_out = c.keep_out ? 1 : 0;
    return d;
}

swcl_status swcl_swarm_energy_set_model(swcl_swarm swarm, swcl_dataset dataset, const swcl_energy_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(desc, sizeof(swcl_energy_model_desc), "desc");
        check_struct_size(&desc->noise, sizeof(swcl_noise_desc), "desc->noise");
        auto d = datasets().get(dataset.id);
        EnergyModelConfig c;
        c.weights = weights_from(desc->weights);
        c.danger_weights = weights_from(desc->danger_weights);
        c.rho = desc->rho;
        c.d_rep = desc->d_rep;
        c.d_att1 = desc->d_att1;
        c.d_att2 = desc->d_att2;
        c.has_fixed_centre = desc->has_fixed_centre != 0;
        for (int a = 0; a < 3; ++a) c.fixed_centre[a] = desc->fixed_centre[a];
        c.span = desc->span;
        c.accel_time = desc->accel_time;
        c.danger_horizon = desc->danger_horizon;
        c.noise = noise_config_from(desc->noise);
        c.stimuli = stimuli_from(desc->stimuli, desc->stimulus_count);
        c.keypoints = keypoints_from(desc->keypoints, desc->keypoint_count);
        c.keypoints_closed = desc->keypoints_closed != 0;
        c.bidirectional = desc->bidirectional != 0;
        c.keypoint_reach = desc->keypoint_reach;
        c.keep_out = desc->keep_out != 0;
        s.set_behavior(std::make_shared<EnergyModel>(s, std::move(c), d));
    });
}

swcl_status swcl_swarm_energy_set_stimuli(swcl_swarm swarm, const swcl_stimulus* stimuli, uint32_t count) {
    return with_swarm(__func__, swarm,
                      [&](Swarm& s) { energy_model_of(s).set_stimuli(stimuli_from(stimuli, count)); });
}

swcl_status swcl_swarm_energy_set_keypoints(swcl_swarm swarm, const float* xyz, uint32_t count, int32_t closed) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        energy_model_of(s).set_keypoints(keypoints_from(xyz, count), closed != 0);
    });
}

swcl_status swcl_swarm_energy_get_goals(swcl_swarm swarm, int32_t* out_goals, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(out_goals != nullptr || count == 0, "out_goals is NULL");
        const size_t agents = size_t(s.agent_count()) * s.worlds();
        require(count == agents, "count is " + std::to_string(count) + " but the swarm has " + std::to_string(agents) +
                                     " agents" + (s.worlds() > 1 ? " (all its worlds)" : ""));
        std::vector<int32_t> goal;
        std::vector<uint8_t> back;
        energy_model_of(s).goals(s, goal, back);
        std::copy(goal.begin(), goal.end(), out_goals);
    });
}

swcl_status swcl_swarm_start_from_tracks(swcl_swarm swarm, const uint32_t* counts, size_t track_count,
                                         const double* times, const float* xyz, const swcl_dataset_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        swcl_dataset_desc d = swcl_dataset_desc_default();
        if (desc) {
            check_struct_size(desc, offsetof(swcl_dataset_desc, delimiter), "desc");
            d = *desc;
        }
        start_from_tracks(s, tracks_from_arrays(counts, track_count, times, xyz, track_options(d)));
    });
}

}  // extern "C"

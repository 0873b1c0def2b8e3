// The evaluation against real insects through the C API (noise paper §3;
// docs/evaluation.md): metric sets from tracks or frames, their PDFs,
// distances and scores, and entropy weights.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "capi_common.hpp"
#include "capi_tracks.hpp"
#include "eval/entropy_weights.hpp"
#include "eval/metric_accumulator.hpp"
#include "eval/metrics.hpp"
#include "eval/pdf_distance.hpp"
#include "eval/swarm_metrics.hpp"
#include "eval/time_window.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

// What a swcl_metrics holds: the samples themselves (tracks, frames: exact
// PDFs), the streamed fine histograms of a swarm's metrics on the device
// (eval/swarm_metrics.hpp), which keep the swarm alive and are sampled under
// its lock, or one world's streamed result taken at a point in time
// (swcl_metrics_world).
struct MetricSet {
    std::optional<MetricSamples> samples;
    std::shared_ptr<Swarm> swarm;
    std::unique_ptr<SwarmMetrics> stream;
    std::optional<MetricAccumulator> taken;
    double frame_time = 0.0;

    Moments moments(Metric m) const {
        if (samples) return moments_of((*samples)[m]);
        return stream_result().moments(m);
    }
    // Median and MAD (unscaled) of the finite samples.
    std::pair<double, double> median_mad(Metric m) const {
        if (samples) {
            const double med = median_of((*samples)[m]);
            return {med, mad_of((*samples)[m], med)};
        }
        const MetricAccumulator a = stream_result();
        return {a.median(m), a.mad(m)};
    }
    // The samples as fine histograms (a swarm's streamed result as it is).
    MetricAccumulator accumulated() const {
        if (!samples) return stream_result();
        MetricAccumulator a;
        a.add(*samples);
        return a;
    }
    uint64_t count(Metric m) const { return samples ? (*samples)[m].size() : stream_result().count(m); }
    std::vector<double> pdf(Metric m, const PdfOptions& o) const {
        if (samples) {
            const auto& x = (*samples)[m];
            for (double v : x)
                if (!std::isfinite(v))
                    fail(Status::InvalidArgument, std::string("pdf: a sample of ") + metric_name(m) + " is not finite");
            return discrete_pdf(x, location_scale(x, o.standardise), o);
        }
        return stream_result().discrete_pdf(m, o);
    }
    // The streamed result, taken once per call under the swarm's lock (or
    // the world's result taken before).
    MetricAccumulator stream_result() const {
        if (taken) return *taken;
        std::lock_guard<std::mutex> lock(swarm->mutex());
        if (stream->worlds() > 1)
            fail(Status::InvalidArgument, "these metrics hold " + std::to_string(stream->worlds()) +
                                              " worlds: read one world's with swcl_metrics_world");
        return stream->result();
    }
};

HandleRegistry<MetricSet>& metric_sets() {
    static auto* registry = new HandleRegistry<MetricSet>(0xE7, "metrics");
    return *registry;
}

void add_metrics(swcl_metrics* out, MetricSamples&& m) {
    auto set = std::make_shared<MetricSet>();
    set->frame_time = m.frame_time;
    set->samples = std::move(m);
    out->id = metric_sets().add(set);
}

TrackLoadOptions options_or_default(const swcl_dataset_desc* desc) {
    if (!desc) return track_options(swcl_dataset_desc_default());
    check_struct_size(desc, offsetof(swcl_dataset_desc, delimiter), "tracks");
    return track_options(*desc);
}

// The metric a C caller named, if it is one.  By reference: a by-value copy
// would load the enum before the range check.
std::optional<Metric> metric_if_valid(const swcl_metric& m) {
    const uint32_t k = enum_bits(m);
    if (k >= uint32_t(SWCL_METRIC_COUNT)) return std::nullopt;
    return Metric(k);
}

Metric metric_from(const swcl_metric& m) {
    const std::optional<Metric> k = metric_if_valid(m);
    require(k.has_value(), "metric " + c_enum_text(enum_bits(m)) + " is not a swcl_metric");
    return *k;
}

PdfOptions pdf_options_from(const swcl_pdf_options* o) {
    PdfOptions p;
    if (!o) return p;
    check_struct_size(o, offsetof(swcl_pdf_options, standardise), "options");  // the first version's size
    p.bins = o->bins;
    p.half_width = o->half_width;
    if (o->struct_size >= offsetof(swcl_pdf_options, standardise) + sizeof(o->standardise)) {
        const uint32_t standardise = enum_bits(o->standardise);  // a C caller's value may be any int
        require(standardise == SWCL_STANDARDISE_MEAN_SIGMA || standardise == SWCL_STANDARDISE_MEDIAN_MAD,
                "options->standardise (" + c_enum_text(standardise) +
                    ") must be SWCL_STANDARDISE_MEAN_SIGMA or SWCL_STANDARDISE_MEDIAN_MAD");
        p.standardise = Standardise(standardise);
    }
    return p;
}

// swcl_metric is the metric table's order (eval/metric_table.hpp; every
// enumerator is checked against the table's names by tests/test_eval_capi.cpp).
static_assert(SWCL_METRIC_COUNT == int(kMetricCount), "swcl_metric and swarmcl::Metric disagree");

}  // namespace

extern "C" {

const char* swcl_metric_name(swcl_metric metric) {
    const std::optional<Metric> m = metric_if_valid(metric);
    return m ? metric_info(*m).name : nullptr;
}

swcl_status swcl_metrics_from_csv(const char* path, const swcl_dataset_desc* tracks, double window_from,
                                  double window_to, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        require(path != nullptr && *path, "path is NULL or empty");
        const TrackLoadOptions o = options_or_default(tracks);
        add_metrics(out, track_metrics(time_window(load_tracks_csv(path, o), window_from, window_to)));
    });
}

swcl_status swcl_metrics_from_tracks(const uint32_t* counts, size_t track_count, const double* times,
                                     const float* xyz, const swcl_dataset_desc* tracks, double window_from,
                                     double window_to, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        const TrackLoadOptions o = options_or_default(tracks);
        add_metrics(out, track_metrics(time_window(tracks_from_arrays(counts, track_count, times, xyz, o),
                                                   window_from, window_to)));
    });
}

swcl_status swcl_tracks_read_csv(const char* path, const swcl_dataset_desc* tracks, double window_from,
                                 double window_to, uint32_t* counts, uint32_t* insects, size_t segment_capacity,
                                 double* times, float* xyz, size_t sample_capacity, size_t* out_segments,
                                 size_t* out_samples, double* out_frame_time) {
    return guarded(__func__, [&] {
        check_out(out_segments, "out_segments");
        check_out(out_samples, "out_samples");
        require(path != nullptr, "path is NULL");
        const TrackSet set = time_window(load_tracks_csv(path, options_or_default(tracks)), window_from, window_to);
        size_t samples = 0;
        for (const Track& t : set.tracks) samples += t.t.size();
        const bool sizes_only = !counts && !insects && !times && !xyz && segment_capacity == 0 && sample_capacity == 0;
        if (!sizes_only) {
            require(counts && insects && times && xyz, "counts, insects, times and xyz: all NULL (sizes) or none");
            require(segment_capacity >= set.tracks.size() && sample_capacity >= samples,
                    "capacity too small: " + std::to_string(set.tracks.size()) + " segments and " +
                        std::to_string(samples) + " samples");
            std::map<std::string, uint32_t> insect_of;
            size_t s = 0;
            for (size_t k = 0; k < set.tracks.size(); ++k) {
                const Track& t = set.tracks[k];
                counts[k] = uint32_t(t.t.size());
                insects[k] = insect_of.emplace(t.id, uint32_t(insect_of.size())).first->second;
                for (size_t i = 0; i < t.t.size(); ++i, ++s) {
                    times[s] = t.t[i];
                    for (int a = 0; a < 3; ++a) xyz[3 * s + a] = float(t.p[i][size_t(a)]);
                }
            }
        }
        *out_segments = set.tracks.size();
        *out_samples = samples;
        if (out_frame_time) *out_frame_time = set.frame_time;
    });
}

swcl_status swcl_metrics_from_frames(const float* xyz, size_t frames, size_t agents, double dt, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        require(frames == 0 || agents <= (size_t(1) << 40) / frames, "frames * agents is too large");
        add_metrics(out, frame_metrics(xyz, frames, agents, dt));
    });
}

swcl_status swcl_metrics_from_frames_strided(const float* xyz, size_t frames, size_t agents, size_t frame_stride,
                                             double dt, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        require(frame_stride >= 3 * agents && frame_stride > 0,
                "frame_stride " + std::to_string(frame_stride) + ": at least 3 * agents = " +
                    std::to_string(3 * agents) + " and above 0");
        require(frames == 0 || frame_stride <= (size_t(1) << 42) / frames, "frames * frame_stride is too large");
        add_metrics(out, frame_metrics(xyz, frames, agents, dt, frame_stride));
    });
}

swcl_status swcl_metrics_attach(swcl_swarm swarm, double sample_dt, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        auto set = std::make_shared<MetricSet>();
        set->swarm = swarms().get(swarm.id);
        {
            std::lock_guard<std::mutex> lock(set->swarm->mutex());
            set->stream = std::make_unique<SwarmMetrics>(*set->swarm, sample_dt);
        }
        set->frame_time = sample_dt;
        out->id = metric_sets().add(set);
    });
}

swcl_status swcl_metrics_sample(swcl_metrics metrics) {
    return guarded(__func__, [&] {
        const auto set = metric_sets().get(metrics.id);
        if (!set->stream) fail(Status::InvalidArgument, "these metrics come from tracks or frames, not a swarm (swcl_metrics_attach)");
        std::lock_guard<std::mutex> lock(set->swarm->mutex());
        set->stream->sample();
    });
}

swcl_status swcl_metrics_world(swcl_metrics metrics, uint32_t world, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        const auto set = metric_sets().get(metrics.id);
        if (!set->stream)
            fail(Status::InvalidArgument, "these metrics come from tracks or frames, not a swarm (swcl_metrics_attach)");
        auto one = std::make_shared<MetricSet>();
        {
            std::lock_guard<std::mutex> lock(set->swarm->mutex());
            one->taken = set->stream->result(world);
        }
        one->frame_time = set->frame_time;
        out->id = metric_sets().add(one);
    });
}

swcl_status swcl_metrics_merge(const swcl_metrics* parts, size_t count, swcl_metrics* out) {
    return guarded(__func__, [&] {
        check_out(out, "out");
        require(parts != nullptr && count > 0, "parts: at least one metrics handle (parts NULL or count 0)");
        std::vector<std::shared_ptr<MetricSet>> sets;
        sets.reserve(count);
        for (size_t i = 0; i < count; ++i) sets.push_back(metric_sets().get(parts[i].id));
        const double ft = sets[0]->frame_time;
        for (size_t i = 1; i < count; ++i)
            if (!(std::fabs(sets[i]->frame_time - ft) <= 1e-9 * std::fabs(ft)))
                fail(Status::InvalidArgument, "parts[" + std::to_string(i) + "] has frame time " +
                                                  std::to_string(sets[i]->frame_time) + " s, parts[0] " +
                                                  std::to_string(ft) + " s: pool metrics on one clock");
        auto set = std::make_shared<MetricSet>();
        set->frame_time = ft;
        bool exact = true;
        for (const auto& s : sets) exact = exact && s->samples.has_value();
        if (exact) {
            MetricSamples all;
            all.frame_time = ft;
            for (size_t m = 0; m < kMetricCount; ++m) {
                size_t n = 0;
                for (const auto& s : sets) n += s->samples->values[m].size();
                all.values[m].reserve(n);
                for (const auto& s : sets)
                    all.values[m].insert(all.values[m].end(), s->samples->values[m].begin(), s->samples->values[m].end());
            }
            set->samples = std::move(all);
        } else {
            MetricAccumulator sum;
            for (const auto& s : sets) sum.merge(s->accumulated());  // refuses metrics of several worlds
            set->taken = std::move(sum);
        }
        out->id = metric_sets().add(set);
    });
}

swcl_status swcl_metrics_destroy(swcl_metrics metrics) {
    return guarded(__func__, [&] { metric_sets().remove(metrics.id); });
}

swcl_status swcl_metrics_frame_time(swcl_metrics metrics, double* out_seconds) {
    return guarded(__func__, [&] {
        check_out(out_seconds, "out_seconds");
        *out_seconds = metric_sets().get(metrics.id)->frame_time;
    });
}

swcl_status swcl_metrics_get_info(swcl_metrics metrics, swcl_metric metric, swcl_metric_info* out) {
    return guarded(__func__, [&] {
        check_struct_size(out, offsetof(swcl_metric_info, median), "out");  // the first version's size
        const auto set = metric_sets().get(metrics.id);
        const Moments m = set->moments(metric_from(metric));
        out->count = m.count;
        out->mean = m.mean;
        out->sigma = m.sigma;
        if (out->struct_size >= offsetof(swcl_metric_info, mad) + sizeof(out->mad)) {
            const auto [median, mad] = set->median_mad(metric_from(metric));
            out->median = median;
            out->mad = mad;
        }
    });
}

const char* swcl_metric_unit(swcl_metric metric) {
    const std::optional<Metric> m = metric_if_valid(metric);
    return m ? metric_info(*m).unit : nullptr;
}

swcl_status swcl_metrics_wasserstein(swcl_metrics real, swcl_metrics sim, swcl_metric metric, double* out_distance) {
    return guarded(__func__, [&] {
        require(out_distance != nullptr, "out_distance is NULL");
        const Metric m = metric_from(metric);
        const auto r = metric_sets().get(real.id);
        const auto s = metric_sets().get(sim.id);
        for (const auto& [set, side] : {std::pair{r.get(), "real"}, std::pair{s.get(), "sim"}})
            if (set->count(m) == 0)
                fail(Status::InvalidArgument,
                     std::string(metric_name(m)) + " has no samples in " + side + " (wasserstein distance)");
        for (const auto* set : {r.get(), s.get()})
            if (set->samples)
                for (double x : (*set->samples)[m])
                    if (!std::isfinite(x))
                        fail(Status::InvalidArgument, std::string("wasserstein: a sample of ") + metric_name(m) +
                                                          " is not finite");
        if (r->samples && s->samples) {  // both exact
            *out_distance = wasserstein1((*r->samples)[m], (*s->samples)[m]);
            return;
        }
        *out_distance = r->accumulated().wasserstein1(m, s->accumulated());
    });
}

swcl_pdf_options swcl_pdf_options_default(void) {
    swcl_pdf_options o;
    std::memset(&o, 0, sizeof(o));
    const PdfOptions p;
    o.struct_size = sizeof(o);
    o.bins = p.bins;
    o.half_width = p.half_width;
    return o;
}

swcl_status swcl_metrics_pdf(swcl_metrics metrics, swcl_metric metric, const swcl_pdf_options* options, double* out,
                             size_t count) {
    return guarded(__func__, [&] {
        const PdfOptions p = pdf_options_from(options);
        require(out != nullptr, "out is NULL");
        require(count == p.bins, "count must equal options->bins (" + std::to_string(p.bins) + ")");
        const auto set = metric_sets().get(metrics.id);
        const auto q = set->pdf(metric_from(metric), p);
        std::memcpy(out, q.data(), q.size() * sizeof(double));
    });
}

swcl_status swcl_metrics_distances(swcl_metrics real, swcl_metrics sim, const swcl_pdf_options* options, double* out,
                                   size_t count) {
    return guarded(__func__, [&] {
        const PdfOptions p = pdf_options_from(options);
        require(out != nullptr, "out is NULL");
        require(count == kMetricCount, "count must be SWCL_METRIC_COUNT (7)");
        const auto r = metric_sets().get(real.id);
        const auto s = metric_sets().get(sim.id);
        if (r->samples && s->samples) {  // both exact: the samples' own distances
            const auto e = metric_distances(*r->samples, *s->samples, p);
            std::memcpy(out, e.data(), sizeof(e));
            return;
        }
        // Eq. 2 per metric; a metric with no samples on a side gets the
        // largest distance, as metric_distances does.
        const double worst = 2.0 * p.bins / (2.0 * p.half_width);
        for (size_t k = 0; k < kMetricCount; ++k) {
            const Metric m = Metric(k);
            out[k] = r->count(m) == 0 || s->count(m) == 0 ? worst : pdf_l1(r->pdf(m, p), s->pdf(m, p));
        }
    });
}

swcl_score_weights swcl_score_weights_default(void) {
    swcl_score_weights w;
    std::memset(&w, 0, sizeof(w));
    const ScoreWeights d;
    w.struct_size = sizeof(w);
    for (size_t k = 0; k < kMetricCount; ++k) w.w[k] = d.w[k], w.p1[k] = d.p1[k], w.p2[k] = d.p2[k];
    return w;
}

swcl_status swcl_score(const double* distances, size_t count, const swcl_score_weights* weights, double* out_score) {
    return guarded(__func__, [&] {
        require(distances != nullptr, "distances is NULL");
        require(count == kMetricCount, "count must be SWCL_METRIC_COUNT (7)");
        check_out(out_score, "out_score");
        ScoreWeights w;
        if (weights) {
            check_struct_size(weights, sizeof(swcl_score_weights), "weights");
            for (size_t k = 0; k < kMetricCount; ++k) {
                require(std::isfinite(weights->w[k]) && std::isfinite(weights->p1[k]),
                        "weights: every w and p1 must be finite");
                w.w[k] = weights->w[k], w.p1[k] = weights->p1[k], w.p2[k] = weights->p2[k];
            }
        }
        std::array<double, kMetricCount> e;
        for (size_t k = 0; k < kMetricCount; ++k) {
            require(std::isfinite(distances[k]), "distances: every value must be finite");
            e[k] = distances[k];
        }
        *out_score = score(e, w);
    });
}

swcl_status swcl_entropy_weights(const double* x, size_t models, size_t terms, double* out_w, double* out_p1,
                                 double* out_p2) {
    return guarded(__func__, [&] {
        require(x != nullptr, "x is NULL");
        check_out(out_w, "out_w");
        require(models >= 2 && terms >= 1 && terms <= (size_t(1) << 20) && models <= (size_t(1) << 20),
                "expected 2..2^20 models and 1..2^20 terms");
        const auto r = entropy_weights(std::vector<double>(x, x + models * terms), models, terms);
        std::memcpy(out_w, r.w.data(), terms * sizeof(double));
        if (out_p1) std::memcpy(out_p1, r.p1.data(), terms * sizeof(double));
        if (out_p2) std::memcpy(out_p2, r.p2.data(), terms * sizeof(double));
    });
}

}  // extern "C"

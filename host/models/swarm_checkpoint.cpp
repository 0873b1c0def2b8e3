#include "models/swarm_checkpoint.hpp"

#include <algorithm>
#include <utility>

namespace swarmcl {
namespace {

void write_float4s(ByteWriter& w, const std::vector<cl_float4>& v) {
    for (const cl_float4& x : v)
        for (int a = 0; a < 4; ++a) w.f32(x.s[a]);
}

std::vector<cl_float4> read_float4s(ByteReader& r, uint64_t n) {
    std::vector<cl_float4> v(static_cast<size_t>(n));
    for (cl_float4& x : v)
        for (int a = 0; a < 4; ++a) x.s[a] = r.f32();
    return v;
}

CheckpointSection section(const char (&tag)[5], uint32_t version, std::string bytes) {
    CheckpointSection s;
    s.tag = section_tag(tag);
    s.version = version;
    s.bytes = std::move(bytes);
    return s;
}

}  // namespace

std::string swarm_checkpoint_bytes(Swarm& swarm) {
    ByteWriter model, model_state;
    if (Behavior* b = swarm.behavior()) {
        b->save_checkpoint(swarm, model, model_state);
    } else {
        write_ballistic_descriptor(model);
    }
    const SwarmState st = swarm.export_state();
    const SwarmConfig& c = swarm.config();

    ByteWriter cfg;
    cfg.u32(c.capacity);
    cfg.u32(c.agent_count);
    cfg.u64(c.seed);
    for (float v : c.domain_min) cfg.f32(v);
    for (float v : c.domain_max) cfg.f32(v);
    cfg.f32(c.interaction_radius);
    cfg.f32(c.dt);

    ByteWriter agents;
    agents.u64(st.steps);
    agents.u64(st.ids.size());
    write_float4s(agents, st.positions);
    write_float4s(agents, st.velocities);
    for (cl_uint id : st.ids) agents.u32(id);

    ByteWriter stats;
    stats.u32(st.stats.mde_moved_last);
    stats.u64(st.stats.mde_moved_total);
    stats.u64(st.stats.steps);

    std::vector<CheckpointSection> sections;
    if (swarm.worlds() > 1) {
        // Worlds: their seeds, statistics and the parameters that differ
        // (older readers refuse the unknown section, as they should).
        ByteWriter w;
        w.u32(swarm.worlds());
        for (uint32_t k = 0; k < swarm.worlds(); ++k) w.u64(swarm.world_seed(k));
        for (const StepStats& s : st.world_stats) {
            w.u32(s.mde_moved_last);
            w.u64(s.mde_moved_total);
        }
        const Behavior* b = swarm.behavior();
        const std::vector<std::string> keys = b ? b->varied_world_params() : std::vector<std::string>{};
        w.u32(uint32_t(keys.size()));
        for (const std::string& key : keys) {
            const std::vector<double> v = b->world_param(key);
            w.string(key);
            w.u64(v.size());
            for (double x : v) w.f64(x);
        }
        // Version 2 when the worlds have domains of their own (version 1
        // readers can still read the others).
        const bool domains = !swarm.same_domain_in_every_world();
        if (domains)
            for (uint32_t k = 0; k < swarm.worlds(); ++k) {
                for (float v : swarm.world_domain(k).min) w.f32(v);
                for (float v : swarm.world_domain(k).max) w.f32(v);
            }
        sections.push_back(section("WRLD", domains ? 2 : 1, w.take()));
    }
    sections.push_back(section("SWRM", kSwarmSectionVersion, cfg.take()));
    sections.push_back(section("AGNT", kAgentSectionVersion, agents.take()));
    sections.push_back(section("STAT", kStatsSectionVersion, stats.take()));
    sections.push_back(section("MODL", kModelSectionVersion, model.take()));
    sections.push_back(section("MDST", kStateSectionVersion, model_state.take()));
    return checkpoint_to_bytes(sections);
}

SwarmCheckpoint decode_swarm_checkpoint(const std::string& bytes, bool verify_checksum) {
    const std::vector<CheckpointSection> sections = parse_checkpoint(bytes, verify_checksum);
    for (const CheckpointSection& s : sections) {
        bool known = false;
        for (const char* t : {"SWRM", "AGNT", "STAT", "MODL", "MDST", "WRLD"}) known |= s.tag_name() == t;
        // Every section holds state a step depends on: one this reader does
        // not know cannot be skipped.
        if (!known) fail(Status::Parse, "checkpoint: unknown section " + s.tag_name() + " (written by a newer swarmcl?)");
    }
    SwarmCheckpoint cp;
    {
        const CheckpointSection& s = find_section(sections, "SWRM", kSwarmSectionVersion);
        ByteReader r(s.bytes, "section SWRM (swarm)");
        SwarmConfig& c = cp.config;
        c.capacity = r.u32();
        c.agent_count = r.u32();
        c.seed = r.u64();
        for (float& v : c.domain_min) v = r.f32();
        for (float& v : c.domain_max) v = r.f32();
        c.interaction_radius = r.f32();
        c.dt = r.f32();
        r.expect_end();
    }
    const bool has_worlds = std::any_of(sections.begin(), sections.end(),
                                        [](const CheckpointSection& s) { return s.tag_name() == "WRLD"; });
    std::vector<StepStats> world_stats;
    if (has_worlds) {
        const CheckpointSection& s = find_section(sections, "WRLD", kWorldsSectionVersion);
        ByteReader r(s.bytes, "section WRLD (worlds)");
        SwarmConfig& c = cp.config;
        c.worlds = r.u32();
        if (c.worlds < 2) r.bad("a swarm of worlds holds 2 or more, not " + std::to_string(c.worlds));
        if (uint64_t(c.worlds) * (8 + 4 + 8) > r.remaining())  // a seed and the counters per world
            r.bad(std::to_string(c.worlds) + " worlds do not fit in the " + std::to_string(r.remaining()) + " bytes left");
        if (uint64_t(c.worlds) * c.capacity > (uint64_t(1) << 31)) r.bad("too many worlds for the capacity");
        c.world_seeds.resize(c.worlds);
        for (uint64_t& seed : c.world_seeds) seed = r.u64();
        world_stats.resize(c.worlds);
        for (StepStats& w : world_stats) {
            w.mde_moved_last = r.u32();
            w.mde_moved_total = r.u64();
        }
        const uint32_t keys = r.u32();
        for (uint32_t i = 0; i < keys; ++i) {
            std::string key = r.string();
            const uint64_t count = r.count(8);
            std::vector<double> v(static_cast<size_t>(count));
            for (double& x : v) x = r.f64();
            cp.world_params.emplace_back(std::move(key), std::move(v));
        }
        if (s.version >= 2) {
            if (uint64_t(c.worlds) * 24 > r.remaining())
                r.bad(std::to_string(c.worlds) + " world domains do not fit in the " + std::to_string(r.remaining()) +
                      " bytes left");
            c.world_domains.resize(c.worlds);
            for (Domain& d : c.world_domains) {
                for (float& v : d.min) v = r.f32();
                for (float& v : d.max) v = r.f32();
            }
        }
        r.expect_end();
    }
    {
        const CheckpointSection& s = find_section(sections, "AGNT", kAgentSectionVersion);
        ByteReader r(s.bytes, "section AGNT (agent state)");
        cp.state.steps = r.u64();
        const uint64_t n = r.count(2 * 16 + 4);  // a position, a velocity and an id per agent
        if (n > uint64_t(cp.config.capacity) * cp.config.worlds)
            r.bad(std::to_string(n) + " agents exceed the capacity " + std::to_string(cp.config.capacity) +
                  (cp.config.worlds > 1 ? " x " + std::to_string(cp.config.worlds) + " worlds" : std::string()));
        cp.state.positions = read_float4s(r, n);
        cp.state.velocities = read_float4s(r, n);
        cp.state.ids.resize(size_t(n));
        for (cl_uint& id : cp.state.ids) id = r.u32();
        r.expect_end();
    }
    {
        const CheckpointSection& s = find_section(sections, "STAT", kStatsSectionVersion);
        ByteReader r(s.bytes, "section STAT (step statistics)");
        cp.state.stats.agents = uint32_t(cp.state.ids.size());
        cp.state.stats.mde_moved_last = r.u32();
        cp.state.stats.mde_moved_total = r.u64();
        cp.state.stats.steps = r.u64();
        r.expect_end();
        for (StepStats& w : world_stats) {
            w.agents = cp.config.worlds ? uint32_t(cp.state.ids.size() / cp.config.worlds) : 0;
            w.steps = cp.state.stats.steps;
        }
        cp.state.world_stats = std::move(world_stats);
    }
    {
        const CheckpointSection& s = find_section(sections, "MODL", kModelSectionVersion);
        ByteReader r(s.bytes, "section MODL (model)");
        cp.model = read_model_descriptor(r, s.version);
    }
    cp.model_state = find_section(sections, "MDST", kStateSectionVersion).bytes;
    return cp;
}

std::shared_ptr<Swarm> swarm_from_checkpoint(std::shared_ptr<Context> ctx, const SwarmCheckpoint& cp) {
    // Values that parse but do not make a swarm or model are a bad file too.
    try {
        auto swarm = std::make_shared<Swarm>(std::move(ctx), cp.config);
        swarm->import_state(cp.state);
        std::shared_ptr<Behavior> behavior = behavior_from_checkpoint(*swarm, cp.model);
        ByteReader r(cp.model_state, "section MDST (model state)");
        if (behavior) {
            behavior->restore_checkpoint(*swarm, r);
            for (const auto& [key, values] : cp.world_params)
                behavior->set_world_param(*swarm, key, values.data(), values.size());
        } else {
            r.expect_end();
            if (!cp.world_params.empty()) fail(Status::Parse, "checkpoint: world parameters without a model");
        }
        swarm->set_behavior(std::move(behavior));
        // Which set_behavior zeroed.
        if (cp.state.world_stats.empty()) {
            swarm->restore_step_stats(cp.state.stats);
        } else {
            swarm->restore_world_step_stats(cp.state.world_stats);
        }
        return swarm;
    } catch (const Error& e) {
        if (e.status() == Status::InvalidArgument) fail(Status::Parse, std::string("checkpoint: ") + e.what());
        throw;
    }
}

void save_swarm(Swarm& swarm, const std::string& path) { write_checkpoint_file(path, swarm_checkpoint_bytes(swarm)); }

std::shared_ptr<Swarm> load_swarm(std::shared_ptr<Context> ctx, const std::string& path) {
    return swarm_from_checkpoint(std::move(ctx), decode_swarm_checkpoint(read_checkpoint_file(path)));
}

}  // namespace swarmcl

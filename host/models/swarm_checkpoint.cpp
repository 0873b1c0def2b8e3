#include "models/swarm_checkpoint.hpp"

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
        for (const char* t : {"SWRM", "AGNT", "STAT", "MODL", "MDST"}) known |= s.tag_name() == t;
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
    {
        const CheckpointSection& s = find_section(sections, "AGNT", kAgentSectionVersion);
        ByteReader r(s.bytes, "section AGNT (agent state)");
        cp.state.steps = r.u64();
        const uint64_t n = r.count(2 * 16 + 4);  // a position, a velocity and an id per agent
        if (n > cp.config.capacity)
            r.bad(std::to_string(n) + " agents exceed the capacity " + std::to_string(cp.config.capacity));
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
        } else {
            r.expect_end();
        }
        swarm->set_behavior(std::move(behavior));
        swarm->restore_step_stats(cp.state.stats);  // which set_behavior zeroed
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

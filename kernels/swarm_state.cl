// Moving agent attributes between the caller's packed xyz arrays (agent-id
// order) and the device's float4 arrays (cell order), and the plain
// integration step.

// dst[3 id + k] = src[slot_of[id]].k
__kernel void gather_xyz(__global const float4* src, __global const uint* slot_of, uint n,
                         __global float* dst) {
    const uint id = get_global_id(0);
    if (id >= n) return;
    const float4 v = src[slot_of[id]];
    dst[3 * id + 0] = v.x;
    dst[3 * id + 1] = v.y;
    dst[3 * id + 2] = v.z;
}

// The place in id order (over all worlds) of slot s holding agent `id`:
// world s / world_agents counts its ids from s / world_agents * world_agents.
static inline uint swcl_id_place(uint s, uint world_agents, uint id) { return s / world_agents * world_agents + id; }

// One frame of swcl_swarm_step_frames: dst[offset + 3 id + k] = src[s].k for
// every slot s, id = its agent's place in id order (swcl_id_place).  A
// scatter by ids rather than gather_xyz's gather through slot_of: one launch
// a frame instead of slot_of's, gather_xyz's and a copy into the frames
// buffer.
__kernel void frame_xyz(__global const float4* src, __global const uint* ids, uint n, uint world_agents,
                        __global float* dst, ulong offset) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const float4 v = src[s];
    __global float* o = dst + offset + 3 * (size_t)swcl_id_place(s, world_agents, ids[s]);
    o[0] = v.x;
    o[1] = v.y;
    o[2] = v.z;
}

// dst[slot_of[id]] = (src[3 id], src[3 id + 1], src[3 id + 2], 0)
__kernel void scatter_xyz(__global const float* src, __global const uint* slot_of, uint n,
                          __global float4* dst) {
    const uint id = get_global_id(0);
    if (id >= n) return;
    dst[slot_of[id]] = (float4)(src[3 * id], src[3 * id + 1], src[3 * id + 2], 0.0f);
}

// Agent id order: slot s holds agent s.  With worlds of world_agents agents
// each (lib/grid_common.cl) ids count from 0 in every world: slot s holds
// agent s mod world_agents of world s / world_agents.
__kernel void identity_layout(uint n, uint world_agents, __global uint* ids, __global uint* slot_of) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    ids[s] = s % world_agents;
    slot_of[s] = s;
}

// The inverse of ids: slot_of[w world_agents + ids[s]] = s for the slots s of
// world w (built on demand, before reads and writes in id order).  The
// worlds' slots stay apart in every order (their cells are).
__kernel void slot_of_from_ids(__global const uint* ids, uint n, uint world_agents, __global uint* slot_of) {
    const uint s = get_global_id(0);
    if (s < n) slot_of[swcl_id_place(s, world_agents, ids[s])] = s;
}

// Ballistic step (no behaviour model): p += v dt.
__kernel void integrate_ballistic(__global float4* pos, __global const float4* vel, uint n, float dt) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    pos[s] = pos[s] + vel[s] * dt;
}

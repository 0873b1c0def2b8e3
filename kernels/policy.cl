// The policy model (issue 15 item 7; paper drl-swarm-animation-rule-based-
// action-generator, §III-IV): a trained actor MLP drives a swarm that follows
// a leader.  Each step: the observations of Eq. 11-13 over the swarm's
// neighbour grid with the environment's code (lib/rl_common.cl), the MLP
// batched over agents (policy_mlp), Eq. 2's kinematics (policy_apply).  The
// leader is stepped by rl_env.cl's rl_leader_step.  docs/rl-swarm.md,
// "Policy model".
//
// Swarm state: pos[s] = (x, y, z, -), vel[s] = (u q, -): the velocity, so
// reads and recordings are the velocity.  Speed u = |vel.xyz|, heading
// q = vel.xyz / u; an agent at rest (u = 0) heads towards the leader (ours:
// the swarm has no other place to keep a heading).
#pragma OPENCL FP_CONTRACT OFF
// -DPM_W (1, 8 or 16; the host's) is the lane width of the MLP and of the
// observations' per-width body: SWCL_W (lib/lanes.cl) is PM_W.
#if defined(PM_W) && PM_W > 1 && !defined(NOISE_WIDTH)
#define NOISE_WIDTH PM_W
#endif
#include "lib/lanes.cl"
#include "lib/grid_common.cl"
#include "lib/rl_common.cl"

// (q, u) of an agent at p with velocity v, the leader at lp.
SWCL_INLINE float4 policy_qu(float4 v, float3 p, float3 lp) {
    const float u = length(v.xyz);
    if (u > 0.0f) return (float4)(v.xyz / u, u);
    const float3 to = lp - p;
    const float l = length(to);
    return l > 0.0f ? (float4)(to / l, 0.0f) : (float4)(1.0f, 0.0f, 0.0f, 0.0f);
}

// Every agent's (q, u) for policy_observe, once a step: the observation
// walk meets each agent as a candidate of about 40 work-items (width 8), and
// policy_qu's length and division cost a tenth of the walk there.
__kernel void policy_headings(__global const float4* pos, __global const float4* vel, uint n,
                              __global const float4* lst, __global float4* qu) {
    const uint s = get_global_id(0);
    if (s >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1): its agents and leader state.
    const size_t world_base = get_global_id(1) * n;
    pos += world_base;
    vel += world_base;
    qu += world_base;
    lst += 2 * get_global_id(1);
#endif
    qu[s] = policy_qu(vel[s], pos[s].xyz, lst[0].xyz);
}

// ---- observations (Eq. 11-13) by slot, one body per width -----------------------
#define SWCL_BW 1
#include "wide/policy_observe.inc.cl"
#undef SWCL_BW

// ---- the MLP (§IV-A, Fig. 6), batched over agents ---------------------------
// PM_W agents per work-item (1, 8 or 16 lanes: on CPU devices the lanes are
// the SIMD vector; weights are read once per PM_W agents).  Work-item t of a
// launch handles tile first_tile + t, agents tile * PM_W + lane.
// Activations live in `scratch`, per work-item 2 * max_width * PM_W floats,
// feature-major ([feature][lane]) so a feature of all lanes is one vector.
// params: every layer's weight (out x in, row-major) then bias, and the
// normalisation; layers[5 l ..] = {in, out, activation, weight offset, bias
// offset}; activation 0 relu, 1 linear, 2 tanh.  acc = fma(w, x, acc) in
// input order from the bias, as the C++ reference does.
#ifndef PM_W
#define PM_W 1
#endif
#if PM_W == 16
typedef float16 pm_f;
#define PM_LOAD(i, p) vload16(i, p)
#define PM_STORE(v, i, p) vstore16(v, i, p)
#elif PM_W == 8
typedef float8 pm_f;
#define PM_LOAD(i, p) vload8(i, p)
#define PM_STORE(v, i, p) vstore8(v, i, p)
#elif PM_W == 1
typedef float pm_f;
#define PM_LOAD(i, p) ((p)[i])
#define PM_STORE(v, i, p) ((p)[i] = (v))
#else
#error "PM_W must be 1, 8 or 16"
#endif

SWCL_INLINE pm_f pm_activate(pm_f x, uint act) {
    if (act == 0u) return fmax(x, (pm_f)(0.0f));
    if (act == 2u) return tanh(x);
    return x;
}

__kernel void policy_mlp(__global const float* obs, uint n, uint obs_dim, uint first_tile,
                         __global const float* params, __global const uint* layers, uint nlayers, int norm,
                         uint mean_off, uint std_off, float4 scale, uint max_width, __global float* scratch,
                         __global float* actions) {
    const uint t = get_global_id(0);
    const uint tile = first_tile + t;
    const uint a0 = tile * PM_W;
    if (a0 >= n) return;
    __global float* xa = scratch + (size_t)t * 2u * max_width * PM_W;
    __global float* xb = xa + (size_t)max_width * PM_W;
    // Input: obs gathered lane by lane (agents past n read agent n-1).
    for (uint i = 0; i < obs_dim; ++i) {
        for (uint l = 0; l < PM_W; ++l) {
            const uint a = min(a0 + l, n - 1u);
            float x = obs[(size_t)a * obs_dim + i];
            if (norm) x = (x - params[mean_off + i]) / params[std_off + i];
            xa[i * PM_W + l] = x;
        }
    }
    for (uint L = 0; L < nlayers; ++L) {
        const uint in = layers[5 * L], out = layers[5 * L + 1], act = layers[5 * L + 2];
        __global const float* W = params + layers[5 * L + 3];
        __global const float* B = params + layers[5 * L + 4];
        uint o = 0;
        // Eight outputs per pass over the inputs: each input vector loaded
        // once for eight FMAs (each output's chain is the same, in input
        // order from its bias, so the results are too).
        for (; o + 8 <= out; o += 8) {
            pm_f c0 = (pm_f)(B[o]), c1 = (pm_f)(B[o + 1]), c2 = (pm_f)(B[o + 2]), c3 = (pm_f)(B[o + 3]);
            pm_f c4 = (pm_f)(B[o + 4]), c5 = (pm_f)(B[o + 5]), c6 = (pm_f)(B[o + 6]), c7 = (pm_f)(B[o + 7]);
            __global const float* w0 = W + (size_t)o * in;
            for (uint i = 0; i < in; ++i) {
                const pm_f x = PM_LOAD(i, xa);
                c0 = fma((pm_f)(w0[i]), x, c0);
                c1 = fma((pm_f)(w0[in + i]), x, c1);
                c2 = fma((pm_f)(w0[2 * in + i]), x, c2);
                c3 = fma((pm_f)(w0[3 * in + i]), x, c3);
                c4 = fma((pm_f)(w0[4 * in + i]), x, c4);
                c5 = fma((pm_f)(w0[5 * in + i]), x, c5);
                c6 = fma((pm_f)(w0[6 * in + i]), x, c6);
                c7 = fma((pm_f)(w0[7 * in + i]), x, c7);
            }
            PM_STORE(pm_activate(c0, act), o, xb);
            PM_STORE(pm_activate(c1, act), o + 1, xb);
            PM_STORE(pm_activate(c2, act), o + 2, xb);
            PM_STORE(pm_activate(c3, act), o + 3, xb);
            PM_STORE(pm_activate(c4, act), o + 4, xb);
            PM_STORE(pm_activate(c5, act), o + 5, xb);
            PM_STORE(pm_activate(c6, act), o + 6, xb);
            PM_STORE(pm_activate(c7, act), o + 7, xb);
        }
        for (; o < out; ++o) {
            pm_f c = (pm_f)(B[o]);
            __global const float* w0 = W + (size_t)o * in;
            for (uint i = 0; i < in; ++i) c = fma((pm_f)(w0[i]), PM_LOAD(i, xa), c);
            PM_STORE(pm_activate(c, act), o, xb);
        }
        __global float* tmp = xa;
        xa = xb;
        xb = tmp;
    }
    // Output: 4 actions per agent, times the action scale.
    for (uint l = 0; l < PM_W; ++l) {
        const uint a = a0 + l;
        if (a >= n) break;
        actions[4 * (size_t)a] = xa[l] * scale.x;
        actions[4 * (size_t)a + 1] = xa[PM_W + l] * scale.y;
        actions[4 * (size_t)a + 2] = xa[2 * PM_W + l] * scale.z;
        actions[4 * (size_t)a + 3] = xa[3 * PM_W + l] * scale.w;
    }
}

// ---- the MLP as tiled matrix products (the GPU profile) ---------------------
// One launch per layer: Y[o][a] = act(B[o] + sum_i W[o][i] X[i][a]).  One
// agent per work-item with its activations in a private row of global
// memory (policy_mlp at PM_W = 1) reads nothing coalesced and reused no
// weight: 43 GFLOP/s on an H100.  Here a 16 x 16 work-group computes 64
// outputs x 64 agents, each work-item a 4 x 4 block (outputs ty + 16 r,
// agents tx + 16 c: neighbouring work-items store neighbouring agents),
// from k-tiles of 16 inputs of W and X staged in local memory.  Each
// output's accumulator is its own fma chain from the bias in input order,
// stopping at `in` (padded k entries are never added), so the results are
// bitwise policy_mlp's.  X and Y are addressed as x[(x_first + a) *
// x_agent_stride + i * x_feature_stride]: the first layer reads `obs`
// agent-major (normalised when norm is set, as policy_mlp), the hidden
// layers a feature-major buffer (agent stride 1: coalesced), the last layer
// writes actions[4 a + o] times the action scale (scaled set).
#define PMT_TILE 64u
#define PMT_K 16u

SWCL_INLINE float pmt_activate(float x, uint act) {
    if (act == 0u) return fmax(x, 0.0f);
    if (act == 2u) return tanh(x);
    return x;
}

// One k step of the 4 x 4 block: acc[r][c] = fma(w[r], x[c], acc[r][c]).
#define PMT_STEP(kk)                                                                   \
    do {                                                                               \
        float w_[4], x_[4];                                                            \
        for (uint r_ = 0; r_ < 4u; ++r_) w_[r_] = ws[kk][ty + 16u * r_];               \
        for (uint c_ = 0; c_ < 4u; ++c_) x_[c_] = xs[kk][tx + 16u * c_];               \
        for (uint r_ = 0; r_ < 4u; ++r_)                                               \
            for (uint c_ = 0; c_ < 4u; ++c_) acc[r_][c_] = fma(w_[r_], x_[c_], acc[r_][c_]); \
    } while (0)

// Launched as 16 x 16 work-groups (policy_model.cpp checks the kernel's
// CL_KERNEL_WORK_GROUP_SIZE allows 256).
__kernel void policy_mlp_tiled(
    __global const float* x, uint x_first, uint x_agent_stride, uint x_feature_stride, uint n,
    __global const float* params, uint in, uint out, uint act, uint w_off, uint b_off, int norm, uint mean_off,
    uint std_off, __global float* y, uint y_first, uint y_agent_stride, uint y_feature_stride, int scaled,
    float4 scale) {
    const uint a0 = get_group_id(0) * PMT_TILE, o0 = get_group_id(1) * PMT_TILE;
    // A whole group past the count (never with the host's exact launch);
    // no single work-item returns: the barriers below need all 256.
    if (a0 >= n || o0 >= out) return;
    const uint tx = get_local_id(0), ty = get_local_id(1), lid = ty * 16u + tx;
    // ws[k][o - o0] (a column of padding against bank conflicts on the
    // transposing store), xs[k][a - a0].
    __local float ws[PMT_K][PMT_TILE + 1u];
    __local float xs[PMT_K][PMT_TILE];
    float acc[4][4];
    for (uint r = 0; r < 4u; ++r) {
        const uint o = o0 + ty + 16u * r;
        const float b = o < out ? params[b_off + o] : 0.0f;
        for (uint c = 0; c < 4u; ++c) acc[r][c] = b;
    }
    for (uint k0 = 0; k0 < in; k0 += PMT_K) {
        // 16 x 64 of W and of X, four elements per work-item; zeros outside
        // the layer (they feed only outputs and agents that are not stored).
        // W: neighbouring work-items read neighbouring inputs of a row.
        for (uint j = 0; j < 4u; ++j) {
            const uint e = lid + 256u * j, kk = e % PMT_K, ol = e / PMT_K;
            const uint o = o0 + ol, i = k0 + kk;
            ws[kk][ol] = (o < out && i < in) ? params[w_off + (size_t)o * in + i] : 0.0f;
        }
        if (x_feature_stride != 1u) {
            // Feature-major (the host's hidden buffers, a stride of at least
            // 64): neighbouring work-items read neighbouring agents.
            for (uint j = 0; j < 4u; ++j) {
                const uint e = lid + 256u * j, al = e % PMT_TILE, kk = e / PMT_TILE;
                const uint a = a0 + al, i = k0 + kk;
                xs[kk][al] = (a < n && i < in) ? x[(size_t)(x_first + a) * x_agent_stride + (size_t)i * x_feature_stride] : 0.0f;
            }
        } else {
            // Agent-major (obs, feature stride 1): neighbouring work-items
            // read neighbouring inputs.
            for (uint j = 0; j < 4u; ++j) {
                const uint e = lid + 256u * j, kk = e % PMT_K, al = e / PMT_K;
                const uint a = a0 + al, i = k0 + kk;
                float v = 0.0f;
                if (a < n && i < in) {
                    v = x[(size_t)(x_first + a) * x_agent_stride + (size_t)i * x_feature_stride];
                    if (norm) v = (v - params[mean_off + i]) / params[std_off + i];
                }
                xs[kk][al] = v;
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
        // Only the layer's real inputs join a chain.
        const uint kn = in - k0 < PMT_K ? in - k0 : PMT_K;
        if (kn == PMT_K) {
            for (uint kk = 0; kk < PMT_K; ++kk) PMT_STEP(kk);
        } else {
            for (uint kk = 0; kk < kn; ++kk) PMT_STEP(kk);
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    for (uint r = 0; r < 4u; ++r) {
        const uint o = o0 + ty + 16u * r;
        if (o >= out) continue;
        const float s = o == 0u ? scale.x : o == 1u ? scale.y : o == 2u ? scale.z : scale.w;
        for (uint c = 0; c < 4u; ++c) {
            const uint a = a0 + tx + 16u * c;
            if (a >= n) continue;
            float v = pmt_activate(acc[r][c], act);
            if (scaled) v = v * s;
            y[(size_t)(y_first + a) * y_agent_stride + (size_t)o * y_feature_stride] = v;
        }
    }
}

// ---- observations, PM_W agents per work-item (CPU devices) --------------------
// policy_observe_w: the same body in PM_W lanes (wide/policy_observe.inc.cl).
#if PM_W > 1
#define SWCL_BW SWCL_W
#include "wide/policy_observe.inc.cl"
#undef SWCL_BW
#endif

// ---- Eq. 2: the actions applied (rl_agents_step on the swarm's layout) -------
__kernel void policy_apply(__global float4* pos, __global float4* vel, __global const float* actions, uint n,
                           __global const float4* lst_before, __global const float* params, float dt) {
    const uint s = get_global_id(0);
    if (s >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1): its agents, actions, leader state and block.
    const size_t world = get_global_id(1), world_base = world * n;
    pos += world_base;
    vel += world_base;
    actions += world_base * 4;
    lst_before += 2 * world;
    params += world * POLICY_FLOATS;
#endif
    // du_max, u_max and dq_max (degrees to radians, as the host did) from
    // the model's block.
    const float du_max = params[POLICY_DU_MAX], u_max = params[POLICY_U_MAX];
    const float dq_max = params[POLICY_DQ_MAX_DEG] * 0.017453292519943295f;
    const float3 p = pos[s].xyz;
    const float4 qu = policy_qu(vel[s], p, lst_before[0].xyz);
    const float du = clamp(actions[4 * s], -du_max, du_max);
    const float3 dq = (float3)(actions[4 * s + 1], actions[4 * s + 2], actions[4 * s + 3]);
    const float u = clamp(qu.w + du, 0.0f, u_max);
    const float3 q = rl_turn(qu.xyz, dq, dq_max);
    vel[s] = (float4)(u * q, 0.0f);
    pos[s] = (float4)(p + (u * dt) * q, 0.0f);
}

// The leader's state as policy_observe reads it: lst[2 w] = world w's
// leader position, lst[2 w + 1] = its (q, u); copied before the leader
// moves, so the followers' actions and rest headings use the state they were
// observed in.
__kernel void policy_leader_copy(__global const float4* lpos, __global const float4* lvel, __global float4* lst,
                                 uint worlds) {
    const uint w = get_global_id(0);
    if (w >= worlds) return;
    lst[2 * w] = lpos[w];
    lst[2 * w + 1] = lvel[w];
}

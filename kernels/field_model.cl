// The local behaviour of the curl-noise paper (§4 and §6, Eq. 9 without the
// global path field): each agent's velocity is the noise field at its position
// plus, outside an optional goal sphere, a pull towards the goal at speed s0
// (optionally ramped up over a falloff distance);
// then p += v dt (explicit Euler, the paper's position update).
// Built per noise configuration like noise_field.cl (NOISE_* defines).  The
// kernel body is wide/field_model_advance.inc.cl, written once for any width:
// field_model_advance is plain scalar code (PoCL vectorises it across
// agents), field_model_advance_w runs SWCL_W agents per work-item (CPU
// devices; lib/noise_field.cl, explicit-width path).
#include "lib/noise_field.cl"

#define SWCL_BW 1
#include "wide/field_model_advance.inc.cl"
#undef SWCL_BW

#ifdef NOISE_WIDE
#define SWCL_BW SWCL_W
#include "wide/field_model_advance.inc.cl"
#undef SWCL_BW
#endif

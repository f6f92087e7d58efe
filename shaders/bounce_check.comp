#version 460
// Pass 6d, after each gather: whether the bounces are done, and the next bounce's dispatch sizes.
// The gather's per-workgroup sums are added in a fixed order (deterministic). Done after
// maxGathers, or where the change still to come, estimated as the geometric tail of the last two
// changes (change · r / (1 − r), r their ratio), is at most `tolerance` of the light: the next
// gather and its pull-up then run zero workgroups.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) readonly buffer BounceSums { BounceSum sums[]; };
layout(std430, binding = 1) buffer BounceStates { BounceState state; };
layout(std430, binding = 2) readonly buffer FullArgs {
  uvec4 fullArgs[];
};  // gather, interpolation, then each pull-up level
layout(std430, binding = 3) writeonly buffer BounceArgs { uvec4 bounceArgs[]; };
layout(push_constant) uniform Push { BounceCheckPush push; };

void main() {
  if (state.done != 0u) return;
  float total = 0.0, change = 0.0;
  for (uint g = 0u; g < push.groups; ++g) total += sums[g].total, change += sums[g].change;
  const uint gathers = state.gathers + 1u;
  float remaining = 1e30;
  if (gathers >= 2u && state.change > 0.0) {
    const float r = change / state.change;
    remaining = r < 1.0 ? change * r / (1.0 - r) / max(total, 1e-30) : 1e30;
  }
  if (change == 0.0) remaining = 0.0;  // nothing changes (no light, or no bounce light)
  const bool done =
      gathers >= push.maxGathers || (gathers >= 2u && push.tolerance >= 0.0 && remaining <= push.tolerance);
  state.gathers = gathers;
  state.done = done ? 1u : 0u;
  state.change = change;
  state.total = total;
  state.remaining = remaining;
  for (uint i = 0u; i < push.dispatches; ++i) bounceArgs[i] = done ? uvec4(0u, 1u, 1u, 0u) : fullArgs[i];
}

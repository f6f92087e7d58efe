#version 460
// iv's bounces, after each gather: whether the bounces are done, and the next bounce's dispatch
// sizes. The interpolation's per-workgroup sums are added in a fixed order (deterministic). Past
// the first bounces the changes decay geometrically (the slowest mode of the transport dominates),
// so the bounces not run add about change · q / (1 − q), q the ratio of the last two changes; with
// that tail the light is estimated far more closely than by the bounces run alone (bounce_tail.comp
// adds it at every surfel). Done after maxGathers, or where that estimate has settled: it moved by
// at most `tolerance` of the light at this gather, and by at most that over q at the one before (a
// single small step may be the estimate crossing its limit). Done, the next gather and its pull-up
// run zero workgroups and the tail runs once. Also done, without the tail, where the bounces
// diverge: a change past kDivergingGrowth times the least from the second gather on (the first
// bounce's, the second gather's, may exceed the direct light's) and past kDivergingFloor of the
// light; the host says so.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 1) in;

layout(std430, binding = 0) readonly buffer BounceSums { BounceSum sums[]; };
layout(std430, binding = 1) buffer BounceStates { BounceState state; };
layout(std430, binding = 2) readonly buffer FullArgs { uvec4 fullArgs[]; };       // gather, interpolation, pull-up
layout(std430, binding = 3) writeonly buffer BounceArgs { uvec4 bounceArgs[]; };  // and the tail's last
layout(push_constant) uniform Push { BounceCheckPush push; };

const uvec4 kNoGroups = uvec4(0u, 1u, 1u, 0u);

void main() {
  if (state.done != 0u) {
    bounceArgs[push.dispatches] = kNoGroups;  // the tail ran where the bounces ended
    return;
  }
  float total = 0.0, change = 0.0;
  for (uint g = 0u; g < push.groups; ++g) total += sums[g].total, change += sums[g].change;
  const uint gathers = state.gathers + 1u;
  const bool automatic = push.tolerance >= 0.0;
  float gain = 0.0;
  if (automatic && gathers >= 2u && state.change > 0.0 && change < state.change) {
    const float q = change / state.change;
    gain = q / (1.0 - q);
  }
  const float estimate = total + change * gain, light = max(total, 1e-30);
  // The estimate's moves: known from the third gather (the second's q, direct light to the first
  // bounce, is no guide to the decay).
  const float step = gathers >= 3u && gain > 0.0 && state.gain > 0.0 ? abs(estimate - state.estimate) / light : 1e30;
  float remaining = max(step, gain > 0.0 ? state.step * gain / (1.0 + gain) : 1e30);
  if (change == 0.0) remaining = 0.0;  // nothing changes (no light, or no bounce light)
  const bool diverged = gathers >= 3u && change > kDivergingGrowth * state.least && change > kDivergingFloor * total;
  const float least = gathers == 2u ? change : min(state.least, change);
  const bool done =
      diverged || gathers >= push.maxGathers || (automatic && gathers >= 2u && remaining <= push.tolerance);
  state.gathers = gathers;
  state.done = done ? 1u : 0u;
  state.change = change;
  state.total = total;
  state.remaining = remaining;
  state.gain = gain;
  state.estimate = estimate;
  state.step = step;
  state.least = least;
  state.diverged = diverged ? 1u : 0u;
  for (uint i = 0u; i < push.dispatches; ++i) bounceArgs[i] = done ? kNoGroups : fullArgs[i];
  bounceArgs[push.dispatches] = done && gain > 0.0 ? fullArgs[1] : kNoGroups;
}

#version 460
// iv's bounces, at every surfel: irradiance E interpolated from the receivers' gathered irradiance
// with the coefficients of interpolation_weights.comp (a receiver takes its own), each turned to the
// surfel's normal by its rotation gradient (by a crease, the still senders' part its own), plus the
// depth maps' direct light (zero where the bins carry it), radiosity B = π·Le + ρ·E at its leaf.
// Reads last bounce's radiosity only for the change, writes the next (no race); keeps the
// irradiance's change for the tail (bounce_tail.comp).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 11
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(binding = 1, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 2, rg32ui) readonly uniform uimageBuffer taps;  // InterpolationTap, kInterpolationTaps a surfel
layout(binding = 3, rgba32f) readonly uniform imageBuffer gathered;
layout(binding = 4, rgba32f) readonly uniform imageBuffer albedo;
layout(binding = 5, rgba32f) readonly uniform imageBuffer emission;
layout(binding = 6, rgba32f) readonly uniform imageBuffer radiosityIn;
layout(std430, binding = 7) writeonly buffer RadiosityOut { vec4 radiosityOut[]; };
layout(std430, binding = 8) buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 13) writeonly buffer IrradianceChange { vec4 irradianceChange[]; };
layout(binding = 14, rgba32f) readonly uniform imageBuffer surfelDirect;
layout(binding = 15, rgba32f) readonly uniform imageBuffer rotationGradients;         // 3 a surfel: r, g, b
layout(std430, binding = 9) writeonly buffer BounceSums { BounceSum bounceSums[]; };  // per workgroup
layout(std430, binding = 10) readonly buffer FrameCounters { uint frameCounters[]; };
layout(std430, binding = 12) readonly buffer StaticCounters { uint staticCounters[]; };
// per surfel, at receivers and by creases: the static links' light, and (a) their Σ F (gather_creases.comp)
layout(std430, binding = 16) readonly buffer StillGathered { vec4 stillGathered[]; };
layout(binding = 17, r32ui) readonly uniform uimageBuffer surfelCrease;  // per surfel: 1 by a crease (creases.h)
layout(binding = 18, r32ui) readonly uniform uimageBuffer surfelRoot;
layout(binding = 19, r32ui) readonly uniform uimageBuffer rootFlags;
layout(push_constant) uniform Push { InterpolatePush push; };
#include "turned_irradiance.glsl"

shared BounceSum partial[64];

// Leaves the workgroup's sum for bounce_check, added in a fixed order.
void sumBounce(BounceSum mine) {
  const uint lid = gl_LocalInvocationID.x;
  partial[lid] = mine;
  barrier();
  if (lid == 0u) {
    BounceSum sum = BounceSum(0.0, 0.0);
    for (uint i = 0u; i < 64u; ++i) sum.total += partial[i].total, sum.change += partial[i].change;
    bounceSums[groupIndex()] = sum;
  }
}

// The surfel's new radiosity and irradiance; none (zeros for the sums) past the surfels or in a
// frame that overflowed (it is redone).
BounceSum interpolate(uint s) {
  if (s >= push.surfelCount || (frameCounters[kCounterOverflow] | staticCounters[kCounterOverflow]) != 0u)
    return BounceSum(0.0, 0.0);
  const uint count = imageLoad(tapCounts, int(s)).x;
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  const vec3 n = nodeNormalCone(leaf).xyz;
  const bool crease = imageLoad(surfelCrease, int(s)).x != 0u;
  vec3 e = vec3(0.0), tapsStill = vec3(0.0);
  float tapsCovered = 0.0;
  bool stillTaps = crease;
  for (uint t = 0u; t < count; ++t) {
    uvec2 tap = imageLoad(taps, int(s * kInterpolationTaps + t)).xy;
    const float w = uintBitsToFloat(tap.y);
    e += w * turnedIrradiance(tap.x, n);
    if (crease) {
      const vec4 still = stillGathered[tap.x];
      tapsStill += w * still.rgb, tapsCovered += w * still.a;
      const uint root = imageLoad(surfelRoot, int(tap.x)).x;
      stillTaps = stillTaps && tap.x != s && (imageLoad(rootFlags, int(root)).x & kRootStill) != 0u;
    }
  }
  // By a crease, the still senders' light is the surfel's own (gather_creases.comp), the rest its
  // receivers'. The other surface only adds to what a surfel there sees: where it covers less of its
  // hemisphere than its receivers do, the bins lost it beside the edge (their gaps, where the faces
  // meet), and the lost part is taken at the mean of what it sees.
  if (stillTaps) {
    const vec4 own = stillGathered[s];
    if (own.a > 0.0) e += own.rgb * (1.0 + max(tapsCovered - own.a, 0.0) / own.a) - tapsStill;
  }
  e = max(e, vec3(0.0)) + imageLoad(surfelDirect, int(s)).rgb;  // the fit's coefficients may be negative
  const vec3 b = kPi * imageLoad(emission, int(s)).rgb + imageLoad(albedo, int(s)).rgb * e;
  radiosityOut[leaf] = vec4(b, 0.0);
  irradianceChange[s] = vec4(e - irradiance[s].rgb, 0.0);
  irradiance[s] = vec4(e, 0.0);
  const float area = nodePositionArea(leaf).w;
  return BounceSum(area * luminance(b), area * abs(luminance(b) - luminance(imageLoad(radiosityIn, int(leaf)).rgb)));
}

void main() { sumBounce(interpolate(itemIndex())); }

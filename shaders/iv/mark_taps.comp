#version 460
// What the image reads of iv's reflections, last the receivers whose reflections (reflect_receivers)
// the surfels marked kShownFit interpolate, where their own lobe faces the eye (reflect_surfels).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;

#include "lobe.glsl"
layout(binding = 4, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 5, rg32ui) readonly uniform uimageBuffer taps;  // InterpolationTap
layout(std430, binding = 6) buffer ShownSurfels { uint shownSurfels[]; };

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount || (shownSurfels[s] & kShownFit) == 0u || !lobeOf(s).seen) return;
  const uint count = imageLoad(tapCounts, int(s)).x;
  for (uint t = 0u; t < count; ++t) {
    const uint r = imageLoad(taps, int(s * kInterpolationTaps + t)).x;
    if ((shownSurfels[r] & kShownTap) == 0u) atomicOr(shownSurfels[r], kShownTap);
  }
}

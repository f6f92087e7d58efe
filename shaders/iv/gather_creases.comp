#version 460
// iv's bounces, after the gather: at each still surfel by a concave crease (engine/gi/iv/creases.h),
// the light of the still senders its own static links keep, over every one of them (the frame's
// overrides left aside; the emitters' own light, which the depth maps give, left out as the prune's
// correction takes it out), and their Σ F: what the gather sums at the receivers likewise. The
// interpolation gives such a surfel that light of its own and its receivers' for the rest: the
// crease's near field, which its receivers a few cells away do not see, is the surfel's own.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer CreaseSurfels { uint creaseSurfels[]; };
layout(binding = 1, rg32ui) readonly uniform uimageBuffer staticRanges;              // LeafRange
layout(binding = 2, rg32ui) readonly uniform uimageBuffer staticLinks[kTexelParts];  // LeafLink
layout(binding = 3, rgba32f) readonly uniform imageBuffer radiosityIn;
layout(std430, binding = 4) writeonly buffer StillGathered { vec4 stillGathered[]; };  // per surfel
layout(std430, binding = 5) readonly buffer BounceStates { BounceState state; };
layout(std430, binding = 6) readonly buffer FrameCounters { uint frameCounters[]; };
layout(std430, binding = 7) readonly buffer StaticCounters { uint staticCounters[]; };
// per static leaf: `correction`, less the emitters' own light its static links bring (prune_bins)
layout(std430, binding = 8) readonly buffer StaticLeaves { StaticLeaf staticLeaves[]; };
layout(push_constant) uniform Push { CountPush push; };

void main() {
  const uint k = itemIndex();
  // Done bounces run no gather; a frame that overflowed is redone.
  if (k >= push.count || state.done != 0u || (frameCounters[kCounterOverflow] | staticCounters[kCounterOverflow]) != 0u)
    return;
  const uint s = creaseSurfels[k];
  const uvec2 range = imageLoad(staticRanges, int(s)).xy;
  vec3 g = vec3(0.0);
  float covered = 0.0;
  for (uint i = range.x; i < range.x + range.y; ++i) {
    const uvec2 link = loadParted(staticLinks, i).xy;
    const float f = uintBitsToFloat(link.y);
    g += f * imageLoad(radiosityIn, int(link.x)).rgb, covered += f;
  }
  stillGathered[s] = vec4(g + (range.y > 0u ? staticLeaves[s].correction.rgb : vec3(0.0)), covered);
}

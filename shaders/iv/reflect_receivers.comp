#version 460
// iv's reflections, first at the receivers: what each glossy receiver's lobe reflects toward the
// eye of the light its links bring (lobe_links.glsl), over what its lobe reflects of light arriving
// evenly (per channel), so that a neighbour of a like roughness takes it for its own material
// (reflect_surfels). Its α beside it; −1 where it reflects nothing toward the eye. Only at the
// receivers the image reads (mark_taps): the others' values are left as they were, never read.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
#define NODE_TEXELS 0
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = kReceiverGroup) in;

#include "lobe_links.glsl"
layout(binding = 16, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 17) readonly buffer ReceiverCounts { uint receiverCounts[]; };
layout(std430, binding = 18) writeonly buffer ReceiverLobe { vec4 receiverLobe[]; };  // per surfel
layout(std430, binding = 19) readonly buffer ShownSurfels { uint shownSurfels[]; };

void main() {
  const uint count = receiverCounts[kReceiverCount];
  FOR_GROUP_RECEIVERS(k, 0u, count) {
    const uint s = imageLoad(receivers, int(k)).x;
    if ((shownSurfels[s] & kShownTap) == 0u) continue;
    const Lobe lobe = lobeOf(s);
    vec4 reflected = vec4(0.0, 0.0, 0.0, -1.0);
    if (lobe.seen) reflected = vec4(reflectedAt(lobe, s) / max(kPi * lobe.evenShare, vec3(1e-4)), lobe.brdf.alpha);
    if (linkLane() == 0u) receiverLobe[s] = reflected;
  }
}

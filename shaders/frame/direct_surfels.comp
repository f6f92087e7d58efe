#version 460
// Direct light at the surfels: each surfel's irradiance from the emitter samples, seen or hidden by
// their depth maps (direct_light.glsl), and the punctual lights', the source of the first
// bounce; and the emitter samples' light with every sample seen, which the pixels' own shadows
// scale (direct_pixels, resolve).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 1) readonly buffer LightPoints { LightPoint lightPoints[]; };
layout(std430, binding = 2) readonly buffer LightViews { Camera lightViews[]; };
layout(binding = 3, r32ui) readonly uniform uimageBuffer lightDepth;  // depths' float bits
layout(std430, binding = 4) writeonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(std430, binding = 5) writeonly buffer SurfelUnshadowed { vec4 surfelUnshadowed[]; };
layout(push_constant) uniform Push { DirectLightPush push; };
#include "direct_light.glsl"

void main() {
  const uint i = itemIndex();
  if (i >= push.count) return;
  const Surfel s = surfels[i];
  vec3 unshadowed;
  const vec3 p = s.positionArea.xyz, n = s.normal.xyz;
  surfelDirect[i] = vec4(sampledIrradiance(p, n, push.sampleCount, push.resolution, 0u, 1u, unshadowed) +
                             punctualIrradiance(p, n, push.sampleCount, push.punctualLights, push.resolution),
                         0.0);
  surfelUnshadowed[i] = vec4(unshadowed, 0.0);
}

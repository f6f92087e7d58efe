#version 460
// iv, once a frame before the bounces (a scene with a metal): the receivers whose first bounce's
// arriving light arrival_lobes files, those the surfels whose lobe reflects most of their light
// (gpu::lobeDominates, send_arrival.comp) interpolate from. The marks start cleared.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 1, rg32ui) readonly uniform uimageBuffer taps;  // InterpolationTap
layout(binding = 2, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(std430, binding = 3) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(binding = 4, r32ui) writeonly uniform uimageBuffer arrivalTaps;  // per surfel: 1 where tapped
layout(push_constant) uniform Push { GatherPush push; };
#include "common/specular_albedo.glsl"

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const SurfaceBrdf brdf = surfelBrdf[s];
  if (!lobeDominates(brdf, specularAlbedoAt(brdf, 1.0))) return;
  const uint count = imageLoad(tapCounts, int(s)).x;
  for (uint t = 0u; t < count; ++t)
    imageStore(arrivalTaps, int(imageLoad(taps, int(s * kInterpolationTaps + t)).x), uvec4(1u));
}

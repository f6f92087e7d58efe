#version 460
// ar, the local pass (docs/design.md §2.2): per surfel, K reflects the incident light into radiance
// (on a radiance step; an antiradiance step keeps it) and J lets the incident light go through. A
// surfel is flat: what it sends toward ω is exitance · cos⁺ − antiradiance · |cos| with its own
// normal, so it keeps its exitance (area · L) and, per bin, its antiradiance times its area, and the
// cosines are applied exactly where they are read. Where the emitters' light comes from depth maps
// (inside the irradiance), the emission is not sent: only the light the surfels reflect travels.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that finding a bin's opposite is cheap

layout(std430, binding = 1) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(std430, binding = 2) readonly buffer Albedo { vec4 albedo[]; };
layout(std430, binding = 3) readonly buffer Emission { vec4 emission[]; };  // Le
layout(std430, binding = 4) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 5) buffer Radiance { vec4 radiance[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer incident;          // per surfel and bin (looking)
layout(binding = 7, rgba32f) writeonly uniform imageBuffer intensity;        // per node and bin (travel)
layout(std430, binding = 8) writeonly buffer Exitance { vec4 exitance[]; };  // per node, area · L
layout(push_constant) uniform Push { ArLocalPush push; };

void main() {
  uint s = itemIndex();
  if (s >= push.surfelCount) return;
  const uint leaf = leafOfSurfel[s], bins = 6u * kDirs * kDirs;
  float area = nodePositionArea(leaf).w;
  vec3 L = radiance[s].rgb;
  if (push.updateRadiance != 0u) {
    L = albedo[s].rgb * irradiance[s].rgb / kPi;
    if (push.emittersByMaps == 0u) L += emission[s].rgb;
    radiance[s] = vec4(L, 0.0);
  }
  exitance[leaf] = vec4(area * L, 0.0);
  for (uint c = 0u; c < bins; ++c) {
    // Antiradiance toward c: the light that arrived travelling along c, from the opposite bin.
    vec3 through = imageLoad(incident, int(s * bins + oppositeBin(c, kDirs))).rgb;
    imageStore(intensity, int(leaf * bins + c), vec4(area * through, 0.0));
  }
}

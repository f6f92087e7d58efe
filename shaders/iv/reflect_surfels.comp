#version 460
// iv's reflections, then at every glossy surfel: interpolated from its receivers (its irradiance's
// taps) as its irradiance is. A receiver whose lobe is of a like roughness gives what it found
// (reflect_receivers) for the surfel's material; any other, what the surfel's own lobe reflects of
// its links (lobe_links.glsl). The resolve carries each surfel's value to its vertex and across its
// triangles. Only at the surfels the image reads (kShownFit).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
#include "common/parted_texels.glsl"
layout(local_size_x = 64) in;

#include "lobe_links.glsl"
layout(binding = 16, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 17, rg32ui) readonly uniform uimageBuffer taps;                  // InterpolationTap
layout(binding = 18, rgba32f) readonly uniform imageBuffer receiverLobe;          // per surfel
layout(std430, binding = 19) writeonly buffer SurfelLobe { vec4 surfelLobe[]; };  // rgb radiance
layout(std430, binding = 20) readonly buffer ShownSurfels { uint shownSurfels[]; };

// The roughnesses whose lobes one stands for the other's: α within this share of each other.
const float kLikeAlpha = 0.1;

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount || (shownSurfels[s] & kShownFit) == 0u) return;
  const Lobe lobe = lobeOf(s);
  vec3 sum = vec3(0.0);
  const uint count = lobe.seen ? imageLoad(tapCounts, int(s)).x : 0u;
  for (uint t = 0u; t < count; ++t) {
    const uvec2 tap = imageLoad(taps, int(s * kInterpolationTaps + t)).xy;
    const vec4 found = imageLoad(receiverLobe, int(tap.x));
    const bool alike = found.w > 0.0 && abs(found.w - lobe.brdf.alpha) <= kLikeAlpha * lobe.brdf.alpha;
    vec3 reflected;
    if (alike)
      reflected = found.rgb * kPi * lobe.evenShare;
    else
      reflected = reflectedAt(lobe, tap.x);
    sum += uintBitsToFloat(tap.y) * reflected;
  }
  surfelLobe[s] = vec4(max(sum, vec3(0.0)), 0.0);  // the fit's coefficients may be negative
}

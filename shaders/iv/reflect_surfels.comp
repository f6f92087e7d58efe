#version 460
// iv's reflections, then at every glossy surfel: interpolated from its receivers (its irradiance's
// taps) as its irradiance is. A receiver stands for the surfel where its lobe is of a like
// roughness and its view mirrors to a like direction (within the lobe's width): what it found
// (reflect_receivers) is taken for the surfel's material. The like receivers stand for the rest
// where they hold at least half the weight; else the rest of the indirect light is reflected as if
// it arrived evenly. On a curved surface a surfel toward its silhouette faces the eye at grazing
// while most of its receivers face it squarely or face away: their views mirror elsewhere.
// The resolve carries each surfel's value to its vertex and across its triangles. Only at the
// surfels the image reads (kShownFit).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;

#include "lobe.glsl"
layout(binding = 4, r32ui) readonly uniform uimageBuffer tapCounts;
layout(binding = 5, rg32ui) readonly uniform uimageBuffer taps;                  // InterpolationTap
layout(binding = 6, rgba32f) readonly uniform imageBuffer receiverLobe;          // per surfel
layout(std430, binding = 7) writeonly buffer SurfelLobe { vec4 surfelLobe[]; };  // rgb radiance
layout(std430, binding = 8) readonly buffer ShownSurfels { uint shownSurfels[]; };
layout(std430, binding = 9) readonly buffer Irradiance { vec4 irradiance[]; };  // per surfel, direct light in it
layout(binding = 10, rgba32f) readonly uniform imageBuffer surfelDirect;

// The roughnesses whose lobes one stands for the other's: α within this share of each other.
const float kLikeAlpha = 0.1;
// The lobe's width, in units of its (widened) α, within which two views' mirror directions are
// alike: twice the reflected direction's spread, √2·α per axis.
const float kLikeMirror = 2.0 * sqrt(2.0);
// The share of a surfel's interpolation weight its like receivers must hold to stand for the rest.
const float kLikeShare = 0.5;

// The direction the eye's view of a surface at x facing n mirrors to.
vec3 mirrorAt(vec3 x, vec3 n) {
  const vec3 v = normalize(towardEye(push.eye, x));
  return 2.0 * dot(n, v) * n - v;
}

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount || (shownSurfels[s] & kShownFit) == 0u) return;
  const Lobe lobe = lobeOf(s);
  const uint count = lobe.seen ? imageLoad(tapCounts, int(s)).x : 0u;
  const vec3 mirror = mirrorAt(lobe.x, lobe.n);
  const float alike = cos(min(kLikeMirror * widenedLobe(lobe.brdf, push.leastSpread).alpha, kPi));
  vec3 like = vec3(0.0);
  float likeWeight = 0.0, weight = 0.0;
  for (uint t = 0u; t < count; ++t) {
    const uvec2 tap = imageLoad(taps, int(s * kInterpolationTaps + t)).xy;
    const vec4 found = imageLoad(receiverLobe, int(tap.x));
    const float w = uintBitsToFloat(tap.y);
    weight += abs(w);
    if (!(found.w > 0.0 && abs(found.w - lobe.brdf.alpha) <= kLikeAlpha * lobe.brdf.alpha)) continue;
    const uint leaf = imageLoad(leafOfSurfel, int(tap.x)).x;
    if (dot(mirrorAt(nodePositionArea(leaf).xyz, nodeNormalCone(leaf).xyz), mirror) >= alike)
      like += w * found.rgb, likeWeight += w;
  }
  vec3 sum = like * (kPi * lobe.evenShare);
  if (likeWeight >= kLikeShare * weight) {
    sum /= likeWeight;
  } else if (count > 0u) {
    // The fit's weights sum to 1: the rest's share of the indirect light, reflected as if even.
    const vec3 indirect = max(irradiance[s].rgb - imageLoad(surfelDirect, int(s)).rgb, vec3(0.0));
    sum += (1.0 - likeWeight) * lobe.evenShare * indirect;
  }
  surfelLobe[s] = vec4(max(sum, vec3(0.0)), 0.0);  // the fit's coefficients may be negative
}

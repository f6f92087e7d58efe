#version 460
// Direct light at the surfels: each surfel's irradiance from the emitter samples, seen or hidden by
// their depth maps (direct_light.glsl), and the punctual lights', the source of the first
// bounce; and the emitter samples' light with every sample seen, which the pixels' own shadows
// scale (direct_pixels, resolve). Where the pixels take the direct light so, a surfel's shadowed
// light feeds only the bounces, which blur it, and it looks up every surfelStride-th sample's maps
// alone (from its index on, so that neighbours take different ones). Where only moving objects
// were drawn again over still maps, a surfel whose lookups they cannot reach keeps its light
// (DirectLightPush::changed). With kArrivals (some lobe sends by direction), the mean direction the
// light arrives from, for the lobes that send it on (shaders/common/sender_lobes.glsl).
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Surfels { Surfel surfels[]; };
layout(binding = 1, rgba32f) readonly uniform imageBuffer lightPoints;  // LightPoint
layout(binding = 2, rgba32f) readonly uniform imageBuffer lightViews;   // Camera
layout(binding = 3, r32ui) readonly uniform uimageBuffer lightDepth;    // depths' float bits
layout(std430, binding = 4) writeonly buffer SurfelDirect { vec4 surfelDirect[]; };
layout(std430, binding = 5) writeonly buffer SurfelUnshadowed { vec4 surfelUnshadowed[]; };
layout(std430, binding = 6) buffer SurfelsLit { uint surfelsLit; };  // with `changed`: how many are lit again
// The luminance-weighted means of the unit directions toward the seen light (xyz: its length is 1
// where all of it arrives from one direction, less as it spreads) and of the solid angle the
// surfel's disk spans from the lights (w).
layout(std430, binding = 7) writeonly buffer SurfelArrival { vec4 surfelArrival[]; };
layout(constant_id = 0) const bool kArrivals = false;
layout(push_constant) uniform Push { DirectLightPush push; };
#include "direct_light.glsl"

// Texels either side of a lookup's direction whose depths it may read (the bilinear four, and
// a margin).
const float kLookupTexels = 3.0;

// Whether anything within sphere `m` can change p's light: whether it comes within a lookup's reach
// of a segment from p to a point of the lights' sphere. Those segments fill the cone from p around
// that sphere, up to its far side; a cube's texel spans at most 2 / side of the distance from its
// origin (at a face's centre).
bool reachedBy(vec4 m, vec3 p) {
  const vec3 toLights = push.lights.xyz - p, toMoved = m.xyz - p;
  const float dl = length(toLights), dm = length(toMoved), far = dl + push.lights.w;
  const float r = m.w + kLookupTexels * 2.0 / float(push.resolution) * far;
  if (dm <= r || dl <= push.lights.w) return true;  // p within either sphere
  if (dm - r > far) return false;                   // beyond every light
  const float between = acos(clamp(dot(toLights, toMoved) / (dl * dm), -1.0, 1.0));
  return between <= asin(push.lights.w / dl) + asin(r / dm);
}

// The emitter samples' light at p (unit normal n), every sample seen.
vec3 unshadowedIrradiance(vec3 p, vec3 n) {
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < push.sampleCount; ++k) {
    float cosine;
    vec3 toward;
    sum += lightFrom(lightPointAt(k), p, n, cosine, toward);
  }
  return sum;
}

void main() {
  const uint i = itemIndex();
  if (i >= push.count) return;
  const Surfel s = surfels[i];
  vec3 unshadowed;
  const vec3 p = s.positionArea.xyz, n = s.normal.xyz;
  if (push.changed != 0u) {
    if (!reachedBy(push.moved[0], p) && !reachedBy(push.moved[1], p)) return;
    atomicAdd(surfelsLit, 1u);
  }
  vec4 sampled, punctual;
  float sampledFootprint, punctualFootprint;
  const float area = kArrivals ? s.positionArea.w : 0.0;
  const uint stride = push.surfelStride;
  surfelDirect[i] = vec4(sampledIrradiance(p, n, push.sampleCount, push.resolution, i % stride, stride, unshadowed,
                                           sampled, area, sampledFootprint) +
                             punctualIrradiance(p, n, push.sampleCount, push.punctualLights, push.resolution, punctual,
                                                area, punctualFootprint),
                         0.0);
  if (stride > 1u) unshadowed = unshadowedIrradiance(p, n);
  surfelUnshadowed[i] = vec4(unshadowed, 0.0);
  if (kArrivals) {
    const vec4 arrival = sampled + punctual;
    surfelArrival[i] =
        arrival.w > 0.0 ? vec4(arrival.xyz, sampledFootprint + punctualFootprint) / arrival.w : vec4(0.0);
  }
}

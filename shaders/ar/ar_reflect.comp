#version 460
// ar, once its iterations are done: what each glossy surfel's specular lobe reflects toward the
// eye of its incident light (ar_incident's table: the radiance averaged over each bin, less the
// emitters' direct light where the depth maps give it), bin by bin through the lobe widened by
// what the tables blur (written and read between bins, binTaps). The bins weigh the lobe at their
// centres, which a lobe about as narrow as a bin falls between or onto by where its peak lies; so
// the weights are scaled to sum to what the lobe reflects of light arriving evenly, and the
// reflection is a mean of the bins' light by the lobe's shape. Zero at the other surfels the image
// reads (kShownFit); the rest are left as they were, never read.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that the bins' arithmetic folds

layout(std430, binding = 1) readonly buffer LeafOfSurfel { uint leafOfSurfel[]; };
layout(binding = 2, rgba32f) readonly uniform imageBuffer binTable;  // per bin ∫ω dω, Ω
layout(binding = 3, rgba32f) readonly uniform imageBuffer incident;  // per surfel and bin
layout(std430, binding = 4) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(std430, binding = 5) writeonly buffer SurfelLobe { vec4 surfelLobe[]; };  // rgb radiance
layout(std430, binding = 6) readonly buffer ShownSurfels { uint shownSurfels[]; };
layout(binding = 7, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(push_constant) uniform Push { LobePush push; };
#include "common/specular_albedo.glsl"

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount || (shownSurfels[s] & kShownFit) == 0u) return;
  const SurfaceBrdf m = surfelBrdf[s];
  const uint leaf = leafOfSurfel[s];
  const vec3 x = nodePositionArea(leaf).xyz, n = nodeNormalCone(leaf).xyz, toEye = towardEye(push.eye, x);
  const float nv = dot(n, toEye);
  if (isLambertian(m) || !(nv > 0.0)) {
    surfelLobe[s] = vec4(0.0);
    return;
  }
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  const vec3 view = normalize(vec3(dot(toEye, t1), dot(toEye, t2), nv));
  const SurfaceBrdf widened = widenedLobe(m, push.leastSpread);
  const uint bins = 6u * kDirs * kDirs;
  vec3 sum = vec3(0.0), weights = vec3(0.0);
  for (uint b = 0u; b < bins; ++b) {
    const vec3 moment = imageLoad(binTable, int(b)).xyz;  // ∫ω dω: n· it is the bin's cosine-weighted solid angle
    const float weight = dot(n, moment);
    if (weight <= 0.0) continue;
    const vec3 l = normalize(moment);
    // weight 0 in evalBrdf: the lobe alone, not the base
    const vec3 f = weight * evalBrdf(widened, vec3(dot(l, t1), dot(l, t2), dot(l, n)), view, 0.0);
    sum += imageLoad(incident, int(s * bins + b)).rgb * f, weights += f;
  }
  const vec3 even = lobeReflectanceOf(m, specularAlbedoAt(m, view.z));
  sum *= vec3(weights.r > 0.0 ? even.r / weights.r : 0.0, weights.g > 0.0 ? even.g / weights.g : 0.0,
              weights.b > 0.0 ? even.b / weights.b : 0.0);
  surfelLobe[s] = vec4(max(sum, vec3(0.0)), 0.0);  // antiradiance may leave a bin below zero
}

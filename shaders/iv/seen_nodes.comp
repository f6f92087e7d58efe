#version 460
// The nodes the image sees: those above a surfel whose value it reads (kShownFit), each marked with
// its sharpness, how many times nearer than the light's own spacing its receivers must lie (1 where
// the light alone decides; 0 where unseen). The receivers' refinement judges the unseen at
// --unseen-tol: their light reaches the image only after a bounce. Where a surfel's lobe sends most
// of what the eye sees of it (gpu::lobeDominates toward the eye: a metal), the image shows the
// reflections its receivers found through a narrow lobe and carried to it (reflect_surfels); each
// comes from few links and differs from its neighbours', so a receiver standing for many surfels
// would decide a patch of the image alone. The nearness test is scaled by kLobeSpacing · share / α'
// (narrower lobes, nearer receivers), so that each surfel takes its reflection from several. A
// dielectric's lobe holds too little of its light to ask for more.
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 7
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 1, r32ui) readonly uniform uimageBuffer leafOfSurfel;
layout(std430, binding = 2) readonly buffer ShownSurfels { uint shownSurfels[]; };
layout(std430, binding = 3) buffer SeenNodes { uint seenNodes[]; };  // float bits
layout(binding = 4, rgba32f) readonly uniform imageBuffer views;     // the image's Camera
layout(std430, binding = 5) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(binding = 6, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(push_constant) uniform Push { SeenPush push; };
#include "common/specular_albedo.glsl"

// How much of a lobe's width (α', as the bins widen it) a receiver's reflection may stand for.
const float kLobeSpacing = 0.5;

float sharpnessOf(uint s) {
  const SurfaceBrdf brdf = surfelBrdf[s];
  if (isLambertian(brdf)) return 1.0;
  const Camera camera = Camera(imageLoad(views, 0), imageLoad(views, 1), imageLoad(views, 2), imageLoad(views, 3));
  const uint leaf = imageLoad(leafOfSurfel, int(s)).x;
  const vec3 n = nodeNormalCone(leaf).xyz;
  const float nv = dot(n, normalize(towardEye(cameraEye(camera), nodePositionArea(leaf).xyz)));
  if (nv <= 0.0) return 1.0;
  const vec2 table = specularAlbedoAt(brdf, nv);
  if (!lobeDominates(brdf, table)) return 1.0;
  const float share = luminance(lobeReflectanceOf(brdf, table)) / max(luminance(reflectanceOf(brdf, table)), 1e-6);
  return max(1.0, kLobeSpacing * share / widenedLobe(brdf, push.leastSpread).alpha);
}

void main() {
  const uint s = itemIndex();
  if (s >= push.surfelCount || (shownSurfels[s] & kShownFit) == 0u) return;
  const uint sharpness = floatBitsToUint(sharpnessOf(s));  // positive floats order as their bits
  // A node marked as sharp already has its ancestors so marked, or being marked by the surfel that
  // marked it.
  for (int node = int(imageLoad(leafOfSurfel, int(s)).x); node >= 0; node = int(imageLoad(tree, node).x))
    if (atomicMax(seenNodes[node], sharpness) >= sharpness) break;
}

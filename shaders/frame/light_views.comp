#version 460
// Direct light, first: each emitter sample where the frame put it (its triangle's corners as the
// animate pass left them), the area it stands for, and the cube of 90° views around it that its
// depth maps are rasterized in (a face wholly behind the emitter is no view: near < 0); then each
// direction toward the environment, and each directional light of the frame, its one orthographic
// view along it over the scene's bounds (world_bounds), and a directional punctual light its
// cascades around the camera; and each point and spot light its cube around its position.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(std430, binding = 2) readonly buffer EmitterSamples { EmitterSample emitterSamples[]; };
layout(std430, binding = 3) writeonly buffer LightPoints { LightPoint lightPoints[]; };
layout(std430, binding = 4) writeonly buffer LightViews { Camera lightViews[]; };
layout(std430, binding = 5) readonly buffer PunctualLights { PunctualLight punctualLights[]; };
layout(std430, binding = 6) readonly buffer SceneBounds { uint sceneBounds[6]; };  // orderedBits
layout(push_constant) uniform Push { LightViewsPush push; };

vec3 positionOf(uint vertex) { return imageLoad(world, int(2u * vertex)).xyz; }
vec3 normalOf(uint vertex) { return imageLoad(world, int(2u * vertex + 1u)).xyz; }

// Point i's first view: a cube an emitter sample and a punctual light, one view an environment direction.
uint firstView(uint i) {
  const uint e = push.sampleCount, k = push.environmentDirections;
  return i < e ? kCubeFaces * i : (i < e + k ? kCubeFaces * e + (i - e) : kCubeFaces * (i - k) + k);
}

// The cube of views around `origin` whose near plane is `near`, each face wholly behind `front` (a
// zero front: none) no view.
void writeCube(uint i, vec3 origin, float near, vec3 front) {
  for (uint face = 0u; face < kCubeFaces; ++face) {
    const uint axis = face >> 1u;
    vec3 forward = vec3(0.0), right = vec3(0.0), up = vec3(0.0);
    forward[axis] = (face & 1u) == 0u ? 1.0 : -1.0;
    right[axis == 2u ? 0u : axis + 1u] = 1.0;
    up[axis == 0u ? 2u : axis - 1u] = 1.0;
    // Wholly behind: every direction of the face's pyramid on the emitter's back.
    const bool behind = front != vec3(0.0) && dot(forward, front) + abs(dot(right, front)) + abs(dot(up, front)) <= 0.0;
    lightViews[firstView(i) + face] =
        Camera(vec4(origin, behind ? -1.0 : near), vec4(right, 0.0), vec4(up, 0.0), vec4(forward, 0.0));
  }
}

void main() {
  const uint i = itemIndex();
  if (i >= push.sampleCount + push.punctualLights) return;
  if (i >= push.sampleCount) {
    const PunctualLight l = punctualLights[i - push.sampleCount];
    if (l.position.w == kLightDirectional) {
      // One view from the plane before the scene's bounding sphere, along the light; no other face.
      vec3 lo, hi;
      fromOrderedBox(sceneBounds, lo, hi);
      const vec3 centre = 0.5 * (lo + hi), forward = normalize(l.direction.xyz);
      const float radius = 0.5 * length(hi - lo) * 1.01 + 1e-6 * (1.0 + length(centre));
      vec3 right, up;
      tangentFrame(forward, right, up);
      const vec3 origin = centre - radius * forward;
      // A punctual light's place holds a cube: past the first face, its cascades (none for an
      // environment direction, which has one view), and the faces past those no view.
      const bool punctual = i >= push.sampleCount + push.environmentDirections;
      const uint cascades = punctual ? push.cascadeCount : 0u;
      lightPoints[i] =
          LightPoint(vec4(origin, float(cascades)), l.direction, vec4(l.intensity.rgb, uintBitsToFloat(firstView(i))),
                     vec4(l.cone.xy, l.position.w, kLightPointIsPunctual));
      const Camera scene =
          Camera(vec4(origin, 0.0), vec4(radius * right, 0.0), vec4(radius * up, kOrthographic), vec4(forward, 0.0));
      lightViews[firstView(i)] = scene;
      for (uint face = 1u; face < (punctual ? kCubeFaces : 1u); ++face) {
        if (face > cascades) {
          lightViews[firstView(i) + face] = Camera(vec4(origin, -1.0), scene.right, scene.up, scene.forward);
          continue;
        }
        // Its sphere's centre moved across the light by whole texels (the maps of a moving camera
        // then hold still on the scene), drawn from before the scene's bounds.
        const vec4 sphere = push.cascades[face - 1u];
        const float texel = 2.0 * sphere.w / float(push.side);
        const vec2 across = floor(vec2(dot(sphere.xyz, right), dot(sphere.xyz, up)) / texel + 0.5) * texel;
        const vec3 c = across.x * right + across.y * up + dot(sphere.xyz, forward) * forward;
        lightViews[firstView(i) + face] =
            Camera(vec4(c - (radius + distance(c, centre)) * forward, 0.0), vec4(sphere.w * right, 0.0),
                   vec4(sphere.w * up, kOrthographic), vec4(forward, 0.0));
      }
      return;
    }
    lightPoints[i] =
        LightPoint(vec4(l.position.xyz, 0.0), l.direction, vec4(l.intensity.rgb, uintBitsToFloat(firstView(i))),
                   vec4(l.cone.xy, l.position.w, kLightPointIsPunctual));
    writeCube(i, l.position.xyz, 1e-4 * (1.0 + length(l.position.xyz)), vec3(0.0));
    return;
  }
  const EmitterSample s = emitterSamples[i];
  const uvec4 t = imageLoad(triangles, int(s.triangle));
  const vec3 a = positionOf(t.x), b = positionOf(t.y), c = positionOf(t.z);
  const vec3 p = a + s.b * (b - a) + s.c * (c - a), g = cross(b - a, c - a);
  const float doubleArea = length(g);
  vec3 n = doubleArea > 0.0 ? g / doubleArea : vec3(0.0, 0.0, 1.0);
  // The front is the side the shading normals face (flat shaded: the winding's), as the surfels'.
  if ((t.w & kFlatShaded) == 0u &&
      dot((1.0 - s.b - s.c) * normalOf(t.x) + s.b * normalOf(t.y) + s.c * normalOf(t.z), n) < 0.0)
    n = -n;
  lightPoints[i] = LightPoint(vec4(p, 0.5 * doubleArea * s.weightPerArea), vec4(n, 0.0),
                              vec4(s.radiance.rgb, uintBitsToFloat(firstView(i))), vec4(0.0));

  // The views start a little off the emitter, and their near plane as far again: rays along the
  // emitter's plane then pass over it and its neighbours, which its front cannot light.
  const float offset = 1e-3 * sqrt(0.5 * doubleArea) + 1e-6 * length(p);
  writeCube(i, p + offset * n, offset, n);
}

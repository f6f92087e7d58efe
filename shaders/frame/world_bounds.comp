#version 460
// Direct light, where a directional light is drawn: the bounds of the scene as the animate pass
// left it, which its orthographic map covers (light_views). Each coordinate is kept as an ordered
// uint (orderedBits), so that atomicMin and atomicMax order them as floats; `sceneBounds` starts at
// the empty bounds.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;          // WorldVertex: position, normal
layout(std430, binding = 1) buffer SceneBounds { uint sceneBounds[6]; };  // min xyz, max xyz
layout(push_constant) uniform Push { CountPush push; };                   // count: vertices

void main() {
  const uint v = itemIndex();
  if (v >= push.count) return;
  const vec3 p = imageLoad(world, int(2u * v)).xyz;
  for (uint axis = 0u; axis < 3u; ++axis) {
    atomicMin(sceneBounds[axis], orderedBits(p[axis]));
    atomicMax(sceneBounds[3u + axis], orderedBits(p[axis]));
  }
}

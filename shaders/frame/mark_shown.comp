#version 460
// What the image reads of the reflections, first the surfels at the vertices of the triangles the
// image's samples hit: the resolve takes a glossy sample's reflection from its triangle's vertices.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rg32ui) readonly uniform uimageBuffer visibility;   // 64-bit keys, low word first
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 2, r32ui) readonly uniform uimageBuffer vertexSurfel;  // int, -1: none
layout(std430, binding = 3) buffer ShownSurfels { uint shownSurfels[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: the image's samples

void main() {
  const uint sample_ = itemIndex();
  if (sample_ >= push.count) return;
  const uint64_t key = packUint2x32(imageLoad(visibility, int(sample_)).xy);
  if (key == kEmptyVisibility) return;
  const uvec4 t = imageLoad(triangles, int(keyId(key)));
  for (uint j = 0u; j < 3u; ++j) {
    const int s = int(imageLoad(vertexSurfel, int(t[j])).x);
    // Most samples meet surfels their neighbours marked already: a load spares the atomic.
    if (s >= 0 && (shownSurfels[s] & kShownVertex) == 0u) atomicOr(shownSurfels[s], kShownVertex);
  }
}

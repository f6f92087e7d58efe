#version 460
// What the image reads of the reflections, then the surfels whose values the shown vertices' fits
// read (vertex_irradiance): every surfel at a corner of a shown surfel's triangles, and itself.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer surfelSources;  // SurfelSource
layout(binding = 1, r32ui) readonly uniform uimageBuffer surfelTriangles;
layout(binding = 2, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(binding = 3, r32ui) readonly uniform uimageBuffer vertexSurfel;  // int, -1: none
layout(std430, binding = 4) buffer ShownSurfels { uint shownSurfels[]; };
layout(push_constant) uniform Push { CountPush push; };  // count: surfels

void main() {
  const uint s = itemIndex();
  if (s >= push.count || (shownSurfels[s] & kShownVertex) == 0u) return;
  atomicOr(shownSurfels[s], kShownFit);
  const uvec4 src = imageLoad(surfelSources, int(s));  // firstVertex, vertexCount, firstTriangle, triangleCount
  for (uint k = 0u; k < src.w; ++k) {
    const uvec4 t = imageLoad(triangles, int(imageLoad(surfelTriangles, int(src.z + k)).x));
    for (uint j = 0u; j < 3u; ++j) {
      const int other = int(imageLoad(vertexSurfel, int(t[j])).x);
      if (other >= 0 && (shownSurfels[other] & kShownFit) == 0u) atomicOr(shownSurfels[other], kShownFit);
    }
  }
}

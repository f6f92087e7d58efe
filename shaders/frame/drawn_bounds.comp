#version 460
// The raster pass, where it draws many views: the box around the triangles drawn, which drawn_views
// tests each view against. Each workgroup bounds its 64 triangles and widens the box once; each
// coordinate is kept as an ordered uint (orderedBits), so that atomicMin and atomicMax order them as
// floats. `drawnBox` starts at the empty box.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(std430, binding = 2) buffer DrawnBox { uint drawnBox[6]; };      // min xyz, max xyz
layout(push_constant) uniform Push { RasterPush push; };
#include "raster_bounds.glsl"

void main() {
  const uint tri = itemIndex();
  const bool has = tri < push.triangleCount;
  Corners k;
  if (has) k = cornersOf(tri);
  vec3 lo, hi;
  gatherGroupBox(has, k, lo, hi);
  if (gl_LocalInvocationID.x == 0u && lo.x <= hi.x)
    for (uint axis = 0u; axis < 3u; ++axis) {
      atomicMin(drawnBox[axis], orderedBits(lo[axis]));
      atomicMax(drawnBox[3u + axis], orderedBits(hi[axis]));
    }
}

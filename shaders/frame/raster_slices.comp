#version 460
// The raster pass, first: how many workgroups in z the raster needs, the slices of the largest
// triangle bounds in any of its views (raster.comp walks at most kTilesPerSlice tiles of a
// triangle in one workgroup), times the views. Counted for the image's size instead, a finely
// supersampled frame of small triangles would start tens of idle workgroups for every 64 triangles.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int kTilesPerSlice = 448;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
// The raster's VkDispatchIndirectCommand (x, y as the triangles need; z: the views, raised here).
layout(std430, binding = 2) buffer RasterArgs { uint rasterArgs[]; };
layout(std430, binding = 3) readonly buffer Views { Camera views[]; };  // a view whose near is < 0: none
layout(push_constant) uniform Push { RasterPush push; };
#include "raster_bounds.glsl"

void main() {
  const uint tri = itemIndex();
  if (tri >= push.triangleCount) return;
  uint slices = 1u;
  for (uint view = 0u; view < push.viewCount; ++view) {
    if (views[view].origin.w < 0.0) continue;
    const Projected t = projected(views[view], tri);
    if (!isLarge(t)) continue;
    const Slicing s = slicing(t, kTilesPerSlice);
    slices = max(slices, uint(s.columnBlocks * s.rowBlocks));
  }
  if (slices > 1u) atomicMax(rasterArgs[2], slices * push.viewCount);
}

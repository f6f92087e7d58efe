#version 460
// The raster pass, second: how many workgroups in z the raster needs, the slices of the largest
// triangle bounds in any of the views drawn_views listed (raster.comp walks at most kTilesPerSlice
// tiles of a triangle in one view in one workgroup), times the workgroups those views take. Counted
// for the image's size instead, a finely supersampled frame of small triangles would start tens of
// idle workgroups for every 64 triangles.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int kTilesPerSlice = 896;
layout(constant_id = 1) const uint kViewsPerGroup = 1;  // raster.comp's

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
// The raster's VkDispatchIndirectCommand (x, y as the triangles need; z: the views, raised here).
layout(std430, binding = 2) buffer RasterArgs { uint rasterArgs[]; };
layout(binding = 3, rgba32f) readonly uniform imageBuffer views;                // Camera
layout(std430, binding = 4) readonly buffer DrawnViews { uint drawnViews[]; };  // the count, then the views
layout(push_constant) uniform Push { RasterPush push; };
#include "raster_bounds.glsl"

shared uint largeViews[64];  // of the views judged together, those that may hold large bounds
shared uint largeViewCount;

// Whether any triangle in the box [lo, hi] may have large bounds in `camera`'s view: one across the
// near plane may; else a triangle in it is on screen and large only where the box's bounds are.
bool mayHoldLargeBounds(Camera camera, vec3 lo, vec3 hi) {
  bool across;
  ivec2 blo, bhi;
  if (!boxInView(camera, lo, hi, across, blo, bhi)) return false;
  const ivec2 extent = bhi - blo + 1;
  return across || extent.x * extent.y > kSmallBounds;
}

void main() {
  const uint lid = gl_LocalInvocationID.x, tri = itemIndex();
  const bool has = tri < push.triangleCount;
  Corners k;
  if (has) k = cornersOf(tri);
  vec3 lo, hi;
  gatherGroupBox(has, k, lo, hi);
  uint slices = 1u;
  // 64 views at a time, each judged by one invocation for the whole workgroup: a triangle is
  // projected only into the views where its group's box may hold large bounds, listed (a loop over
  // every view, even one that does nothing, costs lavapipe more than the projections it saves).
  const uint listed = drawnViews[0];
  for (uint base = 0u; base < listed; base += 64u) {
    if (lid == 0u) largeViewCount = 0u;
    barrier();
    const uint view = base + lid < listed ? drawnViews[1u + base + lid] : 0u;
    if (base + lid < listed && mayHoldLargeBounds(CAMERA_TEXELS(views, view), lo, hi))
      largeViews[atomicAdd(largeViewCount, 1u)] = view;
    barrier();
    for (uint n = 0u; has && n < largeViewCount; ++n) {
      const Projected t = projected(CAMERA_TEXELS(views, largeViews[n]), k);
      if (!isLarge(t)) continue;
      const Slicing s = slicing(t, kTilesPerSlice);
      slices = max(slices, uint(s.columnBlocks * s.rowBlocks));
    }
    barrier();  // before the next views' judging
  }
  if (slices > 1u) atomicMax(rasterArgs[2], slices * ((listed + kViewsPerGroup - 1u) / kViewsPerGroup));
}

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

shared uint groupBox[6];     // min x, y, z, max x, y, z as orderedBits
shared uint largeViews[64];  // of the views judged together, those that may hold large bounds
shared uint largeViewCount;

// The box around the workgroup's triangles. Every invocation calls it (it holds barriers); `has`:
// whether k is a triangle.
void gatherGroupBox(bool has, Corners k, out vec3 lo, out vec3 hi) {
  const uint lid = gl_LocalInvocationID.x;
  if (lid < 6u) groupBox[lid] = lid < 3u ? 0xFFFFFFFFu : 0u;
  barrier();
  if (has)
    for (int axis = 0; axis < 3; ++axis) {
      atomicMin(groupBox[axis], orderedBits(min(k.a[axis], min(k.b[axis], k.c[axis]))));
      atomicMax(groupBox[3 + axis], orderedBits(max(k.a[axis], max(k.b[axis], k.c[axis]))));
    }
  barrier();
  lo = vec3(fromOrderedBits(groupBox[0]), fromOrderedBits(groupBox[1]), fromOrderedBits(groupBox[2]));
  hi = vec3(fromOrderedBits(groupBox[3]), fromOrderedBits(groupBox[4]), fromOrderedBits(groupBox[5]));
  if (groupBox[0] > groupBox[3]) lo = vec3(3.4e38), hi = vec3(-3.4e38);  // no triangle
}

// Whether any triangle in the box [lo, hi] may have large bounds in `camera`'s view. Where the whole
// box lies beyond the near plane, a triangle in it projects within the box's projection (a convex
// hull in front of the camera projects to the hull of its corners' projections), so neither is
// on screen and large where the box's bounds are not. One across the near plane may hold them.
bool mayHoldLargeBounds(Camera camera, vec3 lo, vec3 hi) {
  if (camera.origin.w < 0.0 || lo.x > hi.x) return false;  // no view, or no triangle
  vec2 mn = vec2(3.4e38), mx = vec2(-3.4e38);
  uint beyond = 0u;  // corners beyond the near plane
  for (int i = 0; i < 8; ++i) {
    const vec3 p = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
    const float z = dot(p - camera.origin.xyz, camera.forward.xyz);
    if (z > camera.origin.w) {
      const vec2 s = projectAt(camera, p, z);
      mn = min(mn, s), mx = max(mx, s), ++beyond;
    }
  }
  if (beyond < 8u) return beyond > 0u;  // wholly behind the near plane: nothing of it in view
  ivec2 blo, bhi;
  boundsOf(mn, mx, blo, bhi);
  const ivec2 extent = bhi - blo + 1;
  return all(greaterThan(extent, ivec2(0))) && extent.x * extent.y > kSmallBounds;
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
  for (uint base = 0u; base < push.viewCount; base += 64u) {
    if (lid == 0u) largeViewCount = 0u;
    barrier();
    const uint view = push.firstView + base + lid;
    if (base + lid < push.viewCount && mayHoldLargeBounds(views[view], lo, hi))
      largeViews[atomicAdd(largeViewCount, 1u)] = view;
    barrier();
    for (uint n = 0u; has && n < largeViewCount; ++n) {
      const Projected t = projected(views[largeViews[n]], k);
      if (!isLarge(t)) continue;
      const Slicing s = slicing(t, kTilesPerSlice);
      slices = max(slices, uint(s.columnBlocks * s.rowBlocks));
    }
    barrier();  // before the next views' judging
  }
  if (slices > 1u) atomicMax(rasterArgs[2], slices * push.viewCount);
}

#version 460
// The raster pass, first: the views it draws, in order, and its dispatch's z, a workgroup for every
// kViewsPerGroup of them (raster_slices raises it where large triangles need slices). Of the views
// from `firstView` on, those that are views at all; where many are drawn (`cull`), only those that
// the drawn triangles' box reaches (drawn_bounds), so that a moving object drawn over the still maps
// starts no workgroups in the cube faces that cannot see it. One workgroup.
#extension GL_GOOGLE_include_directive : require
#include "common/common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint kViewsPerGroup = 1;  // raster.comp's

layout(binding = 0, rgba32f) readonly uniform imageBuffer views;  // Camera, a view whose near is < 0: none
layout(std430, binding = 1) readonly buffer DrawnBox { uint drawnBox[6]; };
layout(std430, binding = 2) writeonly buffer DrawnViews { uint drawnViews[]; };  // the count, then the views
layout(std430, binding = 3) writeonly buffer RasterArgs { uint rasterArgs[]; };
layout(push_constant) uniform Push { RasterPush push; };
#include "view_bounds.glsl"

shared bool drawnHere[64];

void main() {
  const uint lid = gl_LocalInvocationID.x;
  vec3 lo, hi;
  fromOrderedBox(drawnBox, lo, hi);
  const bool empty = drawnBox[0] > drawnBox[3];  // no triangle
  uint listed = 0u;
  // 64 views at a time, judged one an invocation, listed in order by the first: 65 rounds a 64
  // views, about 29,000 for the most the settings allow (4,096 samples' cubes and 4,096
  // directions), within lavapipe's loop budget (common.glsl).
  for (uint base = 0u; base < push.viewCount; base += 64u) {
    const uint view = push.firstView + base + lid;
    bool drawn = false;
    if (base + lid < push.viewCount) {
      bool across;
      ivec2 blo, bhi;
      const Camera camera = CAMERA_TEXELS(views, view);
      drawn = camera.origin.w >= 0.0 && (push.cull == 0u || (!empty && boxInView(camera, lo, hi, across, blo, bhi)));
    }
    drawnHere[lid] = drawn;
    barrier();
    if (lid == 0u)
      for (uint t = 0u; t < 64u; ++t)
        if (drawnHere[t]) drawnViews[1u + listed++] = push.firstView + base + t;
    barrier();
  }
  if (lid == 0u) drawnViews[0] = listed, rasterArgs[2] = (listed + kViewsPerGroup - 1u) / kViewsPerGroup;
}

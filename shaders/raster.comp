#version 460
// Pass 7a, rasterise: one workgroup per triangle walks the pixels of its screen bounds in 8×8 tiles
// (no integer division: lavapipe divides one lane at a time), casts the camera ray through each
// sample centre and keeps the nearest hit by 64-bit atomicMin. A workgroup walks at most
// kTilesPerSlice tiles, so that it stays within lavapipe's loop budget (common.glsl; past it a large
// triangle would silently lose its lower rows); bounds holding more are cut into slices of tile
// rows, slice z walked by workgroup z (the host dispatches as many as bounds as large as the image
// need).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int kTilesPerSlice = 32768;

layout(binding = 0, rgba32f) readonly uniform imageBuffer world;        // WorldVertex: position, normal
layout(binding = 1, rgba32ui) readonly uniform uimageBuffer triangles;  // Triangle
layout(std430, binding = 2) buffer Visibility { uint64_t visibility[]; };
layout(push_constant) uniform Push { ImagePush push; };  // count: triangles

// Sample-space x/y of a world point, or false when it lies at or behind the near plane.
bool project(vec3 p, out vec2 s) {
  vec3 d = p - push.camera.origin.xyz;
  float z = dot(d, push.camera.forward.xyz);
  s = vec2(0.0);
  if (z <= push.camera.origin.w) return false;
  vec2 ndc = vec2(dot(d, push.camera.right.xyz) / dot(push.camera.right.xyz, push.camera.right.xyz),
                  dot(d, push.camera.up.xyz) / dot(push.camera.up.xyz, push.camera.up.xyz)) /
             z;
  s = vec2((ndc.x + 1.0) * 0.5 * float(push.size.x), (1.0 - ndc.y) * 0.5 * float(push.size.y));
  return true;
}

void main() {
  uint tri = groupIndex();
  if (tri >= push.count) return;  // count: triangles
  uvec4 t = imageLoad(triangles, int(tri));
  vec3 a = imageLoad(world, int(2u * t.x)).xyz, b = imageLoad(world, int(2u * t.y)).xyz,
       c = imageLoad(world, int(2u * t.z)).xyz;
  vec2 pa, pb, pc;
  ivec2 lo = ivec2(0), hi = ivec2(push.size) - 1;
  if (project(a, pa) && project(b, pb) && project(c, pc)) {
    vec2 mn = min(pa, min(pb, pc)), mx = max(pa, max(pb, pc));
    if (mx.x < -1.0 || mx.y < -1.0 || mn.x > float(push.size.x) + 1.0 || mn.y > float(push.size.y) + 1.0) return;
    lo = max(lo, ivec2(floor(mn)) - 1);
    hi = min(hi, ivec2(ceil(mx)));
  }  // else: a vertex behind the near plane, so the whole image is a conservative bound
  if (any(lessThan(hi, lo))) return;
  // This workgroup's slice: its tile rows, at most kTilesPerSlice tiles (a subgroup's rounds: the
  // tiles plus a round per row, under 35,000).
  int tileColumns = (hi.x - lo.x) / 8 + 1, rowsPerSlice = max(1, kTilesPerSlice / tileColumns);
  int first = lo.y + 8 * rowsPerSlice * int(gl_WorkGroupID.z), last = min(hi.y, first + 8 * rowsPerSlice - 1);
  ivec2 lane = ivec2(gl_LocalInvocationID.x & 7u, gl_LocalInvocationID.x >> 3u);
  for (int y = first; y <= last; y += 8)
    for (int x = lo.x; x <= hi.x; x += 8) {
      ivec2 px = ivec2(x, y) + lane;
      if (any(greaterThan(px, ivec2(hi.x, last)))) continue;
      vec3 dir = cameraRay(push.camera, vec2(px) + 0.5, push.size);
      float depth;
      vec2 uv;
      if (!intersectTriangle(push.camera.origin.xyz, dir, a, b, c, depth, uv)) continue;
      if (depth <= push.camera.origin.w || (push.camera.forward.w > 0.0 && depth > push.camera.forward.w)) continue;
      atomicMin(visibility[uint(px.y) * push.size.x + uint(px.x)], packDepthKey(depth, tri));
    }
}

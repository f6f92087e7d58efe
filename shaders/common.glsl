// Definitions shared by every ivgi compute shader: interface.h (layouts, constants, push constants
// and the functions the host uses too) and the helpers only shaders need.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "interface.h"

// Linear item index of a dispatch laid out over x then y (Program::dispatchItems).
uint itemIndex() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x; }
uint groupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }
// Indirect dispatch size for `items` invocations of `size`, laid out over x then y (itemIndex()).
uvec4 groupsFor(uint items, uint size) {
  const uint groups = (items + size - 1u) / size;
  return uvec4(min(groups, 65535u), (groups + 65534u) / 65535u, 1u, 0u);
}

// Möller–Trumbore without culling; t along the unnormalised ray (= depth along forward).
// Barycentrics get a tiny negative slack so that shared edges leave no cracks.
bool intersectTriangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c, out float t, out vec2 uv) {
  vec3 e1 = b - a, e2 = c - a;
  vec3 p = cross(d, e2);
  float det = dot(e1, p);
  t = 0.0;
  uv = vec2(0.0);
  if (det == 0.0) return false;
  float inv = 1.0 / det;
  vec3 s = o - a;
  float u = dot(s, p) * inv;
  vec3 q = cross(s, e1);
  float v = dot(d, q) * inv;
  const float slack = -1e-6;
  if (u < slack || v < slack || u + v > 1.0 - slack) return false;
  t = dot(e2, q) * inv;
  uv = vec2(u, v);
  return true;
}

// Face of a direction and its position on the face in bin units, (0,0) to (N,N).
uint binFace(vec3 d, uint n, out vec2 position) {
  vec3 a = abs(d);
  uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float major = axis == 0u ? d.x : (axis == 1u ? d.y : d.z);
  vec2 uv = axis == 0u ? d.yz : (axis == 1u ? d.zx : d.xy);
  position = (uv / abs(major) + 1.0) * 0.5 * float(n);
  return 2u * axis + (major < 0.0 ? 1u : 0u);
}

// lavapipe's loop budget. Mesa's gallivm, which compiles lavapipe's shaders, counts the rounds of
// every loop a subgroup runs, all loops of the shader together, and once they reach 65,535
// (LP_MAX_TGSI_LOOP_ITERATIONS, never reset while the subgroup runs) it ends each loop after one
// round, silently. Passes keep a subgroup's rounds below it: the rasteriser cuts large triangles
// into slices, one workgroup each; the gather's loops are bounded by a leaf's bins (at most
// 2·6·64² = 49,152); ar's global pass walks a link list in chunks (kArGatherChunk); the prune
// probes whether its workgroup ran out (the frame is then redone with more subgroups a workgroup);
// the other passes loop a few thousand rounds at most.
// True when the budget ran out before this call: a loop of lid + 2 rounds, a count no compiler
// knows, then runs one round. Devices without such a budget never report it.
bool loopBudgetSpent() {
  uint rounds = 0u, wanted = gl_LocalInvocationID.x + 2u;
  for (uint i = 0u; i < wanted; ++i) ++rounds;
  return rounds != wanted;
}

// Hot loops read arrays through imageBuffers: lavapipe gathers texels with vector loads but reads a
// storage buffer one lane at a time. A shader defines NODE_TEXELS (the binding) before including
// this file to read NodeState as three rgba32f texels per node.
#ifdef NODE_TEXELS
layout(binding = NODE_TEXELS, rgba32f) readonly uniform imageBuffer nodes;
vec4 nodePositionArea(uint i) { return imageLoad(nodes, int(3u * i)); }
vec4 nodeNormalCone(uint i) { return imageLoad(nodes, int(3u * i + 1u)); }
vec4 nodeShape(uint i) { return imageLoad(nodes, int(3u * i + 2u)); }
float nodeRadius(uint i) { return nodeShape(i).x; }
NodeState nodeState(uint i) { return NodeState(nodePositionArea(i), nodeNormalCone(i), nodeShape(i)); }

// The half-sides of a sender's rectangle (refit.comp) in the world; zero for a curved sender (a cone
// past 90°), which is filed as a square facing the receiver.
void senderSides(uint s, vec4 normalCone, out vec3 sideA, out vec3 sideB) {
  sideA = sideB = vec3(0.0);
  if (length(normalCone.xyz) == 0.0 || normalCone.w >= 0.5 * kPi) return;
  vec4 shape = nodeShape(s);
  rectangleAxes(normalCone.xyz, shape.y, sideA, sideB);
  sideA *= shape.z;
  sideB *= shape.w;
}
#endif

// The four bins around a direction, with bilinear weights between their centres (over a cube
// face's edge, cells of the neighbouring face): ar deposits and reads its tables through them, so
// that a sender seen near a bin's edge does not alias into one bin. Vectors, not arrays: lavapipe
// keeps a small array in memory, a vector in registers.
void binTaps(vec3 d, uint n, out uvec4 bins, out vec4 weights) {
  vec2 position;
  uint face = binFace(d, n, position);
  vec2 x = position - 0.5, cell = floor(x), f = x - cell;
  ivec2 c = ivec2(cell);
  bins = uvec4(binOfCell(face, c, n), binOfCell(face, c + ivec2(1, 0), n), binOfCell(face, c + ivec2(0, 1), n),
               binOfCell(face, c + ivec2(1, 1), n));
  weights = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
}

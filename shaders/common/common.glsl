// Definitions shared by every ivgi compute shader: interface.h (layouts, constants, push constants
// and the functions the host uses too) and the helpers only shaders need.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#include "interface.h"

// Rec. 709 luminance of linear RGB, by which light is weighed (image::luminance on the host).
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// Set by vk::Program from the device. A CPU device's atomics already order the memory around them,
// and lavapipe loses lanes of a divergent loop at a memory barrier: fences between workgroups of one
// dispatch (climb.glsl, a last workgroup's bookkeeping) are a GPU's only.
layout(constant_id = 29) const bool cpuDevice = false;
// Set by vk::Program from the device: whether the device's subgroup holds a whole workgroup, so
// that subgroup operations reach every lane of it without a barrier.
layout(constant_id = 25) const bool groupInOneSubgroup = false;

// Ends main() in every invocation but the first of the dispatch's last workgroup to get here, which
// may then read what every workgroup wrote (a dispatch's bookkeeping for the next, without a
// dispatch of its own). `done`: a counter, zero before and set back to zero here. Use in main(),
// after the work, in uniform control flow.
#define ONLY_IN_THE_LAST_WORKGROUP(done)                                          \
  barrier();                                                                      \
  if (gl_LocalInvocationIndex != 0u) return;                                      \
  if (!cpuDevice) memoryBarrier(); /* its work before its finish is counted */    \
  if (atomicAdd(done, 1u) + 1u < gl_NumWorkGroups.x * gl_NumWorkGroups.y) return; \
  done = 0u;                                                                      \
  if (!cpuDevice) memoryBarrier() /* every workgroup's work after the last finish */

// Linear item index of a dispatch laid out over x then y (Program::dispatchItems).
uint itemIndex() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x; }
uint groupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// Watertight ray–triangle test without culling (Woop, Benthin and Wald 2013): the corners are moved
// into the ray's frame, sheared so that the ray runs along its major axis, and each edge's function
// is a 2D cross product of its two corners alone. So two triangles sharing an edge compute it as
// exact negatives of each other, and a ray through the edge, or through a shared corner, hits at
// least one of them (a tolerance on barycentrics left cracks wherever rounding exceeded it). t along
// the unnormalised ray (= depth along forward); uv the weights of b and c.
bool intersectTriangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c, out float t, out vec2 uv) {
  t = 0.0;
  uv = vec2(0.0);
  const vec3 ad = abs(d);
  const int kz = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < 0.0) {  // keep the winding: the frame stays right-handed
    const int k = kx;
    kx = ky, ky = k;
  }
  const vec3 shear = vec3(d[kx], d[ky], 1.0) / d[kz];
  const vec3 A = a - o, B = b - o, C = c - o;
  const vec2 a2 = vec2(A[kx], A[ky]) - shear.xy * A[kz], b2 = vec2(B[kx], B[ky]) - shear.xy * B[kz],
             c2 = vec2(C[kx], C[ky]) - shear.xy * C[kz];
  const float u = c2.x * b2.y - c2.y * b2.x, v = a2.x * c2.y - a2.y * c2.x, w = b2.x * a2.y - b2.y * a2.x;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  const float det = u + v + w;
  if (det == 0.0) return false;  // edge-on or degenerate
  const float inv = 1.0 / det;
  t = (u * A[kz] + v * B[kz] + w * C[kz]) * shear.z * inv;
  uv = vec2(v, w) * inv;
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
// storage buffer one lane at a time. A struct of four vec4 (a Camera, a LightPoint, a mat4) written as
// a storage buffer is read back as four rgba32f texels: the v-th of imageBuffer `image`.
#define FOUR_TEXELS(Type, image, v)                                                                               \
  Type(imageLoad(image, int(4u * (v))), imageLoad(image, int(4u * (v)) + 1), imageLoad(image, int(4u * (v)) + 2), \
       imageLoad(image, int(4u * (v)) + 3))
#define CAMERA_TEXELS(views, v) FOUR_TEXELS(Camera, views, v)
// A shader defines NODE_TEXELS (the binding) before including this file to read NodeState as three
// rgba32f texels per node.
#ifdef NODE_TEXELS
layout(binding = NODE_TEXELS, rgba32f) readonly uniform imageBuffer nodes;
// A shader that also defines NODE_POSE sees every node through a rigid motion it sets (nodeTurn,
// nodeShift; the prune: a leaf sees the scene in its bin frame, a rigidly moving leaf as from its
// object's rest pose).
#ifdef NODE_POSE
mat3 nodeTurn = mat3(1.0);
vec3 nodeShift = vec3(0.0);
vec3 posedPoint(vec3 p) { return nodeTurn * p + nodeShift; }
vec3 posedDirection(vec3 d) { return nodeTurn * d; }
#else
vec3 posedPoint(vec3 p) { return p; }
vec3 posedDirection(vec3 d) { return d; }
#endif
vec4 nodePositionArea(uint i) {
  const vec4 v = imageLoad(nodes, int(3u * i));
  return vec4(posedPoint(v.xyz), v.w);
}
vec4 nodeNormalCone(uint i) {
  const vec4 v = imageLoad(nodes, int(3u * i + 1u));
  return vec4(posedDirection(v.xyz), v.w);
}
vec4 nodeShape(uint i) { return imageLoad(nodes, int(3u * i + 2u)); }
float nodeRadius(uint i) { return nodeShape(i).x; }

// The least angle between direction d and the directions in a cone (axis, half-angle); negative
// inside it.
float angleOutside(vec4 cone, vec3 d) { return acos(clamp(dot(cone.xyz, d), -1.0, 1.0)) - min(cone.w, kPi); }
NodeState nodeState(uint i) { return NodeState(nodePositionArea(i), nodeNormalCone(i), nodeShape(i)); }

// The half-sides of a sender's rectangle (refit.comp) in the world; zero for a curved sender (a cone
// past 90°), which is filed as a square facing the receiver.
void senderSides(uint s, vec4 normalCone, out vec3 sideA, out vec3 sideB) {
  sideA = sideB = vec3(0.0);
  if (length(normalCone.xyz) == 0.0 || normalCone.w >= 0.5 * kPi) return;
  // The rectangle's axes turn with the node: its angle is about the frame of its own normal.
  const vec4 shape = nodeShape(s);
  rectangleAxes(imageLoad(nodes, int(3u * s + 1u)).xyz, shape.y, sideA, sideB);
  sideA = posedDirection(sideA * shape.z);
  sideB = posedDirection(sideB * shape.w);
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

// A unit vector in 32 bits (octahedral, 16 bits a coordinate), and back.
uint packUnitVector(vec3 n) {
  vec2 o = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
  if (n.z < 0.0) o = (1.0 - abs(o.yx)) * vec2(o.x >= 0.0 ? 1.0 : -1.0, o.y >= 0.0 ? 1.0 : -1.0);
  return packSnorm2x16(o);
}
vec3 unpackUnitVector(uint bits) {
  const vec2 o = unpackSnorm2x16(bits);
  vec3 n = vec3(o, 1.0 - abs(o.x) - abs(o.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}

// The frame a receiver's bins lie along, as rows (frame * d is d in it): its normal and, across it,
// `along` (made a tangent; any tangent where it lies along the normal). Bins along the world's axes
// fall across the horizon of any surface not along them, and along no edge of a room modelled
// askew; along the receiver's own normal the horizon runs between two rows of bins (N even), and
// the prune tilts `along` from its object's axes (gi::objectAxes), so that the faces meeting its
// surface lie along bins too. The axes go through packUnitVector (binFrameOf), so that a pass that
// reads them back (StaticLeaf) bins alike, and so that axes within its precision of the world's
// are the world's.
vec3 frameTangent(vec3 normal, vec3 along) {
  vec3 t1, t2;
  tangentFrame(normal, t1, t2);
  const vec3 x = along - normal * dot(normal, along);
  return dot(x, x) > 1e-12 * dot(along, along) ? normalize(x) : t1;
}
mat3 binFrame(vec3 normal, vec3 along) {
  const vec3 x = frameTangent(normal, along);
  return transpose(mat3(x, cross(normal, x), normal));
}
// A tangent of unit normal n that varies smoothly with n (in some frame: the prune's, its object's
// axes): that frame's first axis `first` about its axis `a` nearest n (first × b = a for the third),
// turned the least way from a onto n (Rodrigues' formula with w = a × n, |w| = sin θ, a · n = cos θ
// ≥ 1/√3). On a surface along the frame's axes it is one of them; neighbours on a curved surface
// get nearly the same one.
vec3 tiltedTangent(vec3 n) {
  const vec3 m = abs(n);
  const uint axis = m.x >= m.y && m.x >= m.z ? 0u : (m.y >= m.z ? 1u : 2u);
  const float sign = n[axis] < 0.0 ? -1.0 : 1.0;
  vec3 a = vec3(0.0), first = vec3(0.0);
  a[axis] = sign;
  first[sign > 0.0 ? (axis + 1u) % 3u : (axis + 2u) % 3u] = 1.0;
  const vec3 w = cross(a, n);
  return dot(a, n) * first + cross(w, first) + w * (dot(w, first) / (1.0 + dot(a, n)));
}
uvec2 packBinFrame(vec3 normal, vec3 along) {
  return uvec2(packUnitVector(normal), packUnitVector(frameTangent(normal, along)));
}
mat3 binFrameOf(uvec2 packed) { return binFrame(unpackUnitVector(packed.x), unpackUnitVector(packed.y)); }

// A float's bits as a uint that orders as the float does (for atomicMin and atomicMax), and back.
uint orderedBits(float f) {
  const uint u = floatBitsToUint(f);
  return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float fromOrderedBits(uint u) { return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7FFFFFFFu : ~u); }
// A box kept as six orderedBits (min x, y, z, max x, y, z), as floats.
void fromOrderedBox(uint box[6], out vec3 lo, out vec3 hi) {
  lo = vec3(fromOrderedBits(box[0]), fromOrderedBits(box[1]), fromOrderedBits(box[2]));
  hi = vec3(fromOrderedBits(box[3]), fromOrderedBits(box[4]), fromOrderedBits(box[5]));
}

// Definitions shared by every ivgi compute shader. Their host twins live in engine/scene/geometry.h
// (layouts), engine/scene/texture_sampling.h (sampling) and engine/gi/shared.h (keys, rays); the
// test tests/shared_definitions_test.cpp runs the same cases through both.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

struct Vertex { vec3 position; uint instance; vec3 normal; uint local; uvec4 joints; vec4 weights; };
struct Instance { uint matrix; uint skinned; uint morphTargets; uint morphWeightBase; uint morphDeltaBase; uint vertexCount; uint pad0; uint pad1; };
struct MorphDelta { vec4 position; vec4 normal; };
struct Triangle { uint v0; uint v1; uint v2; uint material; };
struct Material { vec4 baseColor; vec4 emission; int baseColorTexture; int emissiveTexture; int pad0; int pad1; };
struct Texture { uint offset; uint width; uint height; uint wrap; };
struct SurfelSource { uint firstVertex; uint vertexCount; uint firstTriangle; uint triangleCount; };
struct WorldVertex { vec4 position; vec4 normal; };
struct Surfel { vec4 positionArea; vec4 normal; vec4 shape; };  // shape: as NodeState's

const uint kFlatShaded = 0x80000000u;
const uint kEmitterBit = 0x80000000u;  // on a sender in a receiver's list: it emits
const uint64_t kEmptyVisibility = 0xFFFFFFFFFFFFFFFFul;

// Pinhole camera: right and up are scaled by tan of the half field of view; origin.w = znear,
// forward.w = zfar (0: none). Image size in samples, pixel (0,0) top-left, centres at +0.5.
struct Camera { vec4 origin; vec4 right; vec4 up; vec4 forward; };

// Linear item index of a dispatch laid out over x then y (Program::dispatchItems).
uint itemIndex() {
  return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
}
uint groupIndex() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }

// Visibility key: depth (positive float bits order like unsigned integers) above the triangle id,
// so that 64-bit atomicMin keeps the nearest hit and breaks ties by the lower id.
uint64_t packDepthKey(float depth, uint id) { return (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id); }
uint keyId(uint64_t key) { return uint(key & 0xFFFFFFFFul); }
float keyDepth(uint64_t key) { return uintBitsToFloat(uint(key >> 32)); }

vec3 cameraRay(Camera cam, vec2 samplePos, uvec2 size) {
  vec2 ndc = vec2(2.0 * samplePos.x / float(size.x) - 1.0, 1.0 - 2.0 * samplePos.y / float(size.y));
  return cam.forward.xyz + ndc.x * cam.right.xyz + ndc.y * cam.up.xyz;
}

// Möller–Trumbore without culling; t along the unnormalised ray (= depth along forward).
// Barycentrics get a tiny negative slack so that shared edges leave no cracks.
bool intersectTriangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c, out float t, out vec2 uv) {
  vec3 e1 = b - a, e2 = c - a;
  vec3 p = cross(d, e2);
  float det = dot(e1, p);
  t = 0.0; uv = vec2(0.0);
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

// The two texels and the weight of the second along one axis of a bilinear lookup under a glTF wrap
// mode (33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, else REPEAT). No integer division: lavapipe
// runs it one lane at a time.
ivec2 texelPair(float u, int size, uint mode, out float weight) {
  if (mode == 33648u) {
    float t = fract(u * 0.5) * 2.0;
    u = t < 1.0 ? t : 2.0 - t;
  } else if (mode != 33071u) {
    u = fract(u);
  }
  float x = u * float(size) - 0.5, f = floor(x);
  weight = x - f;
  int i = int(f), j = i + 1;
  if (mode == 33071u || mode == 33648u) return clamp(ivec2(i, j), 0, size - 1);
  return ivec2(i < 0 ? i + size : i, j >= size ? j - size : j);
}

// ---- Direction bins, form factors, link keys (design.md §1.2) ----

const float kPi = 3.14159265358979;

// Cube-map bin of a non-zero direction: face = 2·axis + (negative ? 1 : 0), then (i, j) from the two
// other coordinates divided by the major one. Bins are numbered face·N² + j·N + i.
uint binOf(vec3 d, uint n) {
  vec3 a = abs(d);
  uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float major = axis == 0u ? d.x : (axis == 1u ? d.y : d.z);
  vec2 uv = axis == 0u ? d.yz : (axis == 1u ? d.zx : d.xy);
  uv /= abs(major);
  uvec2 ij = uvec2(clamp(floor((uv + 1.0) * 0.5 * float(n)), vec2(0.0), vec2(float(n - 1u))));
  uint face = 2u * axis + (major < 0.0 ? 1u : 0u);
  return face * n * n + ij.y * n + ij.x;
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

// Direction (unnormalised) through position uv of face `face`'s plane; beyond (−1, 1) the plane
// extends past the face, toward its neighbours.
vec3 faceDirection(uint face, vec2 uv) {
  float s = (face & 1u) == 0u ? 1.0 : -1.0;
  uint axis = face / 2u;
  if (axis == 0u) return vec3(s, uv.x, uv.y);
  if (axis == 1u) return vec3(uv.y, s, uv.x);
  return vec3(uv.x, uv.y, s);
}

// Centre direction (unnormalised, on the unit cube) of bin b.
vec3 binDirection(uint b, uint n) {
  uint face = b / (n * n), r = b % (n * n);
  return faceDirection(face, (vec2(float(r % n), float(r / n)) + 0.5) / float(n) * 2.0 - 1.0);
}

// Bin of cell (x, y) of face `face`'s plane, n cells a side: the face's own bin, or past its edge
// the bin of the neighbouring face that the cell's centre falls in.
uint binOfCell(uint face, ivec2 cell, uint n) {
  if (all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, ivec2(n)))) return face * n * n + uint(cell.y) * n + uint(cell.x);
  return binOf(faceDirection(face, (vec2(cell) + 0.5) / (0.5 * float(n)) - 1.0), n);
}

float cubeAreaIntegral(float u, float v) { return atan(u * v, sqrt(u * u + v * v + 1.0)); }

// Exact solid angle of bin b: Φ(u1,v1) − Φ(u0,v1) − Φ(u1,v0) + Φ(u0,v0).
float binSolidAngle(uint b, uint n) {
  uint r = b % (n * n);
  float step = 2.0 / float(n);
  float u0 = -1.0 + float(r % n) * step, v0 = -1.0 + float(r / n) * step;
  float u1 = u0 + step, v1 = v0 + step;
  return cubeAreaIntegral(u1, v1) - cubeAreaIntegral(u0, v1) - cubeAreaIntegral(u1, v0) + cubeAreaIntegral(u0, v0);
}

// Disk-to-point form factor: ≤ 1 and finite as d → 0.
float formFactor(float senderArea, float cosSender, float cosReceiver, float distance2) {
  return senderArea * max(cosSender, 0.0) * max(cosReceiver, 0.0) / (kPi * distance2 + senderArea);
}

// Link key: squared distance (positive float bits order as integers) above the sender node id, so
// that 64-bit atomicMin keeps the nearest sender per bin and breaks ties by id. The top bit marks a
// footprint's fringe (a bin it only brushes): fringes rank behind every core (a bin holding the
// footprint's centre or half covered by it), so a near sender's blur does not hide what lies beside it.
const uint64_t kFringeKey = 0x8000000000000000ul;
uint64_t packLinkKey(float distance2, uint sender, bool fringe) {
  return packDepthKey(distance2, sender) | (fringe ? kFringeKey : 0ul);
}
float linkKeyDepth(uint64_t key) { return keyDepth(key & ~kFringeKey); }

// ---- The surfel hierarchy and links (engine/gi/hierarchy.h, engine/gi/iv_solver.h) ----

struct TreeNode { int parent; uint firstChild; uint childCount; int surfel; };
// Per frame: area-weighted position and total area; normal and the half-angle of the cone holding
// every normal below; shape: x the radius of a sphere around the position holding every surfel disk
// below, y the angle of the node's rectangle in tangentFrame(normal), zw its half-extents.
struct NodeState { vec4 positionArea; vec4 normalCone; vec4 shape; };

// A tangent frame of unit normal n that depends on n alone (so that neighbours on a flat face agree).
void tangentFrame(vec3 n, out vec3 t1, out vec3 t2) {
  t1 = normalize(abs(n.x) < 0.9 ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
  t2 = cross(n, t1);
}

// lavapipe's loop budget. Mesa's gallivm, which compiles lavapipe's shaders (Mesa 22.3 here), counts
// the rounds of every loop a subgroup runs, all loops of the shader together, and once they reach
// 65,535 (LP_MAX_TGSI_LOOP_ITERATIONS, never reset while the subgroup runs) it ends each loop after
// one round, silently. Passes keep a subgroup's rounds below it: the rasteriser cuts large triangles
// into slices, one workgroup each; the gather's loops are bounded by a leaf's bins (at most
// 2·6·64² = 49,152); the prune probes whether its workgroup ran out (the frame is then redone with
// more subgroups a workgroup); the other passes loop a few thousand rounds at most.
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
layout(binding = NODE_TEXELS, rgba32f) readonly uniform imageBuffer nodeTexels;
vec4 nodePositionArea(uint i) { return imageLoad(nodeTexels, int(3u * i)); }
vec4 nodeNormalCone(uint i) { return imageLoad(nodeTexels, int(3u * i + 1u)); }
vec4 nodeShape(uint i) { return imageLoad(nodeTexels, int(3u * i + 2u)); }
float nodeRadius(uint i) { return nodeShape(i).x; }
NodeState nodeState(uint i) { return NodeState(nodePositionArea(i), nodeNormalCone(i), nodeShape(i)); }
#endif
struct LeafRange { uint first; uint count; };
// Leaf links live in texel buffers (their views reach past maxStorageBufferRange). LeafLink, a
// surviving link of a leaf, one rg32ui texel: sender node, bits of the clamped form factor.
// A bin's covered solid angle is counted in 1/kCoverageUnit of the bin's (integer sums do not
// depend on the order of the atomics).
const uint kCoverageUnit = 65536u;
// StaticBin, one r32ui texel beside each surviving link of a static leaf against static senders
// (made once), merged with a frame's moving senders: its bin (15 bits; 6·64² < 2^15) and the bin's
// covered solid angle capped at the whole bin (17 bits; coverage only counts up to the whole bin,
// so the cap changes nothing).
uint packStaticBin(uint bin, uint covered) { return bin | min(covered, kCoverageUnit) << 15; }
uint staticBinOf(uint packed) { return packed & 0x7FFFu; }
uint staticCoverageOf(uint packed) { return packed >> 15; }
// Indices into the solver's counter buffer.
// kCounterSendersWalked (low word, then the carries): the root-path senders a prune walked, its work.
const uint kCounterWorklistA = 0u, kCounterWorklistB = 1u, kCounterLinks = 2u, kCounterLeafLinks = 3u, kCounterOverflow = 4u,
           kCounterWorklistPeak = 5u, kCounterSendersWalked = 6u;
// Bits of counters[kCounterOverflow]: what a frame ran out of room for (it is redone with more).
// kOverflowLoopBudget: a prune workgroup ran out of lavapipe's loop budget (below); the frame is
// redone with more subgroups a workgroup.
const uint kOverflowWorklist = 1u, kOverflowLinks = 2u, kOverflowLeafLinks = 4u, kOverflowLoopBudget = 8u;
// KHR_lights_punctual, in world space for the frame. position.w: 0 directional, 1 point, 2 spot;
// direction: where the light points, w = range (0: none); cone: cos outer, cos inner.
struct PunctualLight { vec4 position; vec4 direction; vec4 intensity; vec4 cone; };

// Irradiance per unit intensity on a surface at p facing the light: 1/d², the range window, the
// spot cone (smooth between the outer and inner cosines). toLight is not normalised; dist2 is its
// squared length, 3.4e38 for a directional light. Mirrored by lightFalloff() in engine/gi/shared.h.
float lightFalloff(PunctualLight light, vec3 p, out vec3 toLight, out float dist2) {
  dist2 = 3.4e38;
  if (light.position.w == 0.0) {
    toLight = -light.direction.xyz;
    return 1.0;
  }
  toLight = light.position.xyz - p;
  dist2 = dot(toLight, toLight);
  if (dist2 <= 0.0) return 0.0;
  float falloff = 1.0 / dist2;
  if (light.direction.w > 0.0) {
    float window = clamp(1.0 - pow(sqrt(dist2) / light.direction.w, 4.0), 0.0, 1.0);
    falloff *= window * window;
  }
  if (light.position.w == 2.0) {
    float c = dot(normalize(-toLight), light.direction.xyz);
    float t = clamp((c - light.cone.x) / max(light.cone.y - light.cone.x, 1e-6), 0.0, 1.0);
    falloff *= t * t * (3.0 - 2.0 * t);
  }
  return falloff;
}

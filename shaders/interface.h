// What the host and the shaders share, written once: buffer layouts, constants, push-constant
// structs and the functions whose results both sides use (keys, bins, form factors, lights, rays).
// Included by GLSL (shaders/common.glsl) and by C++ (namespace ivgi::gpu, on glm), so that nothing
// is mirrored by hand. Only the common subset of the two languages goes here: no swizzles, float
// literals with an f, IVGI_OUT for out parameters. Structs are std430 and hold no vec3 that a
// scalar does not follow (C++ aligns vec3 to 4 bytes, std430 to 16).
#ifndef IVGI_SHADERS_INTERFACE_H
#define IVGI_SHADERS_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace ivgi::gpu {
using namespace glm;
using uint = uint32_t;
#define IVGI_CONST inline constexpr
#define IVGI_FN inline
#define IVGI_OUT(T) T&
#else
#define IVGI_CONST const
#define IVGI_FN
#define IVGI_OUT(T) out T
#endif

IVGI_CONST float kPi = 3.14159265358979f;

// Indirect dispatch size for `items` invocations of `size`, laid out over x then y (itemIndex()).
IVGI_FN uvec4 groupsFor(uint items, uint size) {
  const uint groups = (items + size - 1u) / size;
  return uvec4(min(groups, 65535u), (groups + 65534u) / 65535u, 1u, 0u);
}

// ---- Scene data (engine/scene/geometry.h builds it; animate, surfels, raster and resolve read it) ----

struct Vertex {
  vec3 position;  // rest pose, primitive space
  uint instance;
  vec3 normal;
  uint local;  // index inside its primitive, for morph deltas
  uvec4 joints;
  vec4 weights;
};
struct Instance {
  uint matrix;  // node world matrix, or first joint matrix when skinned
  uint skinned;
  uint morphTargets;
  uint morphWeightBase;
  uint morphDeltaBase;  // deltas of target k, vertex v at morphDeltaBase + k * vertexCount + v
  uint vertexCount;
  uint pad0;
  uint pad1;
};
struct MorphDelta {
  vec4 position;
  vec4 normal;
};
struct Triangle {
  uint v0;
  uint v1;
  uint v2;
  uint material;  // material index | kFlatShaded when the primitive has no normals
};
IVGI_CONST uint kFlatShaded = 0x80000000u;
struct Material {
  vec4 baseColor;
  vec4 emission;  // rgb: emissive factor × strength (radiance)
  int baseColorTexture;
  int emissiveTexture;
  int pad0;
  int pad1;
};
struct Texture {
  uint offset;  // in texels; each texel is linear RGBA as two packHalf2x16 words
  uint width;
  uint height;
  uint wrap;  // wrapS | wrapT << 16 (glTF enums)
  // KHR_texture_transform as an affine map of (u, v, 1): u' = dot(uvRowU.xyz, …), v' likewise (w unused).
  // A texture referenced with another transform is another record over the same texels.
  vec4 uvRowU;
  vec4 uvRowV;
};
struct SurfelSource {
  uint firstVertex;  // welded vertices, in Geometry::surfelVertices
  uint vertexCount;
  uint firstTriangle;  // adjacent non-degenerate triangles, in Geometry::surfelTriangles
  uint triangleCount;
};
struct WorldVertex {  // the animate pass's output
  vec4 position;
  vec4 normal;
};
struct Surfel {       // the surfel pass's output
  vec4 positionArea;  // centroid of the surfel's area, area
  vec4 normal;
  vec4 shape;  // as NodeState's: x the radius of a disk of its area, y the angle (0), zw half-extents
};

// Pinhole camera: right and up scaled by tan of the half field of view; origin.w = znear,
// forward.w = zfar (0: none). Image size in samples, pixel (0,0) top-left, centres at +0.5.
struct Camera {
  vec4 origin;
  vec4 right;
  vec4 up;
  vec4 forward;
};

// KHR_lights_punctual, in world space for the frame (engine/scene/lights.h).
struct PunctualLight {
  vec4 position;   // w: 0 directional, 1 point, 2 spot
  vec4 direction;  // where the light points; w: range (0: none)
  vec4 intensity;  // rgb: colour × intensity, radiometric
  vec4 cone;       // cos outer, cos inner
};
IVGI_CONST float kLightDirectional = 0.0f;
IVGI_CONST float kLightPoint = 1.0f;
IVGI_CONST float kLightSpot = 2.0f;

// ---- The surfel hierarchy (engine/gi/hierarchy.h) ----

struct TreeNode {
  int parent;       // -1 for a root
  uint firstChild;  // children are contiguous in the next level
  uint childCount;  // 0 for a leaf
  int surfel;       // the leaf's surfel, -1 for an inner node
};
// Per frame: area-weighted position and total area; normal and the half-angle of the cone holding
// every normal below; shape: x the radius of a sphere around the position holding every surfel
// disk below, y the angle of the node's rectangle in tangentFrame(normal), zw its half-extents.
struct NodeState {
  vec4 positionArea;
  vec4 normalCone;
  vec4 shape;
};

// ---- iv: links, leaf links, counters (engine/gi/iv/) ----

// A leaf's surviving links: where they start and how many.
struct LeafRange {
  uint first;
  uint count;
};
// A surviving link of a leaf: sender node and the bits of its clamped form factor (one rg32ui texel).
struct LeafLink {
  uint sender;
  uint formFactorBits;
};
IVGI_CONST uint kEmitterBit = 0x80000000u;  // on a sender in a receiver's list: it emits
// Per node, for the prune: it moves (its object may move: pruned every frame), its object's
// surface is closed (scene::closedInstances), and above kNodeRootShift its object's root node.
IVGI_CONST uint kNodeMoves = 1u;
IVGI_CONST uint kNodeClosed = 2u;
IVGI_CONST uint kNodeRootShift = 2u;
// Arrays that can outgrow one texel view (the leaf links grow with the bins squared) are bound as
// kTexelParts views of one buffer, each 2^texelPartBits texels (shaders/parted_texels.glsl, which
// names each view). Two: the prune binds four such arrays, and a push-descriptor layout holds at
// most 32 descriptors on lavapipe and NVIDIA alike.
IVGI_CONST uint kTexelParts = 2u;

// The slots of a link set's counter buffer. kCounterSendersWalked is the low word of a 64-bit
// count (the carries go to the next slot): the root-path senders a prune walked, its work.
IVGI_CONST uint kCounterWorklistA = 0u;
IVGI_CONST uint kCounterWorklistB = 1u;
IVGI_CONST uint kCounterLinks = 2u;
IVGI_CONST uint kCounterLeafLinks = 3u;
IVGI_CONST uint kCounterOverflow = 4u;
IVGI_CONST uint kCounterWorklistPeak = 5u;
IVGI_CONST uint kCounterSendersWalked = 6u;
IVGI_CONST uint kCounterGroupsDone = 8u;  // a refinement level's finished workgroups (refine_links)
IVGI_CONST uint kCounterSlots = 9u;
// Link creation's workgroups (refine_links, count_links, scatter_links) and its indirect dispatch
// sizes (uvec4 each in its args buffer): the next refinement level's, and the sort's (the links).
IVGI_CONST uint kLinkGroup = 256u;
IVGI_CONST uint kLinkArgsLevel = 0u;
IVGI_CONST uint kLinkArgsSort = 1u;
// The dispatch size for a list of `items`: along x alone, as link creation's shaders loop over what
// their workgroups cannot cover at once.
IVGI_FN uvec4 linkGroupsFor(uint items) { return uvec4(groupsFor(items, kLinkGroup).x, 1u, 1u, 0u); }
// Bits of counters[kCounterOverflow]: what a frame ran out of room for (it is redone with more).
// kOverflowLoopBudget: a prune workgroup ran out of lavapipe's loop budget (common.glsl).
IVGI_CONST uint kOverflowWorklist = 1u;
IVGI_CONST uint kOverflowLinks = 2u;
IVGI_CONST uint kOverflowLeafLinks = 4u;
IVGI_CONST uint kOverflowLoopBudget = 8u;

// The prune's shared-memory queues: root-path senders gathered per round (also the most that can
// be wide), emitters a leaf lists, and emitters a static leaf keeps for the frames.
IVGI_CONST uint kPathChunk = 512u;
IVGI_CONST uint kEmitterQueue = 256u;
IVGI_CONST uint kStaticEmitters = 64u;
IVGI_CONST uint kManyEmitters = 0xFFFFFFFFu;  // a static leaf's emitters that did not fit its list
// What a static leaf keeps of its static survivors between frames (prune_bins.comp): the
// environment through its static bins, the emission those bins credited (taken back where its
// emitters' direct light stands for it), the proximity of what they show, and how many emitters it
// lists (kManyEmitters: too many to list).
struct StaticLeaf {
  vec4 environment;
  vec4 correction;
  float proximity;
  uint emitterCount;
  uint pad0;
  uint pad1;
};

// Mask words of a leaf's 6·N² bins, one bit a bin.
IVGI_FN uint maskWordsFor(uint n) { return (6u * n * n + 31u) / 32u; }

// ---- iv: receivers (engine/gi/iv/receivers.h) ----

// Irradiance is solved at receivers, surfels chosen each frame where the lighting needs them, and
// interpolated to every other surfel. Slots of the receivers' counter buffer:
IVGI_CONST uint kReceiverCandidatesA = 0u;  // the two candidate lists of the refinement rounds
IVGI_CONST uint kReceiverCandidatesB = 1u;
IVGI_CONST uint kReceiverCount = 2u;       // receivers listed so far this frame
IVGI_CONST uint kReceiverRound = 3u;       // the first receiver listed in this round
IVGI_CONST uint kReceiverFills = 4u;       // surfels that no receiver's support reached, made receivers
IVGI_CONST uint kReceiverScale = 5u;       // the largest irradiance gathered (luminance bits)
IVGI_CONST uint kReceiverGroupsDone = 6u;  // workgroups of a round's step that finished
IVGI_CONST uint kReceiverSlots = 8u;
// A surfel's support radius as float bits: +inf while it is not a receiver (atomicMin lists it once).
IVGI_CONST uint kNotReceiver = 0x7F800000u;
// The most receivers a surfel's irradiance is interpolated from (those of largest weight), and the
// most nodes whose receivers may weigh for some surfel of a group of neighbours (listed per group; a
// group with more has its surfels search on their own).
IVGI_CONST uint kInterpolationTaps = 16u;
IVGI_CONST uint kGroupNeighbours = 256u;
// Invocations a workgroup of the dispatches over receivers and candidates: a round lists few, and
// lavapipe runs a workgroup on one thread, so small workgroups keep every thread busy.
IVGI_CONST uint kReceiverGroup = 8u;
// Dispatch arguments of the receivers (shaders/receiver_args.glsl), in order: the round's
// candidates, the round's new receivers, every receiver, then one per prune batch over the new
// receivers.
IVGI_CONST uint kArgsCandidates = 0u;
IVGI_CONST uint kArgsNewReceivers = 1u;
IVGI_CONST uint kArgsReceivers = 2u;
IVGI_CONST uint kArgsPruneBatches = 3u;
// What receiver_args.comp does, as bits of its mode.
IVGI_CONST uint kArgsStartRound = 1u;  // the candidates' dispatch; the round's receivers start here
IVGI_CONST uint kArgsListed = 2u;      // the dispatches over the new and over every receiver

// A sampled node's receiver (its representative) stands for it in the interpolation: its support
// reaches kReceiverReach times the node's radius, and its weight at a surfel falls from a peak to 0
// over it (distances across the surfel's tangent plane count kReceiverPlaneStretch times) and with
// the angle between their normals, to 0 at kReceiverNormalCos.
IVGI_CONST float kReceiverReach = 2.5f;
IVGI_CONST float kReceiverNormalCos = 0.7f;
IVGI_CONST float kReceiverPlaneStretch = 4.0f;

// Refinement is continuous in what it judges by, so that a small change (a frame later, a scaled
// scene) changes the image a little: each sampled node has a need, the largest of its tests'
// statistics over their thresholds; its children are sampled once the need passes kRefineFrom, and
// they take over its place in the interpolation gradually, fully at 1. A node's presence is the
// product of refinementShare over its ancestors' needs (0: not sampled); its own share of that,
// its role, is what its children have not taken.
IVGI_CONST float kRefineFrom = 0.75f;
IVGI_FN float refinementShare(float need) { return clamp((need - kRefineFrom) / (1.0f - kRefineFrom), 0.0f, 1.0f); }

struct InterpolationTap {  // one rg32ui texel: the receiver, the bits of its coefficient
  uint receiver;
  uint weightBits;
};

// ---- Push constants, one struct a pass ----

struct CountPush {  // animate, surfels, emit, pull_up: the items; count_links, scatter_links: the link capacity
  uint count;
};
struct LevelPush {  // the nodes of one level of the trees
  uint first;
  uint count;
};
struct QueueArgsPush {
  uint slot;  // which dispatch arguments to write
};
struct RefinePush {
  uint source;  // counter slots of this level's list and of the next
  uint target;
  uint capacity;  // of each worklist
  uint linkCapacity;
  float epsilon;        // form-factor threshold
  float largeSender;    // κ·Ω of a bin: a sender subtending more is split
  float largeReceiver;  // and a receiver subtending more from its sender (3.4e38: never)
  uint bothSides;       // 1: senders behind the receiver's horizon are linked too (|cos| estimates)
  // A receiver subtending more than this from an emitting sender (nodeEmission nonzero) is split
  // (0: down to its surfels).
  float emitterReceiver;
  uint receiverStaysWhole;  // 1: a pair whose sender is a leaf is stored, however large its receiver
};
struct PrunePush {
  uint firstSurfel;  // the leaves [firstSurfel, endSurfel) of this dispatch's batch; listed: of the
  uint endSurfel;    // round's new receivers
  uint listed;
  uint linkCapacity;
  uint lightCount;
  uint environmentOn;
  uint staticCapacity;
};
struct GatherPush {
  uint maskWords;
  uint newOnly;  // 1: the round's new receivers; 0: every receiver listed
  uint pad;
};
struct ReceiverArgsPush {
  uint mode;    // kArgsStartRound | kArgsListed
  uint source;  // the round's candidate list (counter slot)
  uint target;  // the next round's, emptied
  uint batch;   // receivers a prune batch takes
  uint leavesPerGroup;
  uint maxGroups;  // of a prune batch
  uint batches;    // prune batches recorded a round
  uint pad;
};
struct ReceiverPush {
  uint source;      // candidate list (counter slot) read
  uint target;      // candidate list written
  float tolerance;  // --receiver-tol: how far a sample may miss its prediction from its neighbours
  float proximity;  // a node's support may reach this share of the mean distance to what its receiver sees
  uint nodeCount;
  uint surfelCount;
  float floorShare;  // a sample darker than this share of the largest is judged against that
  uint groupCount;   // of neighbour lists
  float largest;     // the largest radius a cell may have
  // The prune's batching (Prune::Batching), for the dispatch sizes over the receivers listed.
  uint batch, leavesPerGroup, maxGroups, batches;
};
struct InterpolatePush {
  uint surfelCount;
};
// The bounces stop where the light, with the geometric tail of the bounces not run added, settles
// within a tolerance (or after a count): the interpolation leaves per workgroup the area-weighted
// luminance of its leaves' radiosity and of its change, and bounce_check sums them in a fixed order,
// decides, and writes the next bounce's dispatch sizes (zero groups once it is done) and the tail's.
struct BounceSum {
  float total;   // Σ area · Y(B)
  float change;  // Σ area · |Y(B) − Y(B before)|
};
struct BounceState {
  uint gathers;     // run so far this frame (K bounces are K + 1 gathers)
  uint done;        // 1: converged or at the count
  float change;     // of the last gather
  float total;      // after the last gather
  float remaining;  // how far the light with its tail may still be off, over total (bounce_check.comp)
  float gain;       // the tail's factor q/(1 − q) (0: none), q the ratio of the last two changes
  float estimate;   // the light with its tail: total + change · gain
  float step;       // how much that estimate moved at the last gather, over total
  float least;      // the least change from the second gather on
  uint diverged;    // 1: stopped where a change grew past kDivergingGrowth times that least
};
// Each bounce adds less light than the one before wherever albedo is below 1 (a convergent
// transport); a change this many times the least before it, and past kDivergingFloor of the light,
// means the bounces diverge. Below that floor the changes are the float sums' own jitter (a count
// forced far past convergence), which may double.
IVGI_CONST float kDivergingGrowth = 2.0f;
IVGI_CONST float kDivergingFloor = 1e-4f;
struct BounceCheckPush {
  uint groups;      // of the interpolation: BounceSums to add up
  uint dispatches;  // of a bounce: the gather, the interpolation, then one pull-up a level; the tail's after them
  uint maxGathers;  // done after this many
  float tolerance;  // done where remaining ≤ tolerance, and the tail added; negative: only at maxGathers, no tail
};
// ---- ar (engine/gi/ar/): directional tables of 6·N² world bins per node or surfel ----

// Pieces per side a near or wide surfel sender is cut into at most (the gather's loops stay far
// below lavapipe's budget: common.glsl).
IVGI_CONST uint kArPieces = 2u;

// Solid angle per unit area of a sender of area `area` at squared distance `dist2`: that of a disk
// of its area seen on its axis, 2π(1 − 1/√(1 + a/(π d²)))/a, finite as d → 0 and 1/d² far away.
IVGI_FN float solidAnglePerArea(float area, float dist2) {
  const float x = area / (kPi * dist2);
  if (x < 1e-4f) return 1.0f / dist2 * (1.0f - 0.75f * x);  // the series: no cancellation
  return 2.0f * kPi * (1.0f - inversesqrt(1.0f + x)) / area;
}

// The pieces per side the global pass cuts a surfel sender of area `area` at squared distance
// `dist2` into under bins of `n` per face's side: one wider than a bin, or near, goes as k×k pieces
// of its rectangle, each along its own direction (one direction would stand for a spread of them,
// and the disk for a nearby square).
IVGI_FN uint surfelPieces(float area, float dist2, uint n) {
  const float binWidth = 2.0f / float(n);  // of a bin at a face's centre, in the face's plane
  const float width = sqrt(solidAnglePerArea(area, dist2) * area) / binWidth;
  return dist2 <= 4.0f * (area / kPi) ? kArPieces : uint(clamp(ceil(width), 1.0f, float(kArPieces)));
}

// A receiver's senders in the order the global pass walks them, so that the lanes walking
// neighbouring receivers' lists side by side take links of the same kind at the same step (a
// lane's longer link holds up the rest): the clusters first, then the surfels by pieces, most
// first; within a kind by node. The key keeps the emitter bit where the sender has it, the kind in
// the bits below, the node in the rest: the ar solver takes at most 2^kArKindShift nodes.
IVGI_CONST uint kArKindShift = 29u;
IVGI_CONST uint kArNodeMask = (1u << kArKindShift) - 1u;
IVGI_FN uint linkKind(bool cluster, float senderArea, float dist2, uint n) {
  return cluster ? 0u : 1u + kArPieces - surfelPieces(senderArea, dist2, n);
}
IVGI_FN uint walkKey(uint sender, uint kind) {
  return (sender & kEmitterBit) | (kind << kArKindShift) | (sender & kArNodeMask);
}
// Keys compare without the emitter bit; the lists hold the senders (without their kind).
IVGI_FN bool walkedBefore(uint keyA, uint keyB) { return (keyA & ~kEmitterBit) < (keyB & ~kEmitterBit); }
IVGI_FN uint senderOfKey(uint key) { return key & (kEmitterBit | kArNodeMask); }
// The most links of a receiver's list one dispatch of the global pass walks: a link takes at most
// 1 + kArPieces² loop rounds, so that a chunk stays within lavapipe's loop budget (common.glsl).
// Longer lists take more dispatches, each going on where the one before stopped.
IVGI_CONST uint kArGatherChunk = 8192u;
// ar_sort_senders sorts a list of at most this many senders in one invocation; longer ones get a
// workgroup each (ar_sort_long_senders).
IVGI_CONST uint kArShortList = 64u;
// The longest list ar_sort_long_senders orders within lavapipe's loop budget, and the bits of the
// flags the global pass and the sort leave (ArBuffers::gatherFlags): a list longer than the chunks
// recorded walk (the frame is redone in more), a list too long to sort (the solve stops).
IVGI_CONST uint kArSortedMost = 32768u;
IVGI_CONST uint kArFlagChunks = 1u;
IVGI_CONST uint kArFlagUnsorted = 2u;
// The global pass's workgroup size, whose blocks of nodes ar_order_receivers orders.
IVGI_CONST uint kArGatherGroup = 64u;
// The global pass keeps a receiver's table in each invocation up to this many bins (--dirs 8).
IVGI_CONST uint kArGatherTableHere = 384u;
// A node whose normals spread less than this (radians) counts as flat: one plane, a front and a back.
IVGI_CONST float kArFlatCone = 0.05f;
// The asymmetric scheme's antiradiance steps after each radiance step.
IVGI_CONST uint kAntiradianceSteps = 3u;
// Per workgroup of ar_incident, what the host judges an iteration by (area-weighted luminances).
struct IterationSum {
  float total;     // Σ area · Y(E), E ≥ 0 the irradiance shown
  float change;    // Σ area · |Y(E) − Y(E before)|
  float negative;  // Σ area · Y(max(−E, 0)): light cancelled past zero
  float pad;
};
struct ArPush {
  // the items: surfels (local, incident), nodes (gather), a level's inner nodes × bins (pull-up) or
  // its inner nodes (sum-down)
  uint count;
  uint bins;   // N: 6·N² bins
  uint first;  // pull-up, sum-down: the level's first in the inner nodes; incident: the sums' slot; gather: the chunk
  uint updateRadiance;  // local: 1 to reflect the incident light (a radiance step), 0 to keep the radiance
  uint lightCount;
  uint environmentOn;
  uint chunks;      // gather: the chunks recorded (a list longer than they walk is flagged)
  uint chunkLinks;  // gather: the links of a list a chunk walks (kArGatherChunk but in tests)
  // incident: the share ω of an iteration's step that is taken (1: all of it; less damps an
  // iteration that diverges): each surfel's incident table and irradiance go ω of the way to the new.
  float damping;
};

struct ImagePush {  // raster: count = triangles; resolve: count = samples per axis
  Camera camera;
  uvec2 size;
  uint count;
  uint pad;
};

// ---- Keys for 64-bit atomicMin ----

IVGI_CONST uint64_t kEmptyVisibility = 0xFFFFFFFFFFFFFFFFul;

// Visibility key: depth (positive float bits order like unsigned integers) above the id, so that
// 64-bit atomicMin keeps the nearest hit and breaks ties by the lower id.
IVGI_FN uint64_t packDepthKey(float depth, uint id) { return (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id); }
IVGI_FN uint keyId(uint64_t key) { return uint(key & 0xFFFFFFFFul); }
IVGI_FN float keyDepth(uint64_t key) { return uintBitsToFloat(uint(key >> 32)); }

// Link key: squared distance above the sender node, so that atomicMin keeps the nearest sender per
// bin and breaks ties by id. The top bit marks a footprint's fringe (a bin it only brushes):
// fringes rank behind every core (a bin holding the footprint's centre or half covered by it), so
// that a near sender's blur does not hide what lies beside it.
IVGI_CONST uint64_t kFringeKey = 0x8000000000000000ul;
IVGI_FN uint64_t packLinkKey(float distance2, uint sender, bool fringe) {
  return packDepthKey(distance2, sender) | (fringe ? kFringeKey : 0ul);
}
IVGI_FN float linkKeyDepth(uint64_t key) { return keyDepth(key & ~kFringeKey); }

// A bin's covered solid angle is counted in 1/kCoverageUnit of the bin's (integer sums do not depend
// on the order of the atomics).
IVGI_CONST uint kCoverageUnit = 65536u;
// StaticBin, one r32ui texel beside each surviving link of a static leaf: its bin (15 bits;
// 6·64² < 2^15) and the bin's covered solid angle capped at the whole bin (17 bits; coverage only
// counts up to the whole bin, so the cap changes nothing).
IVGI_FN uint packStaticBin(uint bin, uint covered) { return bin | min(covered, kCoverageUnit) << 15; }
IVGI_FN uint staticBinOf(uint packed) { return packed & 0x7FFFu; }
IVGI_FN uint staticCoverageOf(uint packed) { return packed >> 15; }

// ---- Camera rays ----

IVGI_FN vec3 cameraRay(Camera cam, vec2 samplePos, uvec2 size) {
  vec2 ndc = vec2(2.0f * samplePos.x / float(size.x) - 1.0f, 1.0f - 2.0f * samplePos.y / float(size.y));
  return vec3(cam.forward) + ndc.x * vec3(cam.right) + ndc.y * vec3(cam.up);
}

// ---- Textures ----

// The texture coordinates a lookup of texture t reads at uv: its KHR_texture_transform applied.
IVGI_FN vec2 transformedUv(Texture t, vec2 uv) {
  vec3 h = vec3(uv.x, uv.y, 1.0f);
  return vec2(dot(vec3(t.uvRowU.x, t.uvRowU.y, t.uvRowU.z), h), dot(vec3(t.uvRowV.x, t.uvRowV.y, t.uvRowV.z), h));
}

// The two texels and the weight of the second along one axis of a bilinear lookup under a glTF wrap
// mode (33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, else REPEAT). No integer division: lavapipe
// runs it one lane at a time.
IVGI_FN ivec2 texelPair(float u, int size, uint mode, IVGI_OUT(float) weight) {
  if (mode == 33648u) {
    float t = fract(u * 0.5f) * 2.0f;
    u = t < 1.0f ? t : 2.0f - t;
  } else if (mode != 33071u) {
    u = fract(u);
  } else {
    u = clamp(u, 0.0f, 1.0f);  // the same texels, and no integer overflow far outside
  }
  float x = u * float(size) - 0.5f, f = floor(x);
  weight = x - f;
  int i = int(f), j = i + 1;
  if (mode == 33071u || mode == 33648u) return clamp(ivec2(i, j), 0, size - 1);
  return ivec2(i < 0 ? i + size : i, j >= size ? j - size : j);
}

// ---- Direction bins and form factors (docs/design.md §5) ----

// Cube-map bin of a non-zero direction: face = 2·axis + (negative ? 1 : 0), then (i, j) from the two
// other coordinates divided by the major one. Bins are numbered face·N² + j·N + i.
IVGI_FN uint binOf(vec3 d, uint n) {
  vec3 a = abs(d);
  uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float major = axis == 0u ? d.x : (axis == 1u ? d.y : d.z);
  vec2 uv = axis == 0u ? vec2(d.y, d.z) : (axis == 1u ? vec2(d.z, d.x) : vec2(d.x, d.y));
  uv /= abs(major);
  uvec2 ij = uvec2(clamp(floor((uv + 1.0f) * 0.5f * float(n)), vec2(0.0f), vec2(float(n - 1u))));
  uint face = 2u * axis + (major < 0.0f ? 1u : 0u);
  return face * n * n + ij.y * n + ij.x;
}

// Direction (unnormalised) through position uv of face `face`'s plane; beyond (−1, 1) the plane
// extends past the face, toward its neighbours.
IVGI_FN vec3 faceDirection(uint face, vec2 uv) {
  float s = (face & 1u) == 0u ? 1.0f : -1.0f;
  uint axis = face / 2u;
  if (axis == 0u) return vec3(s, uv.x, uv.y);
  if (axis == 1u) return vec3(uv.y, s, uv.x);
  return vec3(uv.x, uv.y, s);
}

// Centre direction (unnormalised, on the unit cube) of bin b.
IVGI_FN vec3 binDirection(uint b, uint n) {
  uint face = b / (n * n), r = b % (n * n);
  return faceDirection(face, (vec2(float(r % n), float(r / n)) + 0.5f) / float(n) * 2.0f - 1.0f);
}

// The bin opposite bin b (binOf(−binDirection(b))): the face of the other sign, its cell mirrored.
IVGI_FN uint oppositeBin(uint b, uint n) {
  uint perFace = n * n;
  return (b / perFace ^ 1u) * perFace + perFace - 1u - b % perFace;
}

// Bin of cell (x, y) of face `face`'s plane, n cells a side: the face's own bin, or past its edge
// the bin of the neighbouring face that the cell's centre falls in.
IVGI_FN uint binOfCell(uint face, ivec2 cell, uint n) {
  if (all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, ivec2(n))))
    return face * n * n + uint(cell.y) * n + uint(cell.x);
  return binOf(faceDirection(face, (vec2(cell) + 0.5f) / (0.5f * float(n)) - 1.0f), n);
}

IVGI_FN float cubeAreaIntegral(float u, float v) { return atan(u * v, sqrt(u * u + v * v + 1.0f)); }

// Exact solid angle of bin b: Φ(u1,v1) − Φ(u0,v1) − Φ(u1,v0) + Φ(u0,v0). GLSL's atan is an
// approximation: the solver builds its table of bins on the host.
IVGI_FN float binSolidAngle(uint b, uint n) {
  uint r = b % (n * n);
  float step = 2.0f / float(n);
  float u0 = -1.0f + float(r % n) * step, v0 = -1.0f + float(r / n) * step;
  float u1 = u0 + step, v1 = v0 + step;
  return cubeAreaIntegral(u1, v1) - cubeAreaIntegral(u0, v1) - cubeAreaIntegral(u1, v0) + cubeAreaIntegral(u0, v0);
}

// Disk-to-point form factor: at most 1, and finite as d → 0.
IVGI_FN float formFactor(float senderArea, float cosSender, float cosReceiver, float distance2) {
  return senderArea * max(cosSender, 0.0f) * max(cosReceiver, 0.0f) / (kPi * distance2 + senderArea);
}

// A tangent frame of unit normal n that depends on n alone (so that neighbours on a flat face agree).
IVGI_FN void tangentFrame(vec3 n, IVGI_OUT(vec3) t1, IVGI_OUT(vec3) t2) {
  t1 = normalize(abs(n.x) < 0.9f ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
  t2 = cross(n, t1);
}

// Direction d in the tangent frame (t1, t2) as its angle times four (a right angle a full turn),
// weighted by its length there: summed over a grid's edges, or over elements' axes, it gives their
// common orientation modulo a right angle (quarterAngle), whatever the grid's rotation.
IVGI_FN vec2 quarterTurns(vec3 d, vec3 t1, vec3 t2) {
  float x = dot(d, t1), y = dot(d, t2), r2 = x * x + y * y;
  if (r2 <= 0.0f) return vec2(0.0f);
  float c2 = (x * x - y * y) / r2, s2 = 2.0f * x * y / r2;  // the angle doubled
  return sqrt(r2) * vec2(c2 * c2 - s2 * s2, 2.0f * c2 * s2);
}
IVGI_FN float quarterAngle(vec2 sum) { return length(sum) > 0.0f ? 0.25f * atan(sum.y, sum.x) : 0.0f; }
// quarterTurns() of the three edges of triangle abc.
IVGI_FN vec2 edgeQuarterTurns(vec3 a, vec3 b, vec3 c, vec3 t1, vec3 t2) {
  return quarterTurns(b - a, t1, t2) + quarterTurns(c - b, t1, t2) + quarterTurns(a - c, t1, t2);
}

// The axes of a rectangle (a surfel's, a node's) turned by `angle` in the tangent frame of n.
IVGI_FN void rectangleAxes(vec3 n, float angle, IVGI_OUT(vec3) u1, IVGI_OUT(vec3) u2) {
  vec3 t1, t2;
  tangentFrame(n, t1, t2);
  float c = cos(angle), s = sin(angle);
  u1 = c * t1 + s * t2;
  u2 = c * t2 - s * t1;
}

// ---- Punctual lights ----

// Irradiance per unit intensity on a surface at p facing the light: 1/d², the range window, the
// spot cone (smooth between the outer and inner cosines). toLight is not normalised; dist2 is its
// squared length, 3.4e38 for a directional light.
IVGI_FN float lightFalloff(PunctualLight light, vec3 p, IVGI_OUT(vec3) toLight, IVGI_OUT(float) dist2) {
  dist2 = 3.4e38f;
  if (light.position.w == kLightDirectional) {
    toLight = -vec3(light.direction);
    return 1.0f;
  }
  toLight = vec3(light.position) - p;
  dist2 = dot(toLight, toLight);
  if (dist2 <= 0.0f) return 0.0f;
  float falloff = 1.0f / dist2;
  if (light.direction.w > 0.0f) {
    float window = clamp(1.0f - pow(sqrt(dist2) / light.direction.w, 4.0f), 0.0f, 1.0f);
    falloff *= window * window;
  }
  if (light.position.w == kLightSpot) {
    float c = dot(normalize(-toLight), vec3(light.direction));
    float t = clamp((c - light.cone.x) / max(light.cone.y - light.cone.x, 1e-6f), 0.0f, 1.0f);
    falloff *= t * t * (3.0f - 2.0f * t);
  }
  return falloff;
}

#ifdef __cplusplus
static_assert(sizeof(Vertex) == 64 && sizeof(Instance) == 32 && sizeof(Material) == 48 && sizeof(Surfel) == 48);
static_assert(sizeof(NodeState) == 48 && sizeof(PunctualLight) == 64 && sizeof(ImagePush) == 80);
#undef IVGI_CONST
#undef IVGI_FN
#undef IVGI_OUT
}  // namespace ivgi::gpu
#endif

#endif

#version 460
// Pass 5, bin pruning and push-down: each leaf takes the links of itself and of all its ancestors,
// re-bins them from its own position into 6×N×N direction bins and keeps the nearest sender per bin
// (64-bit atomicMin on distance², sender; senders centred in the bin rank ahead of those whose
// footprint only brushes it); everything farther in a bin is occluded. The links along
// a leaf's root path partition every other surface once, so the solid angles they subtend also say
// how much of each bin is covered; the survivor stands for that covered part:
// F = cos θr · min(Ω_bin, Ω_covered) / π (a hemisphere never sums above 1). Survivors are written
// in bin order. Punctual lights, the environment and emitters' direct light (each emitter's own
// form factor, not the whole bins it would win) are tested against the same bins. Bins live in
// shared memory where they fit, else in a global slot per workgroup; each workgroup walks many
// leaves and resets only the bins it touched.
//
// Objects that cannot move are linked and pruned once (the static pass, over the links between
// them); every frame (the frame pass) a moving leaf is pruned in full from the links of the pairs
// with a moving side, and a static leaf files only those and merges the bins they touch with its
// static bins: nearest key and summed coverage as a full prune would find them. Its touched bins
// are re-emitted and flagged in an override mask that the gather reads to skip the static entries.
// A static leaf also keeps the emitters of its static links, whose direct light each frame tests
// against the merged bins (a moving block may hide them).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 1
#include "common.glsl"
#include "parted_texels.glsl"
// As few subgroups a workgroup as lavapipe's loop budget allows (engine/gi/iv/prune.cpp): lavapipe
// runs a workgroup's subgroups one after another on one thread, switching at every barrier.
layout(local_size_x_id = 8) in;
const uint kGroupSize = gl_WorkGroupSize.x;  // a multiple of 8

layout(constant_id = 0) const uint kN = 16;  // bins per face side
layout(constant_id = 1) const bool kSharedBins = true;
layout(constant_id = 2) const uint kSharedSlots = 1536;  // 6·N² on the shared path, else 1
layout(constant_id = 3) const uint kMaskWords = 48;      // ⌈6·N² / 32⌉
layout(constant_id = 4) const bool kStaticPass = false;  // prune static leaves against static links, once

layout(binding = 0, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(binding = 2, r32ui) readonly uniform uimageBuffer starts;
layout(binding = 3, r32ui) readonly uniform uimageBuffer senders;  // kEmitterBit marks emitters
layout(binding = 4, r32ui) readonly uniform uimageBuffer leafOfSurfel;
// ∫ω dω over the bin (its cosine-weighted solid angle is n·∫ω dω, exact wherever the bin lies wholly
// above the horizon, so that a hemisphere's bins never sum above π), solid angle
layout(binding = 5, rgba32f) readonly uniform imageBuffer binTable;
layout(std430, binding = 6) buffer GlobalBins { uint64_t globalBins[]; };
layout(std430, binding = 7) writeonly buffer Ranges { LeafRange ranges[]; };
// The leaf links are texel buffers bound in parts (parted_texels.glsl): they reach past one view's
// maxTexelBufferElements (2^27 on lavapipe, 1 GiB of links) and one storage binding's range.
layout(binding = 8, rg32ui) writeonly uniform uimageBuffer leafLinks[kTexelParts];  // LeafLink
layout(std430, binding = 9) buffer Counters { uint counters[]; };
// irradiance from lights and environment
layout(std430, binding = 10) writeonly buffer ExternalLight { vec4 externalLight[]; };
layout(std430, binding = 11) readonly buffer Lights { PunctualLight lights[]; };
layout(binding = 12, rgba32f) readonly uniform imageBuffer environment;  // radiance per bin
layout(std430, binding = 13) buffer GlobalCoverage { uint globalCoverage[]; };
layout(binding = 14, r32ui) readonly uniform uimageBuffer nodeFlags;  // per node: kNodeMoves, kNodeClosed, root
// The static pass writes these; the frame pass reads them.
layout(std430, binding = 15) buffer StaticRanges { LeafRange staticRanges[]; };
layout(binding = 16, rg32ui) uniform uimageBuffer staticLinks[kTexelParts];  // LeafLink
layout(binding = 17, r32ui) uniform uimageBuffer staticBins[kTexelParts];    // StaticBin: bin and coverage, packed
// the key's upper half (fringe bit, d²), beside the link
layout(binding = 18, r32ui) uniform uimageBuffer staticDepths[kTexelParts];
// per leaf and mask word: bins held, entries before
layout(std430, binding = 19) buffer StaticMasks { uvec2 staticMasks[]; };
layout(std430, binding = 20) buffer StaticLeaves { StaticLeaf staticLeaves[]; };
// per static leaf and mask word: bins re-emitted
layout(std430, binding = 21) writeonly buffer Overrides { uint overrides[]; };
layout(binding = 22, rgba32f) readonly uniform imageBuffer nodeEmission;  // π·Le per node, pulled up
// per static leaf: the emitters of its static links
layout(std430, binding = 23) buffer StaticEmitters { uint staticEmitters[]; };
// the static set's (the frame pass merges its bins)
layout(std430, binding = 24) readonly buffer StaticCounters { uint staticCounters[]; };
// Listed: the round's new receivers (receivers from the round's start in the receivers' counters).
layout(binding = 25, r32ui) readonly uniform uimageBuffer receivers;
layout(std430, binding = 26) readonly buffer ReceiverCounts { uint receiverCounts[]; };
// Per leaf: how near what it sees is, Σ cos θ·ω / (π·d) over its survivors, the inverse of the
// harmonic mean distance (the receivers' refinement reads it).
layout(std430, binding = 27) writeonly buffer Proximity { float proximity[]; };
layout(push_constant) uniform Push { PrunePush push; };

shared uint64_t sharedBins[kSharedSlots];
shared uint sharedCoverage[kSharedSlots];  // covered solid angle in 1/kCoverageUnit of the bin's
shared uint mask[kMaskWords], grown[kMaskWords];
shared uint wordStart[kMaskWords];
shared vec3 partial[kGroupSize];
shared uint leafBase;
shared uint pathChunk[kPathChunk], wideQueue[kPathChunk];
shared uint wideCount;
shared uint emitterQueue[kEmitterQueue], sortedEmitters[kEmitterQueue];
shared uint emitterCount;

const uint kBinCount = 6u * kN * kN;

uint64_t loadBin(uint slot, uint b) { return kSharedBins ? sharedBins[b] : globalBins[slot + b]; }
uint64_t minBin(uint slot, uint b, uint64_t key) {
  return kSharedBins ? atomicMin(sharedBins[b], key) : atomicMin(globalBins[slot + b], key);
}
void addCoverage(uint slot, uint b, uint amount) {
  if (kSharedBins)
    atomicAdd(sharedCoverage[b], amount);
  else
    atomicAdd(globalCoverage[slot + b], amount);
}
uint loadCoverage(uint slot, uint b) { return kSharedBins ? sharedCoverage[b] : globalCoverage[slot + b]; }
void resetBin(uint slot, uint b) {
  if (kSharedBins)
    sharedBins[b] = kEmptyVisibility, sharedCoverage[b] = 0u;
  else
    globalBins[slot + b] = kEmptyVisibility, globalCoverage[slot + b] = 0u;
}

// The leaf being pruned (the same in every invocation of the workgroup): whether it merges the
// frame's senders into its static bins, where its static survivors start, where its mask words start.
bool merging = false;
uint staticFirst = 0u, maskBase = 0u;

// What bin b holds: the nearest key and the covered solid angle (in 1/kCoverageUnit of the bin),
// the filed senders merged with the leaf's static entry; staticCovered is that entry's share.
struct Bin {
  uint64_t key;
  uint covered;
  uint staticCovered;
  int staticEntry;
  float staticDistance2;
};

// The leaf's static entry for bin b, or −1: none, not merging, or past a static pass that overflowed
// (the frame is then redone).
int staticEntryOf(uint b) {
  if (!merging) return -1;
  uvec2 word = staticMasks[maskBase + b / 32u];
  uint bit = 1u << (b & 31u);
  if ((word.x & bit) == 0u) return -1;
  uint e = staticFirst + word.y + bitCount(word.x & (bit - 1u));
  return e < push.staticCapacity ? int(e) : -1;
}

Bin binAt(uint slot, uint b) {
  Bin bin = Bin(loadBin(slot, b), loadCoverage(slot, b), 0u, -1, 0.0);
  int e = staticEntryOf(b);
  if (e < 0) return bin;
  const uint entry = uint(e);
  uint staticDepth = loadParted(staticDepths, entry).x;
  bin.key = min(bin.key, uint64_t(staticDepth) << 32 | loadParted(staticLinks, entry).x);
  bin.staticDistance2 = uintBitsToFloat(staticDepth & 0x7FFFFFFFu);  // less the fringe bit
  bin.staticCovered = staticCoverageOf(loadParted(staticBins, entry).x);
  bin.staticEntry = e;
  bin.covered += bin.staticCovered;
  return bin;
}

// Covered solid angle of bin b: the frame's senders and the leaf's static entry, or that entry alone.
uint coverageAt(uint slot, uint b, bool staticOnly) {
  int e = staticEntryOf(b);
  const uint entry = uint(max(e, 0));
  return (staticOnly ? 0u : loadCoverage(slot, b)) + (e >= 0 ? staticCoverageOf(loadParted(staticBins, entry).x) : 0u);
}

// Bin `step` cells from bin b on its face, or past the face's edge the neighbouring face's.
uint neighbourBin(uint b, ivec2 step) {
  uint r = b % (kN * kN);
  return binOfCell(b / (kN * kN), ivec2(r % kN, r / kN) + step, kN);
}

// A bin whose four neighbours are each at least half covered is wholly covered. Footprints
// approximate their senders' outlines, so the elements of one surface leave gaps and overlaps of a
// few per cent of a bin between them, and the per-bin cap would turn the overlaps into lost light
// (a closed room a few per cent dark at every bounce); a surface has no hole narrower than a bin at
// the bins' resolution. A silhouette against what lies beyond has a neighbour mostly uncovered and
// keeps its partial coverage. A neighbour below the receiver's horizon counts as covered: the
// receiver's own surface bounds the bins there, not a silhouette (a wall's bottom row seen from
// the floor beside it). An empty bin stays empty: nothing stands for it.
// The four neighbours are tested one after another, not in a loop: lavapipe bounds the loop rounds
// a subgroup may run over all the leaves of its workgroup.
bool halfCovered(uint slot, uint b, ivec2 step, bool staticOnly, vec3 n) {
  const uint neighbour = neighbourBin(b, step);
  return dot(n, imageLoad(binTable, int(neighbour)).xyz) <= 0.0 ||
         coverageAt(slot, neighbour, staticOnly) >= kCoverageUnit / 2u;
}
uint closedCoverage(uint slot, uint b, uint covered, bool staticOnly, vec3 n) {
  if (covered == 0u || covered >= kCoverageUnit) return covered;
  return halfCovered(slot, b, ivec2(1, 0), staticOnly, n) && halfCovered(slot, b, ivec2(-1, 0), staticOnly, n) &&
                 halfCovered(slot, b, ivec2(0, 1), staticOnly, n) && halfCovered(slot, b, ivec2(0, -1), staticOnly, n)
             ? kCoverageUnit
             : covered;
}

// Marks bin b for re-emission by a merging leaf: not touched by its frame senders, but a static one.
void growInto(uint b) {
  uint bit = 1u << (b & 31u);
  if ((mask[b >> 5] & bit) == 0u && staticEntryOf(b) >= 0) atomicOr(grown[b >> 5], bit);
}

void insert(uint slot, uint b, uint64_t key, float omega, bool covers) {
  minBin(slot, b, key);
  if (covers) addCoverage(slot, b, uint(min(omega / imageLoad(binTable, int(b)).w, 1.0) * float(kCoverageUnit) + 0.5));
}

// Corner c (an offset from the receiver) on cube face `axis`, `sign`, in bin units; false behind it.
bool projectCorner(vec3 c, uint axis, float sign, out vec2 at) {
  float major = sign * (axis == 0u ? c.x : (axis == 1u ? c.y : c.z));
  vec2 minor = axis == 0u ? c.yz : (axis == 1u ? c.zx : c.xy);
  at = (minor / max(major, 1e-30) + 1.0) * 0.5 * float(kN);
  return major > 1e-3 * length(c);
}

float edgeSide(vec2 a, vec2 b, vec2 m) { return (b.x - a.x) * (m.y - a.y) - (b.y - a.y) * (m.x - a.x); }

// Whether m lies in the convex quadrilateral c0 c1 c2 c3 (either winding) scaled by 9/8 about its
// centre: elements of one surface whose rectangles do not quite tile (a mesh that is no grid) leave
// no bin centre between them.
bool insideOutline(vec2 m, vec2 c0, vec2 c1, vec2 c2, vec2 c3) {
  vec2 centre = 0.25 * (c0 + c1 + c2 + c3);
  m = centre + (m - centre) / 1.125;
  vec4 e = vec4(edgeSide(c0, c1, m), edgeSide(c1, c2, m), edgeSide(c2, c3, m), edgeSide(c3, c0, m));
  return all(greaterThanEqual(e, vec4(0.0))) || all(lessThanEqual(e, vec4(0.0)));
}

// Files a solid angle ω seen along d as a rectangular footprint of the same solid angle on the cube
// face, shaped like the filed element (half-sides `sideA`, `sideB` in the world; zero: a square):
// the bounding box of their projection gives its aspect, at most 8:1. Box-filtered over the bins it
// overlaps, on the face of its centre and past its edges on the neighbouring faces: even coverage
// for senders of any size and slant, across cube edges too. Its core bins take the key as it is,
// its fringe bins the fringe key, which ranks behind every core: a bin goes to the nearest surface
// over its centre, as a ray through it would find, so that a nearer object's outline takes its bins
// only as far as it reaches (given whole to any face centred in them, every outline would widen by
// up to a bin and darken its penumbra). The core bins are those whose centre lies in the element's
// own rectangle as the receiver sees it (a quadrilateral on the face): neighbouring elements tile
// the view as their rectangles tile the surface, where footprints of the same solid angle would not
// follow a slanted or turned element's outline and leave gaps, which growing them over would widen
// every outline by. A curved sender, a square without sides, is core where it holds the bin's
// centre (grown by an eighth of its sides) or covers half. A
// footprint at most one bin wide overlaps two bins from the one under its lower edge, so that the
// lanes of a subgroup walk loops of the same length (a CPU device runs a subgroup's loop as long as
// its longest lane); wider footprints walk their own range.
void insertFootprint(uint slot, vec3 d, uint64_t key, float omega, vec3 sideA, vec3 sideB, bool covers) {
  vec2 at;
  uint face = binFace(d, kN, at);
  vec2 uv = at / (0.5 * float(kN)) - 1.0;
  float stretch = 1.0 + dot(uv, uv);  // face area per solid angle: stretch^1.5
  float side = min(sqrt(omega * stretch * sqrt(stretch)) * 0.5 * float(kN), 16.0);  // in bins, as a square
  // A side's step on the face: d(uv) = (d(minor) − uv · d|major|) / |major|; the common factor drops out.
  uint axis = face / 2u;
  float sign = (face & 1u) == 0u ? 1.0 : -1.0;
  vec3 a = axis == 0u ? sideA.yzx : (axis == 1u ? sideA.zxy : sideA),
       b = axis == 0u ? sideB.yzx : (axis == 1u ? sideB.zxy : sideB);
  vec2 box = abs(a.xy - uv * (sign * a.z)) + abs(b.xy - uv * (sign * b.z));
  float aspect = box.x + box.y > 0.0 ? clamp(box.x / max(box.y, 1e-30), 0.125, 8.0) : 1.0;
  vec2 sides = min(side * vec2(sqrt(aspect), inversesqrt(aspect)), vec2(16.0));
  vec2 lo = at - 0.5 * sides, hi = at + 0.5 * sides;
  // The element's own outline on the face, where its corners lie in front of the receiver.
  vec2 c0, c1, c2, c3;
  bool outline = sideA != vec3(0.0) && projectCorner(d - sideA - sideB, axis, sign, c0) &&
                 projectCorner(d + sideA - sideB, axis, sign, c1) && projectCorner(d + sideA + sideB, axis, sign, c2) &&
                 projectCorner(d - sideA + sideB, axis, sign, c3);
  // Cells past the face's edge, up to half a face beyond, lie on the neighbouring faces (binOfCell),
  // so that a footprint across a cube edge does not overfill the face's border bins; the outermost
  // reach to infinity, so that nothing falls off.
  ivec2 lowest = ivec2(-int(kN / 2u)), highest = ivec2(int(kN - 1u + kN / 2u));
  ivec2 first = clamp(ivec2(floor(lo)), lowest, highest), end = clamp(ivec2(floor(hi)), lowest, highest);
  end = mix(end, min(first + 1, highest), lessThanEqual(sides, vec2(1.0)));
  float norm = 1.0 / max(sides.x * sides.y, 1e-12);
  for (int y = first.y; y <= end.y; ++y)
    for (int x = first.x; x <= end.x; ++x) {
      vec2 cellLo = vec2(x == lowest.x ? -1e9 : float(x), y == lowest.y ? -1e9 : float(y));
      vec2 cellHi = vec2(x == highest.x ? 1e9 : float(x + 1), y == highest.y ? 1e9 : float(y + 1));
      vec2 overlap = max(min(hi, cellHi) - max(lo, cellLo), vec2(0.0));
      float covered = overlap.x * overlap.y;  // in bins
      vec2 mid = vec2(x, y) + 0.5, grow = 0.125 * sides;
      bool core = outline ? insideOutline(mid, c0, c1, c2, c3)
                          : covered >= 0.5 || (all(greaterThanEqual(mid, lo - grow)) && all(lessThan(mid, hi + grow)));
      if (covered > 0.0 || side <= 0.0 || core)
        insert(slot, binOfCell(face, ivec2(x, y), kN), core ? key : key | kFringeKey,
               side > 0.0 ? omega * covered * norm : omega, covers);
    }
}

// Solid angle of a disk of radius r facing a point at squared distance d²: 2π(1 − d/√(d² + r²)),
// exact, and 2π (not infinity) as d → 0.
float diskSolidAngle(float r, float dist2) { return 2.0 * kPi * (1.0 - sqrt(dist2 / (dist2 + r * r))); }

// A sender as the receiver sees it: offset d, distance², the solid angle ω it subtends, the least
// cosine it is seen under, and the number k of pieces per side it is filed as (1: whole).
struct View {
  vec3 d;
  float dist2;
  float omega;
  float radius;
  float minCos;
  uint k;
};

View viewOf(vec3 p, vec4 positionArea, vec4 normalCone) {
  View v;
  v.d = positionArea.xyz - p;
  v.dist2 = dot(v.d, v.d);
  v.radius = sqrt(positionArea.w / kPi);
  // A curved node is seen at least as much as along the edge of its cone.
  v.minCos = sin(min(normalCone.w, 0.5 * kPi));
  float cosS = abs(dot(normalCone.xyz, v.d)) * inversesqrt(max(v.dist2, 1e-30));
  v.omega = diskSolidAngle(v.radius, v.dist2) * max(cosS, v.minCos);
  // Width in bins (a bin at a face centre is 2/N wide). Within three radii its near side is seen at
  // twice the scale of its far side or more: footprints centred on a few pieces' directions fall
  // short of the near side (along a room's edges, of the next wall's bottom row), so it is filed as
  // the most pieces.
  float width = sqrt(v.omega) * 0.5 * float(kN);
  v.k = v.dist2 <= 9.0 * v.radius * v.radius ? 8u : uint(clamp(ceil(width), 1.0, 8.0));
  return v;
}

// Piece `index` of the k×k pieces of a sender's rectangle as the receiver (normal n) sees it: its
// offset q, its own solid angle and half-sides. A curved sender is the square of its area facing
// the receiver. False for a piece below the receiver's horizon.
struct Piece {
  vec3 q;
  float omega;
  vec3 sideA, sideB;
};
bool pieceOf(vec3 n, uint s, vec4 normalCone, View v, uint index, out Piece piece) {
  vec3 sideA, sideB;
  senderSides(s, normalCone, sideA, sideB);
  if (sideA == vec3(0.0)) {
    vec3 t1, t2;
    tangentFrame(n, t1, t2);
    sideA = 0.5 * sqrt(kPi) * v.radius * t1, sideB = 0.5 * sqrt(kPi) * v.radius * t2;
  }
  vec2 at = (vec2(index % v.k, index / v.k) + 0.5) / float(v.k) * 2.0 - 1.0;  // in (−1, 1)²
  piece.q = v.d + at.x * sideA + at.y * sideB;
  float q2 = dot(piece.q, piece.q), k = float(v.k);
  if (dot(piece.q, n) <= 0.0 || q2 <= 0.0) return false;
  float cosQ = abs(dot(normalCone.xyz, piece.q)) * inversesqrt(q2);
  piece.omega = diskSolidAngle(v.radius / k, q2) * max(cosQ, v.minCos);
  piece.sideA = sideA / k, piece.sideB = sideB / k;
  return true;
}

// Sender s's key in the bins it is filed into, seen from the receiver (View v), and whether it adds
// to their coverage. On a closed surface the faces turned away from the receiver lie behind faces
// turned toward it in the same directions. So they add no coverage: counted, they would cover a
// silhouette's bins twice over, darkening what is seen past it (the sky between an engine's parts).
// And they rank as if at the far side of their object (its diameter further): by its centre a face
// behind is often nearer than the face in front of it (across a thin part, or a finely meshed back
// behind a coarse front), and would win bins to send nothing. Where the faces in front leave a bin empty
// (a receiver just under the object), the face behind still stands for its object there, at the
// distance of that far side. An open surface's back covers and ranks like a front: nothing else may
// stand in front of it.
uint64_t senderKey(uint s, vec4 normalCone, View v, out bool covers) {
  uint flags = imageLoad(nodeFlags, int(s)).x;
  covers = normalCone.w >= 0.5 * kPi || dot(normalCone.xyz, v.d) <= 0.0 || (flags & kNodeClosed) == 0u;
  float farSide = sqrt(v.dist2) + 2.0 * nodeRadius(flags >> kNodeRootShift);
  return packLinkKey(covers ? v.dist2 : farSide * farSide, s, false);
}

// Piece `index`, filed along its own direction with its own solid angle: the footprints follow the
// sender's outline, and a coincident sender on a hard edge is seen through its off-centre pieces.
void filePiece(uint slot, vec3 n, uint s, vec4 normalCone, View v, uint index) {
  Piece piece;
  bool covers;
  uint64_t key = senderKey(s, normalCone, v, covers);
  if (pieceOf(n, s, normalCone, v, index, piece))
    insertFootprint(slot, piece.q, key, piece.omega, piece.sideA, piece.sideB, covers);
}

// Files one sender of the leaf's root path (`marked`: its node, kEmitterBit if it emits), seen from
// the receiver (p, n, area): skipped where its disk cannot rise above the receiver's tangent plane
// (wholly below it, or lying in it: the receiver's own neighbours on a flat face); an emitter is
// also listed for its direct light; one at most a bin wide is filed whole, a wider one queued for
// its pieces (filed one per lane here, their k² pieces would hold up the whole subgroup).
void fileSender(uint slot, uint leaf, vec3 p, vec3 n, float area, uint marked) {
  uint s = marked & ~kEmitterBit;
  vec4 positionArea = nodePositionArea(s), normalCone = nodeNormalCone(s);
  View v = viewOf(p, positionArea, normalCone);
  float along = dot(normalCone.xyz, n);
  float rise = normalCone.w < 0.5 * kPi ? v.radius * sqrt(max(1.0 - along * along, 0.0)) : nodeRadius(s);
  if (s == leaf || dot(v.d, n) + rise <= 1e-4 * sqrt(area)) return;
  // A loop, not an if: lavapipe would run the if's atomic lane by lane, masked, for every sender,
  // and emitters are rare.
  for (bool emitter = (marked & kEmitterBit) != 0u; emitter; emitter = false) {
    uint queued = atomicAdd(emitterCount, 1u);
    if (queued < kEmitterQueue) emitterQueue[queued] = s;
  }
  if (v.k == 1u) {
    vec3 sideA, sideB;
    senderSides(s, normalCone, sideA, sideB);
    bool covers;
    uint64_t key = senderKey(s, normalCone, v, covers);
    insertFootprint(slot, v.d, key, v.omega, sideA, sideB, covers);
  } else {
    wideQueue[atomicAdd(wideCount, 1u)] = s;  // at most one per sender of the chunk
  }
}

// Whether the ray from p along q crosses node o's rectangle (false for a curved node: it has none).
bool rectangleHit(uint o, vec3 p, vec3 q) {
  vec4 plane = nodeNormalCone(o);
  vec3 sideA, sideB, centre = nodePositionArea(o).xyz;
  senderSides(o, plane, sideA, sideB);
  float along = dot(plane.xyz, q);
  if (sideA == vec3(0.0) || along == 0.0) return false;
  vec3 h = p + q * (dot(plane.xyz, centre - p) / along) - centre;
  return abs(dot(h, sideA)) <= dot(sideA, sideA) && abs(dot(h, sideB)) <= dot(sideB, sideB);
}

// Whether the ray from p along q crosses the surface of sender o: the rectangle of o or of the
// whole flat surface o lies on (its highest ancestor flat in its plane; o may be one of that
// surface's elements, and the ray cross its neighbour). Or, unless `surely`, where neither is a bin
// wide: o is one of many elements smaller than a bin (or a curved one, which has no rectangle), and
// where the ray meets them is not known.
bool crosses(uint o, vec3 p, vec3 q, bool surely) {
  const float flatCone = 0.02;  // radians: a cone this narrow is a plane
  vec3 normal = nodeNormalCone(o).xyz, onPlane = nodePositionArea(o).xyz;
  int top = -1;
  for (int i = int(o); i >= 0; i = int(imageLoad(tree, i).x)) {
    vec4 cone = nodeNormalCone(uint(i));
    if (cone.w > flatCone || dot(cone.xyz, normal) < cos(flatCone) ||
        abs(dot(normal, nodePositionArea(uint(i)).xyz - onPlane)) > 1e-3 * nodeRadius(uint(i)))
      break;  // not in o's plane (parallel surfaces apart share a normal)
    top = i;
  }
  if (top < 0) return !surely;
  if (rectangleHit(o, p, q) || (top != int(o) && rectangleHit(uint(top), p, q))) return true;
  vec4 surface = nodePositionArea(uint(top));
  vec3 d = surface.xyz - p;
  return !surely && surface.w * float(kN * kN) < 4.0 * dot(d, d);  // a bin: (2/N)² at distance 1
}

// A light that is no surface: the punctual lights.
const uint kPunctual = 0xFFFFFFFFu;

// Whether the surface of bin key `key` stands between the receiver at p and the light at p + q:
// emitter s's piece (its node at squared distance dist²), or a punctual light (s = kPunctual, at
// dist²). It is nearer than the light, and for an emitter its plane separates them, each side
// judged within a thousandth of its own distance to that surface (a receiver just under an object
// resting on it lies behind its plane by less than the lamp is far; the ceiling beside a lamp and
// the lamp's own other pieces do not separate).
bool standsBetween(uint64_t key, uint s, float dist2, vec3 p, vec3 q) {
  uint o = keyId(key);
  if (key == kEmptyVisibility || o == s) return false;
  if (s == kPunctual) return linkKeyDepth(key) <= dist2;
  if (linkKeyDepth(key) >= dist2 * 0.999) return false;
  vec4 plane = nodeNormalCone(o);
  vec3 onPlane = nodePositionArea(o).xyz;
  float sideOfReceiver = dot(plane.xyz, p - onPlane), sideOfEmitter = dot(plane.xyz, p + q - onPlane);
  float nearMargin = 1e-3 * sqrt(linkKeyDepth(key)), farMargin = 1e-3 * length(q);
  return plane.w >= 0.5 * kPi || (sideOfReceiver > nearMargin && sideOfEmitter < -farMargin) ||
         (sideOfReceiver < -nearMargin && sideOfEmitter > farMargin);
}

// Whether the surface of bin key `key` hides the light: it stands between, and the ray crosses it
// (crosses(), `surely` or not).
bool hides(uint64_t key, uint s, float dist2, vec3 p, vec3 q, bool surely) {
  return standsBetween(key, s, dist2, p, q) && crosses(keyId(key), p, q, surely);
}

// Whether the light along q, in bin b, is hidden: the ray to it crosses a surface that stands
// between, over the bin's centre or over one of the eight neighbouring bins' centres (the light may
// lie up to a bin from its bin's centre, where another surface holds the view): shadows and
// penumbrae finer than the bins, either way. Over the bin's own centre, a surface whose rectangle
// does not tell where the ray meets it (curved, or elements smaller than a bin) hides it too.
// The eight neighbours are tested one after another, not in a loop (lavapipe's loop budget).
bool hidden(uint slot, uint b, uint s, float dist2, vec3 p, vec3 q) {
  uint64_t key = binAt(slot, b).key;
  return hides(key, s, dist2, p, q, false) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, 0))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, 0))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(0, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(0, -1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, 1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(1, -1))).key, s, dist2, p, q, true) ||
         hides(binAt(slot, neighbourBin(b, ivec2(-1, -1))).key, s, dist2, p, q, true);
}

// Irradiance at the receiver from the punctual lights it does not find hidden.
vec3 punctualLight(uint slot, vec3 p, vec3 n) {
  vec3 sum = vec3(0.0);
  for (uint l = 0u; l < push.lightCount; ++l) {
    vec3 toLight;
    float dist2, falloff = lightFalloff(lights[l], p, toLight, dist2);
    float cosR = dot(n, normalize(toLight));
    if (cosR <= 0.0 || falloff <= 0.0) continue;
    if (hidden(slot, binOf(toLight, kN), kPunctual, dist2, p, toLight)) continue;
    sum += lights[l].intensity.rgb * cosR * falloff;
  }
  return sum;
}

// Fraction of bin b that its senders cover, at most 1.
float coveredFraction(uint covered) { return min(float(covered) / float(kCoverageUnit), 1.0); }

// The part of bin b's surface at squared distance d² in the receiver's proximity: cos θ·ω/(π·d),
// a distance below the receiver's own radius counting as that radius.
float proximityOf(vec3 n, uint b, uint covered, float distance2, float radius) {
  vec4 bin = imageLoad(binTable, int(b));
  return max(dot(n, bin.xyz), 0.0) * coveredFraction(covered) / (kPi * max(max(sqrt(distance2), radius), 1e-20));
}

// Form factor of the survivor of bin b, standing for the covered part of the bin. Front or back is
// judged along the bin: the sender may sit at the receiver (hard edges).
float survivorFormFactor(vec3 n, uint sender, uint b, uint covered) {
  vec4 normalCone = nodeNormalCone(sender), bin = imageLoad(binTable, int(b));
  bool facing = dot(normalCone.xyz, -bin.xyz) > 0.0 || normalCone.w >= 0.5 * kPi;
  return facing ? max(dot(n, bin.xyz), 0.0) * coveredFraction(covered) / kPi : 0.0;
}

// Environment radiance through the uncovered part of bin b, cosine-weighted (0 below the horizon).
vec3 environmentThrough(vec3 n, uint b, uint covered) {
  vec4 bin = imageLoad(binTable, int(b));
  float c = dot(n, bin.xyz);
  return c > 0.0 ? imageLoad(environment, int(b)).rgb * c * (1.0 - coveredFraction(covered)) : vec3(0.0);
}

// Emitted radiosity π·Le of node s (pulled up); zero for a node that emits nothing.
vec3 emitted(uint s) { return imageLoad(nodeEmission, int(s)).rgb; }

// Direct light from emitter s at the receiver (p, n): each of its pieces (as filed) with its own
// form factor, where it is not hidden. Exact where the bins only credit whole bins, so that a small
// emitter's light does not jump as its footprint crosses bin borders.
vec3 directLight(uint slot, vec3 p, vec3 n, uint s) {
  vec4 normalCone = nodeNormalCone(s);
  View v = viewOf(p, nodePositionArea(s), normalCone);
  float sum = 0.0;
  for (uint index = 0u; index < v.k * v.k; ++index) {
    Piece piece;
    if (!pieceOf(n, s, normalCone, v, index, piece) ||
        (dot(normalCone.xyz, piece.q) >= 0.0 && normalCone.w < 0.5 * kPi))
      continue;  // its back
    vec3 q = piece.q;
    float q2 = dot(q, q);
    if (!hidden(slot, binOf(q, kN), s, v.dist2, p, q)) sum += piece.omega * dot(n, q) * inversesqrt(q2) / kPi;
  }
  return sum * emitted(s);
}

// Emitter e of a leaf's list: its static ones first, then those the walk queued.
uint emitterAt(uint surfel, uint staticListed, uint e) {
  return e < staticListed ? staticEmitters[surfel * kStaticEmitters + e] : emitterQueue[e - staticListed];
}

// Sum of the workgroup's partial vectors in a fixed order (deterministic); valid in invocation 0.
vec3 sumPartials(uint lid, vec3 mine) {
  partial[lid] = mine;
  barrier();
  vec3 sum = vec3(0.0);
  if (lid == 0u)
    for (uint t = 0u; t < kGroupSize; ++t) sum += partial[t];
  return sum;
}

void main() {
  // Links cut short by an overflow (this set's, or the static links a frame pass merges): the frame
  // is redone, and pruning them would be wasted.
  if (((counters[kCounterOverflow] | staticCounters[kCounterOverflow]) & (kOverflowWorklist | kOverflowLinks)) != 0u)
    return;
  uint lid = gl_LocalInvocationID.x;
  uint slot = kSharedBins ? 0u : groupIndex() * kBinCount;
  if (kSharedBins)
    for (uint b = lid; b < kBinCount; b += kGroupSize) sharedBins[b] = kEmptyVisibility, sharedCoverage[b] = 0u;
  for (uint w = lid; w < kMaskWords; w += kGroupSize) mask[w] = 0u;
  if (lid == 0u) wideCount = 0u, emitterCount = 0u;
  barrier();

  uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y, end = push.endSurfel, listStart = 0u;
  if (push.listed != 0u) {
    listStart = receiverCounts[kReceiverRound];
    end = min(end, receiverCounts[kReceiverCount] - listStart);
  }
  for (uint item = push.firstSurfel + groupIndex(); item < end; item += groups) {
    const uint surfel = push.listed != 0u ? imageLoad(receivers, int(listStart + item)).x : item;
    uint leaf = imageLoad(leafOfSurfel, int(surfel)).x;
    bool moves = (imageLoad(nodeFlags, int(leaf)).x & kNodeMoves) != 0u;
    if (kStaticPass && moves) {  // pruned every frame instead
      if (lid == 0u) staticRanges[surfel] = LeafRange(0u, 0u);
      continue;
    }
    merging = !kStaticPass && !moves;
    staticFirst = merging ? staticRanges[surfel].first : 0u;
    maskBase = surfel * kMaskWords;
    vec4 receiver = nodePositionArea(leaf);
    vec3 p = receiver.xyz, n = nodeNormalCone(leaf).xyz;
    float area = receiver.w;
    // The emitters whose direct light this leaf takes: a merging leaf's static ones (listed by the
    // static pass) and those the walk queues. Past the queue, the bins credit them as any sender.
    uint staticEmitterCount = merging ? staticLeaves[surfel].emitterCount : 0u;
    // The root path's senders, a chunk at a time, are first gathered into shared memory and then
    // filed in one pass: a CPU device runs the filing code, lanes masked, on every round of a
    // subgroup however few of its lanes have a sender, and ancestor by ancestor the ranges are short
    // (a static leaf's frame senders: a few per ancestor).
    int a = area > 0.0 ? int(leaf) : -1;
    uint next = a >= 0 ? imageLoad(starts, a).x : 0u;
    while (a >= 0) {
      uint listed = 0u;
      while (a >= 0 && listed < kPathChunk) {
        uint end = imageLoad(starts, a + 1).x, take = min(end - next, kPathChunk - listed);
        for (uint j = lid; j < take; j += kGroupSize) pathChunk[listed + j] = imageLoad(senders, int(next + j)).x;
        listed += take;
        next += take;
        if (next == end) {
          a = int(imageLoad(tree, a).x);
          next = a >= 0 ? imageLoad(starts, a).x : 0u;
        }
      }
      barrier();
      if (lid == 0u && atomicAdd(counters[kCounterSendersWalked], listed) > 0xFFFFFFFFu - listed)
        atomicAdd(counters[kCounterSendersWalked + 1u], 1u);
      for (uint j = lid; j < listed; j += kGroupSize) fileSender(slot, leaf, p, n, area, pathChunk[j]);
      barrier();
      // Each group of 8 lanes (a subgroup on lavapipe) takes a queued sender and files its pieces, one per lane.
      for (uint e = lid / 8u; e < wideCount; e += kGroupSize / 8u) {
        uint s = wideQueue[e];
        vec4 normalCone = nodeNormalCone(s);
        View v = viewOf(p, nodePositionArea(s), normalCone);
        for (uint piece = lid % 8u; piece < v.k * v.k; piece += 8u) filePiece(slot, n, s, normalCone, v, piece);
      }
      barrier();
      if (lid == 0u) wideCount = 0u;  // before the next chunk's filing, past its gathering barrier
    }
    barrier();
    // The bins the walk filed senders in, read once from the bins rather than marked by every filing.
    for (uint w = lid; w < kMaskWords; w += kGroupSize) {
      uint bits = 0u;
      for (uint i = 0u; i < 32u && w * 32u + i < kBinCount; ++i)
        bits |= loadBin(slot, w * 32u + i) != kEmptyVisibility ? 1u << i : 0u;
      mask[w] = bits;
    }
    barrier();
    // A merging leaf also re-emits the static bins beside those its frame senders touched: whether a
    // bin's gaps are closed depends on its neighbours' coverage.
    if (merging) {
      for (uint w = lid; w < kMaskWords; w += kGroupSize) grown[w] = 0u;
      barrier();
      for (uint w = lid; w < kMaskWords; w += kGroupSize)
        for (uint bits = mask[w]; bits != 0u; bits &= bits - 1u) {
          uint b = w * 32u + uint(findLSB(bits));
          growInto(neighbourBin(b, ivec2(1, 0)));
          growInto(neighbourBin(b, ivec2(-1, 0)));
          growInto(neighbourBin(b, ivec2(0, 1)));
          growInto(neighbourBin(b, ivec2(0, -1)));
        }
      barrier();
      for (uint w = lid; w < kMaskWords; w += kGroupSize) mask[w] |= grown[w];
      barrier();
    }
    // Emitters' light: direct where they are few enough to list (the static pass keeps the list for
    // the frames, whose moving senders may hide them), the bins then carrying only their reflected
    // light; through the bins like any sender where they are many (a wholly emissive room). In a
    // fixed order whatever order the atomics queued them in: the static list (sorted by the static
    // pass), then the queued ones sorted by node (another object's, so never in the static list). A
    // static leaf whose emitters stand still queues none and sorts nothing.
    uint staticListed = staticEmitterCount == kManyEmitters ? 0u : staticEmitterCount,
         emitters = staticListed + emitterCount;
    bool direct = staticEmitterCount != kManyEmitters && emitters <= (kStaticPass ? kStaticEmitters : kEmitterQueue);
    if (direct)
      for (uint e = lid; e < emitters; e += kGroupSize) {
        uint s = emitterAt(surfel, staticListed, e), rank = min(e, staticListed);
        for (uint j = 0u; j < (e < staticListed ? 0u : emitterCount); ++j) rank += emitterQueue[j] < s ? 1u : 0u;
        sortedEmitters[rank] = s;
      }
    // Survivors in bin order (deterministic): count per mask word, scan, write.
    for (uint w = lid; w < kMaskWords; w += kGroupSize) wordStart[w] = bitCount(mask[w]);
    barrier();
    vec3 emitterLight = vec3(0.0);
    if (kStaticPass) {
      if (direct)
        for (uint e = lid; e < emitters; e += kGroupSize)
          staticEmitters[surfel * kStaticEmitters + e] = sortedEmitters[e];
      if (lid == 0u) staticLeaves[surfel].emitterCount = direct ? emitters : kManyEmitters;
    } else if (direct) {
      for (uint e = lid; e < emitters; e += kGroupSize) emitterLight += directLight(slot, p, n, sortedEmitters[e]);
    }
    if (lid == 0u) {
      uint total = 0u;
      for (uint w = 0u; w < kMaskWords; ++w) {
        uint c = wordStart[w];
        wordStart[w] = total;
        total += c;
      }
      leafBase = atomicAdd(counters[kCounterLeafLinks], total);
      // A leaf past the room is counted (the frame is redone with room for all), its range left
      // empty: nothing reads past the links.
      bool fits = leafBase + total <= push.linkCapacity;
      if (!fits) atomicOr(counters[kCounterOverflow], kOverflowLeafLinks);
      if (kStaticPass)
        staticRanges[surfel] = LeafRange(leafBase, fits ? total : 0u);
      else
        ranges[surfel] = LeafRange(leafBase, fits ? total : 0u);
    }
    barrier();
    // A merging leaf's environment changes only in the bins it touched: this frame's minus its static
    // share; so does the emission taken back from emissive survivors.
    vec3 environmentChange = vec3(0.0);
    float near = 0.0;  // the proximity of what the leaf sees, or for a merging leaf its change
    const float radius = sqrt(area / kPi);
    for (uint w = lid; w < kMaskWords; w += kGroupSize) {
      uint bits = mask[w], outIndex = leafBase + wordStart[w];
      if (kStaticPass) staticMasks[maskBase + w] = uvec2(bits, wordStart[w]);
      if (merging) overrides[maskBase + w] = bits;
      while (bits != 0u) {
        uint b = w * 32u + uint(findLSB(bits));
        bits &= bits - 1u;
        Bin bin = binAt(slot, b);
        uint s = keyId(bin.key), covered = closedCoverage(slot, b, bin.covered, false, n),
             staticCovered = bin.staticEntry >= 0 ? closedCoverage(slot, b, bin.staticCovered, true, n) : 0u;
        float f = survivorFormFactor(n, s, b, covered);
        near += proximityOf(n, b, covered, linkKeyDepth(bin.key), radius);
        if (bin.staticEntry >= 0) near -= proximityOf(n, b, staticCovered, bin.staticDistance2, radius);
        if (outIndex < push.linkCapacity) {
          if (kStaticPass) {
            storeParted(staticLinks, outIndex, uvec4(s, floatBitsToUint(f), 0u, 0u));
            storeParted(staticBins, outIndex, uvec4(packStaticBin(b, bin.covered)));
            storeParted(staticDepths, outIndex, uvec4(uint(bin.key >> 32)));
          } else {
            storeParted(leafLinks, outIndex, uvec4(s, floatBitsToUint(f), 0u, 0u));
          }
        }
        ++outIndex;
        if (direct) {
          emitterLight -= f * emitted(s);
          if (bin.staticEntry >= 0) {
            const uint entry = uint(bin.staticEntry);
            uvec2 link = loadParted(staticLinks, entry).xy;
            emitterLight += uintBitsToFloat(link.y) * emitted(link.x);
          }
        }
        if (merging && push.environmentOn != 0u)
          environmentChange += environmentThrough(n, b, covered) - environmentThrough(n, b, staticCovered);
      }
    }
    // Environment through the empty bins above the horizon, summed in a fixed order.
    vec3 env = environmentChange;
    if (push.environmentOn != 0u && area > 0.0 && !merging)
      for (uint b = lid; b < kBinCount; b += kGroupSize)
        env += environmentThrough(n, b, closedCoverage(slot, b, loadCoverage(slot, b), false, n));
    if (kStaticPass) {
      vec3 correction = sumPartials(lid, emitterLight);
      barrier();
      if (lid == 0u) staticLeaves[surfel].correction = vec4(correction, 0.0);
    }
    near = sumPartials(lid, vec3(near, 0.0, 0.0)).x;
    barrier();
    vec3 sum = sumPartials(lid, kStaticPass ? env : env + emitterLight);
    if (lid == 0u) {
      if (kStaticPass) {
        staticLeaves[surfel].environment = vec4(sum, 0.0);
        staticLeaves[surfel].proximity = near;
      } else {
        if (merging)
          sum += staticLeaves[surfel].environment.rgb + (direct ? staticLeaves[surfel].correction.rgb : vec3(0.0));
        if (area > 0.0) sum += punctualLight(slot, p, n);
        externalLight[surfel] = vec4(sum, 0.0);
        proximity[surfel] = merging ? staticLeaves[surfel].proximity + near : near;
      }
    }
    barrier();  // the lights read the bins
    for (uint w = lid; w < kMaskWords; w += kGroupSize) {
      uint bits = mask[w];
      while (bits != 0u) {
        resetBin(slot, w * 32u + uint(findLSB(bits)));
        bits &= bits - 1u;
      }
      mask[w] = 0u;
    }
    if (lid == 0u) emitterCount = 0u;  // (each chunk already emptied the wide queue)
    barrier();
  }
  // Cut short by lavapipe's loop budget (common.glsl), every leaf after the one it ran out in came
  // out short: the frame is redone with more subgroups a workgroup.
  if (loopBudgetSpent()) atomicOr(counters[kCounterOverflow], kOverflowLoopBudget);
}

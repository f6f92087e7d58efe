#version 460
// ar, the global pass: unoccluded transport U of radiance less antiradiance over the links. Each
// receiver node adds, per link, what its sender sends toward it times the sender's solid angle per
// area (a disk's on its axis: finite when near) into the bins around the direction it sees the
// sender in (binTaps), as radiance averaged over each bin. A surfel sender is exact in direction; a
// cluster's antiradiance (a curved one's intensity) comes from its table, read between bins. A
// receiver's links are two lists: those between static objects (made once), then the frame's, each
// in the order the sorts left (walkKey: the lanes of neighbouring receivers take alike links at once).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
layout(local_size_x = kArGatherGroup) in;
layout(constant_id = 0) const uint kDirs = 4;  // --dirs: a constant, so that the bins' arithmetic folds
// The most bins of a receiver's table kept in each invocation (kArGatherTableHere; tests set fewer).
layout(constant_id = 1) const uint kTableHereMost = kArGatherTableHere;

layout(binding = 1, rgba32ui) readonly uniform uimageBuffer tree;  // TreeNode
layout(std430, binding = 2) readonly buffer Starts { uint starts[]; };
layout(binding = 3, r32ui) readonly uniform uimageBuffer senders;
layout(binding = 4, rgba32f) readonly uniform imageBuffer binTable;   // per bin ∫ω dω, Ω
layout(binding = 5, rgba32f) readonly uniform imageBuffer radiance;   // per surfel
layout(binding = 6, rgba32f) readonly uniform imageBuffer incident;   // per surfel and bin
layout(binding = 7, rgba32f) readonly uniform imageBuffer intensity;  // per node and bin (ar_pull_up)
layout(binding = 8, rgba32f) uniform imageBuffer gathered;            // per node and bin, written whole
// Per flat node, Σ over its links of radiance × solid angle × direction, as three texels (x, y, z,
// each RGB): a surfel's irradiance is its normal against its own and its flat ancestors'
// (ar_incident), with each sender's own direction rather than its bins'.
layout(binding = 9, rgba32f) uniform imageBuffer gatheredVector;
layout(binding = 10, rgba32f) readonly uniform imageBuffer exitance;  // per flat node, area · L
layout(std430, binding = 11) readonly buffer StaticStarts { uint staticStarts[]; };
layout(binding = 12, r32ui) readonly uniform uimageBuffer staticSenders;
layout(std430, binding = 13) readonly buffer GatherOrder { uint gatherOrder[]; };  // ar_order_receivers
// kArFlagChunks where a receiver's list was longer than the chunks recorded walked (the frame is
// redone in more).
layout(std430, binding = 14) buffer GatherFlags { uint gatherFlags[]; };
layout(binding = 15, rg32f) readonly uniform imageBuffer specularAlbedo;
layout(push_constant) uniform Push { ArGatherPush push; };
#include "common/specular_albedo.glsl"
#define SENDER_LOBES 16
#include "common/sender_lobes.glsl"

// The bins around a direction (binTaps) with their bilinear weights, and each bin's ∫ω dω (xyz)
// and solid angle (w), loaded once for every use of the direction.
struct Taps {
  uvec4 bins;
  vec4 weights;
  mat4 vectors;  // column i: bin i's
};
Taps tapsOf(vec3 dir) {
  Taps t;
  binTaps(dir, kDirs, t.bins, t.weights);
  for (int i = 0; i < 4; ++i) t.vectors[i] = imageLoad(binTable, int(t.bins[i]));
  return t;
}

// A flat node keeps a direction's taps on the side of its plane the direction lies on (their
// weights renormalised): light arriving at its front must not spill into bins behind it, nor the
// light that reached it from beyond into bins in front.
vec4 keepSide(vec4 normalCone, vec3 dir, Taps t) {
  if (normalCone.w > kArFlatCone) return t.weights;  // curved: no one plane
  vec4 cosines = vec4(dot(normalCone.xyz, t.vectors[0].xyz), dot(normalCone.xyz, t.vectors[1].xyz),
                      dot(normalCone.xyz, t.vectors[2].xyz), dot(normalCone.xyz, t.vectors[3].xyz));
  vec4 kept = dot(normalCone.xyz, dir) >= 0.0 ? step(0.0, cosines) : vec4(1.0) - step(0.0, cosines);
  vec4 w = t.weights * kept;
  float sum = w.x + w.y + w.z + w.w;
  return sum > 0.0 ? w / sum : t.weights;
}

// The receiver's table while its links are walked, where it is small enough to be kept by each
// invocation (its texels are then written once, at the end); a larger one is summed in place.
const uint kBins = 6u * kDirs * kDirs;
const bool kTableHere = kBins <= kTableHereMost;
vec3 gatheredHere[kTableHere ? kBins : 1u];
uint tableBase;  // the receiver's first texel in `gathered`

// Adds to the receiver's bin `bin` (of solid angle `omega`) radiance × solid angle `sent` over the
// bin's solid angle.
void add(uint bin, float omega, vec3 sent) {
  vec3 share = sent / omega;
  if (kTableHere)
    gatheredHere[bin] += share;
  else
    imageStore(gathered, int(tableBase + bin), vec4(imageLoad(gathered, int(tableBase + bin)).rgb + share, 0.0));
}

vec3 vectorX, vectorY, vectorZ;  // the receiver's Σ sent · dir
vec3 slopeX, slopeY, slopeZ;     // and Σ sent/d · (3 (n·dir) dir − n): its irradiance's gradient

// Deposits radiance × solid angle `sent`, seen along unit `dir` (its taps t): `binShare` of it into
// the receiver's bins around it and, where it arrives at the front of a flat receiver, all of it into
// its vector sum (a curved receiver's surfaces face many ways: their irradiance comes from its bins).
void deposit(vec4 nr, vec3 dir, Taps t, vec3 sent, float binShare, float invDist) {
  if (nr.w <= kArFlatCone && dot(nr.xyz, dir) >= 0.0) {
    vectorX += sent * dir.x, vectorY += sent * dir.y, vectorZ += sent * dir.z;
    const vec3 g = invDist * (3.0 * dot(nr.xyz, dir) * dir - nr.xyz);
    slopeX += sent * g.x, slopeY += sent * g.y, slopeZ += sent * g.z;
  }
  vec4 weights = keepSide(nr, dir, t) * binShare;
  add(t.bins.x, t.vectors[0].w, weights.x * sent);
  add(t.bins.y, t.vectors[1].w, weights.y * sent);
  add(t.bins.z, t.vectors[2].w, weights.z * sent);
  add(t.bins.w, t.vectors[3].w, weights.w * sent);
}

// A table's value at a direction (`base`: the node's or surfel's first texel), read between the
// bins around it with their weights (a macro: GLSL passes no image to a function).
#define READ_TAPS(table, base, taps, weights)                   \
  ((weights).x * imageLoad(table, int((base) + (taps).x)).rgb + \
   (weights).y * imageLoad(table, int((base) + (taps).y)).rgb + \
   (weights).z * imageLoad(table, int((base) + (taps).z)).rgb + \
   (weights).w * imageLoad(table, int((base) + (taps).w)).rgb)

// The radiance surfel sender s (its surfel, normal) sends along unit `dir` (from the receiver to
// it; its taps t): from its front its own with what its lobe sends beyond it (`lobe`), and from
// either side less the antiradiance, the light that reached it from beyond, read between the bins
// on its far side.
vec3 surfelRadiance(uint surfel, uint bins, vec4 ns, vec3 dir, Taps t, vec3 lobe) {
  vec3 through = READ_TAPS(incident, surfel * bins, t.bins, keepSide(ns, dir, t));
  return (dot(ns.xyz, -dir) > 0.0 ? imageLoad(radiance, int(surfel)).rgb + lobe : vec3(0.0)) - through;
}

// Adds what sender node s sends over its link to the receiver (at pr, its normal and cone nr, its area).
void gatherLink(uint s, vec3 pr, vec4 nr, float receiverArea) {
  uint n = kDirs, bins = 6u * n * n;
  vec4 ps = nodePositionArea(s);
  vec3 d = ps.xyz - pr;
  float dist2 = dot(d, d);
  if (dist2 <= 1e-6 * ps.w) return;  // coincident: no direction to bin it in
  uvec4 t = imageLoad(tree, int(s));
  if (t.z != 0u) {  // a cluster: what it sends toward the receiver, read between the bins of its table
    vec3 dir = d * inversesqrt(dist2);
    uvec4 back;
    vec4 weights;
    binTaps(-dir, n, back, weights);
    vec3 sent = READ_TAPS(intensity, s * bins, back, weights);
    vec4 cone = nodeNormalCone(s);
    if (cone.w <= kArFlatCone) {  // flat: its exitance and antiradiance with its own cosine
      float cosine = dot(cone.xyz, -dir);
      sent = imageLoad(exitance, int(s)).rgb * max(cosine, 0.0) - sent * abs(cosine);
    }
    deposit(nr, dir, tapsOf(dir), sent * solidAnglePerArea(ps.w, dist2), 1.0, inversesqrt(dist2));
    return;
  }
  // A surfel goes as pieces of its rectangle, each along its own direction (surfelPieces).
  vec4 ns = nodeNormalCone(s);
  if (abs(dot(ns.xyz, d)) <= 1e-4 * sqrt(dist2)) return;  // the receiver lies in its plane: it sends nothing there
  uint pieces = surfelPieces(ps.w, dist2, n);
  vec3 sideA, sideB;
  senderSides(s, ns, sideA, sideB);
  float pieceArea = ps.w / float(pieces * pieces);
  // What its lobe sends beyond its radiance toward the receiver, spread over the receiver's extent
  // and at least what the tables resolve (a bin's solid angle over 4: engine/gi/bins.h's
  // tableBinSpread).
  const float receiverExtent = receiverArea / (dist2 + receiverArea / kPi);
  const vec3 lobe = excessToward(s, pr, receiverExtent, kPi / float(6u * n * n)) / kPi;
  for (uint j = 0u; j < pieces * pieces; ++j) {
    vec2 at = (vec2(j % pieces, j / pieces) + 0.5) / float(pieces) * 2.0 - 1.0;
    vec3 q = d + at.x * sideA + at.y * sideB;
    float q2 = dot(q, q);
    if (q2 <= 1e-6 * ps.w) continue;
    vec3 dir = q * inversesqrt(q2);
    float omega = pieceArea * solidAnglePerArea(pieceArea, q2) * abs(dot(ns.xyz, dir));
    // In the bins, a piece wider than a bin is credited one bin's worth: they hold radiance, which
    // J passes on, and a near piece's light taken along one direction would pass on more than it
    // has (its neighbours on a curved surface, each in the others' near field, fed it back).
    float binOmega = imageLoad(binTable, int(binOf(dir, kDirs))).w;
    const Taps taps = tapsOf(dir);
    float binShare = omega > binOmega ? binOmega / omega : 1.0;
    deposit(nr, dir, taps, surfelRadiance(t.w, bins, ns, dir, taps, lobe) * omega, binShare, inversesqrt(q2));
  }
}

void main() {
  if (itemIndex() >= push.nodeCount) return;
  uint r = gatherOrder[itemIndex()];
  // One loop over both lists (the link's body is long, and compiled once), this dispatch's chunk of
  // them; the chunks after the first go on from the table and vector sums the one before left.
  uint fixedFirst = staticStarts[r], fixedCount = staticStarts[r + 1u] - fixedFirst;
  uint first = starts[r] - fixedCount, end = fixedCount + starts[r + 1u] - starts[r];
  uint from = push.chunk * push.chunkLinks, to = min(end, from + push.chunkLinks);
  if (push.chunk + 1u == push.chunks && end > to) atomicOr(gatherFlags[0], kArFlagChunks);
  if (push.chunk > 0u && from >= end) return;
  const vec4 receiverAt = nodePositionArea(r);
  const vec3 pr = receiverAt.xyz;
  const float receiverArea = receiverAt.w;
  vec4 nr = nodeNormalCone(r);
  tableBase = r * kBins;
  vectorX = vectorY = vectorZ = slopeX = slopeY = slopeZ = vec3(0.0);
  if (push.chunk > 0u) {  // a later chunk: go on from the sums the one before left
    vectorX = imageLoad(gatheredVector, int(kArVectorTexels * r)).rgb;
    vectorY = imageLoad(gatheredVector, int(kArVectorTexels * r + 1u)).rgb;
    vectorZ = imageLoad(gatheredVector, int(kArVectorTexels * r + 2u)).rgb;
    slopeX = imageLoad(gatheredVector, int(kArVectorTexels * r + 3u)).rgb;
    slopeY = imageLoad(gatheredVector, int(kArVectorTexels * r + 4u)).rgb;
    slopeZ = imageLoad(gatheredVector, int(kArVectorTexels * r + 5u)).rgb;
    for (uint b = 0u; kTableHere && b < kBins; ++b) gatheredHere[b] = imageLoad(gathered, int(tableBase + b)).rgb;
  } else {
    for (uint b = 0u; b < kBins; ++b)
      if (kTableHere)
        gatheredHere[b] = vec3(0.0);
      else
        imageStore(gathered, int(tableBase + b), vec4(0.0));
  }
  for (uint k = from; k < to; ++k) {
    uint s = k < fixedCount ? imageLoad(staticSenders, int(fixedFirst + k)).x : imageLoad(senders, int(first + k)).x;
    gatherLink(s & ~kEmitterBit, pr, nr, receiverArea);
  }
  for (uint b = 0u; kTableHere && b < kBins; ++b) imageStore(gathered, int(tableBase + b), vec4(gatheredHere[b], 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r), vec4(vectorX, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 1u), vec4(vectorY, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 2u), vec4(vectorZ, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 3u), vec4(slopeX, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 4u), vec4(slopeY, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 5u), vec4(slopeZ, 0.0));
}

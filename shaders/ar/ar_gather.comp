#version 460
// ar, the global pass: unoccluded transport U of radiance less antiradiance over the links. Each
// receiver node adds, per link, what its sender sends toward it times the sender's solid angle per
// area (a disk's on its axis: finite when near) into the bins around the direction it sees the
// sender in (binTaps), as radiance averaged over each bin, and a flat receiver into its vector sum
// (a flat cluster there over its rectangle's exact solid angle). A surfel sender is exact in
// direction; a cluster's antiradiance (a curved one's intensity) comes from its table, read between
// bins (a flat one's on the receiver's side of its plane alone). A
// receiver's links are two lists: those between static objects (made once), then the frame's, each
// in the order the sorts left (walkKey: the lanes of neighbouring receivers take alike links at once).
#extension GL_GOOGLE_include_directive : require
#define NODE_TEXELS 0
#include "common/common.glsl"
#include "common/solid_angle.glsl"
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
layout(binding = 15, rgba32f) readonly uniform imageBuffer specularAlbedo;
layout(push_constant) uniform Push { ArGatherPush push; };
#include "common/specular_albedo.glsl"
#define SENDER_LOBES 16
#include "common/sender_lobes.glsl"
layout(std430, binding = 17) readonly buffer SurfelBrdf { SurfaceBrdf surfelBrdf[]; };
layout(std430, binding = 18) readonly buffer Emission { vec4 emission[]; };  // Le per surfel

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
vec3 slopeX, slopeY, slopeZ;     // and its irradiance's gradient over its position (depositInVector)

// Adds radiance × solid angle `sent`, seen along unit `dir` (its taps t), `binShare` of it into the
// receiver's bins around it.
void depositInBins(vec4 nr, vec3 dir, Taps t, vec3 sent, float binShare) {
  vec4 weights = keepSide(nr, dir, t) * binShare;
  add(t.bins.x, t.vectors[0].w, weights.x * sent);
  add(t.bins.y, t.vectors[1].w, weights.y * sent);
  add(t.bins.z, t.vectors[2].w, weights.z * sent);
  add(t.bins.w, t.vectors[3].w, weights.w * sent);
}

// Adds to a flat receiver's vector sum radiance `radiance` over the directions whose ∫ω dω is
// `phi`, and to its gradient what that changes by as the receiver's point moves: `sent` (radiance ×
// solid angle) seen along `dir` at distance 1/invDist grows as 1/d² toward it and turns with the
// receiver's cosine, and the sender's own cosine turns too, by (m + cos·dir)/d for its normal m, which
// changes what it sends by `perCosine` (radiance × solid angle per unit of its cosine) times that.
void depositInVector(vec4 nr, vec3 dir, vec3 radiance, vec3 phi, vec3 sent, float invDist, vec3 perCosine,
                     vec3 change) {
  if (nr.w > kArFlatCone) return;
  vectorX += radiance * phi.x, vectorY += radiance * phi.y, vectorZ += radiance * phi.z;
  if (dot(nr.xyz, dir) < 0.0) return;
  const vec3 g = invDist * (3.0 * dot(nr.xyz, dir) * dir - nr.xyz);
  const vec3 turning = invDist * dot(nr.xyz, dir) * perCosine;
  slopeX += sent * g.x + turning * change.x;
  slopeY += sent * g.y + turning * change.y;
  slopeZ += sent * g.z + turning * change.z;
}

// Deposits radiance × solid angle `sent`, seen along unit `dir` (its taps t): `binShare` of it into
// the receiver's bins around it and, where it arrives at the front of a flat receiver, all of it into
// its vector sum (a curved receiver's surfaces face many ways: their irradiance comes from its bins),
// its gradient with the sender's cosine turning as depositInVector takes it.
void deposit(vec4 nr, vec3 dir, Taps t, vec3 sent, float binShare, float invDist, vec3 perCosine, vec3 change) {
  if (dot(nr.xyz, dir) >= 0.0) depositInVector(nr, dir, sent, dir, sent, invDist, perCosine, change);
  depositInBins(nr, dir, t, sent, binShare);
}

// Lambert's term of the edge between directions a and b: the angle between them times their
// plane's unit normal.
vec3 edgeVector(vec3 a, vec3 b) {
  const vec3 u0 = normalize(a), u1 = normalize(b), across = cross(u0, u1);
  const float len = length(across);
  return len > 1e-7 ? across * (atan(len, dot(u0, u1)) / len) : vec3(0.0);
}

// ∫ω dω over the directions from the receiver toward the rectangle of centre q (from the receiver)
// and half-sides a, b, those above the plane of normal n alone: Lambert's sum, ½ Σ θ_k û_k, over
// the polygon clipped there. A convex polygon crosses the plane at most once each way: the edge
// leaving ends where it crosses, the edge back starts there, and the plane joins the two. Written
// without branches (lavapipe runs both sides of one) and without arrays (it keeps an array indexed at
// run time in memory).
vec3 rectangleVector(vec3 q, vec3 a, vec3 b, vec3 n) {
  vec3 sum = vec3(0.0), leaving = n, entering = n;
  for (uint k = 0u; k < 4u; ++k) {
    const vec3 from = q + (k == 1u || k == 2u ? a : -a) + (k >= 2u ? b : -b);
    const vec3 to = q + (k == 0u || k == 1u ? a : -a) + (k == 1u || k == 2u ? b : -b);
    const float hf = dot(n, from), ht = dot(n, to);
    const bool fromAbove = hf >= 0.0, toAbove = ht >= 0.0;
    const vec3 crossing = fromAbove != toAbove ? from + (to - from) * (hf / (hf - ht)) : from;
    const vec3 edge = edgeVector(fromAbove ? from : crossing, toAbove ? to : crossing);
    sum += fromAbove || toAbove ? edge : vec3(0.0);
    leaving = fromAbove && !toAbove ? crossing : leaving;
    entering = !fromAbove && toAbove ? crossing : entering;
  }
  sum += edgeVector(leaving, entering);  // none where nothing was clipped (both n)
  return 0.5 * (dot(sum, n) < 0.0 ? -sum : sum);
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

// Adds what cluster s sends toward the receiver (at pr, its normal and cone nr). A curved cluster
// sends what its table holds toward the receiver, over its solid angle (a disk's on its axis). A flat
// one sends its exitance and antiradiance over its rectangle's exact solid angle, scaled to the
// cluster's area: into the bins (what a curved receiver's irradiance and J take) the rectangle's
// solid angle, into a flat receiver's vector sum its Lambert's vector. Clusters are linked up to a
// form factor of --eps, near enough that a disk on its axis would take too little of one seen
// askew, and the light of a sender turned away from a flat receiver's centre still reaches the part
// of the receiver that sees it.
void gatherCluster(uint s, vec3 pr, vec4 nr) {
  const vec4 ps = nodePositionArea(s);
  const vec3 d = ps.xyz - pr;
  const float dist2 = dot(d, d);
  if (dist2 <= 1e-6 * ps.w) return;  // coincident: no direction to bin it in
  const vec3 dir = d * inversesqrt(dist2);
  const vec4 cone = nodeNormalCone(s);
  const Taps back = tapsOf(-dir);
  const vec3 table = READ_TAPS(intensity, s * kBins, back.bins, keepSide(cone, -dir, back));
  const Taps taps = tapsOf(dir);
  const float perArea = solidAnglePerArea(ps.w, dist2);
  if (cone.w > kArFlatCone) {
    deposit(nr, dir, taps, table * perArea, 1.0, inversesqrt(dist2), vec3(0.0), vec3(0.0));
    return;
  }
  const float cosine = dot(cone.xyz, -dir);
  const vec3 front = imageLoad(exitance, int(s)).rgb * step(0.0, cosine);
  const vec3 sent = (front - table) * abs(cosine) * perArea;
  vec3 sideA, sideB;
  senderSides(s, cone, sideA, sideB);
  const float rectangle = 4.0 * length(sideA) * length(sideB);
  if (nr.w <= kArFlatCone) {
    const vec3 phi = rectangle > 0.0 ? ps.w / rectangle * rectangleVector(d, sideA, sideB, nr.xyz)
                                     : (dot(nr.xyz, dir) >= 0.0 ? ps.w * abs(cosine) * perArea * dir : vec3(0.0));
    depositInVector(nr, dir, (front - table) / ps.w, phi, sent, inversesqrt(dist2),
                    (front - table * sign(cosine)) * perArea, cone.xyz + cosine * dir);
  }
  const float omegaPerArea =
      rectangle > 0.0 ? abs(rectangleSolidAngle(d, sideA, sideB)) / rectangle : abs(cosine) * perArea;
  depositInBins(nr, dir, taps, (front - table) * omegaPerArea, 1.0);
}

// Adds what surfel sender s sends toward the receiver (at pr, its normal and cone nr, its area): as
// pieces of its rectangle, each along its own direction (surfelPieces).
void gatherSurfel(uint s, vec3 pr, vec4 nr, float receiverArea) {
  const vec4 ps = nodePositionArea(s);
  const vec3 d = ps.xyz - pr;
  const float dist2 = dot(d, d);
  if (dist2 <= 1e-6 * ps.w) return;  // coincident: no direction to bin it in
  const vec4 ns = nodeNormalCone(s);
  if (abs(dot(ns.xyz, d)) <= 1e-4 * sqrt(dist2)) return;  // the receiver lies in its plane: it sends nothing there
  const uint surfel = imageLoad(tree, int(s)).w;
  const uint pieces = surfelPieces(ps.w, dist2, kDirs);
  vec3 sideA, sideB;
  senderSides(s, ns, sideA, sideB);
  const float pieceArea = ps.w / float(pieces * pieces);
  // What its lobe sends beyond its radiance toward the receiver, spread over the receiver's extent
  // and at least what the tables resolve (a bin's solid angle over 4: engine/gi/bins.h's
  // tableBinSpread).
  const float receiverExtent = receiverArea / (dist2 + receiverArea / kPi);
  vec3 lobe = excessToward(s, pr, receiverExtent, kPi / float(kBins)) / kPi;
  // A glossy dielectric's base leaves by its exit angle (baseBeyondEven), taken at the centre.
  if (kBasesByAngle) {
    const SurfaceBrdf brdf = surfelBrdf[surfel];
    const vec3 own =
        imageLoad(radiance, int(surfel)).rgb - (push.emittersByMaps == 0u ? emission[surfel].rgb : vec3(0.0));
    lobe += max(own, vec3(0.0)) * baseBeyondEven(brdf, dot(ns.xyz, -d) * inversesqrt(dist2));
  }
  for (uint j = 0u; j < pieces * pieces; ++j) {
    const vec2 at = (vec2(j % pieces, j / pieces) + 0.5) / float(pieces) * 2.0 - 1.0;
    const vec3 q = d + at.x * sideA + at.y * sideB;
    const float q2 = dot(q, q);
    if (q2 <= 1e-6 * ps.w) continue;
    const vec3 dir = q * inversesqrt(q2);
    const float cosine = dot(ns.xyz, -dir), perArea = solidAnglePerArea(pieceArea, q2);
    const float omega = pieceArea * perArea * abs(cosine);
    // In the bins, a piece wider than a bin is credited one bin's worth: they hold radiance, which
    // J passes on, and a near piece's light taken along one direction would pass on more than it
    // has (its neighbours on a curved surface, each in the others' near field, fed it back).
    const float binOmega = imageLoad(binTable, int(binOf(dir, kDirs))).w;
    const Taps taps = tapsOf(dir);
    const float binShare = omega > binOmega ? binOmega / omega : 1.0;
    const vec3 radiance = surfelRadiance(surfel, kBins, ns, dir, taps, lobe);
    deposit(nr, dir, taps, radiance * omega, binShare, inversesqrt(q2), radiance * (sign(cosine) * pieceArea * perArea),
            ns.xyz + cosine * dir);
  }
}

// The sender of the k-th link of the receiver's two lists (the static one first).
uint fixedFirst, fixedCount, frameFirst;
uint senderAt(uint k) {
  const uint key =
      k < fixedCount ? imageLoad(staticSenders, int(fixedFirst + k)).x : imageLoad(senders, int(frameFirst + k)).x;
  return key & ~kEmitterBit;
}

void main() {
  if (itemIndex() >= push.nodeCount) return;
  uint r = gatherOrder[itemIndex()];
  // This dispatch's chunk of the two lists; the chunks after the first go on from the table and
  // vector sums the one before left.
  fixedFirst = staticStarts[r], fixedCount = staticStarts[r + 1u] - fixedFirst;
  frameFirst = starts[r] - fixedCount;
  const uint end = fixedCount + starts[r + 1u] - starts[r];
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
  // Each list holds its clusters first (walkKey). Each kind has a loop of its own, so that a lane
  // runs only its own kind's body: lavapipe runs every branch a subgroup reaches, taken or not.
  uint k = from;
  for (uint part = 0u; part < 2u; ++part) {
    const uint partEnd = part == 0u ? min(to, fixedCount) : to;
    for (; k < partEnd; ++k) {
      const uint s = senderAt(k);
      if (imageLoad(tree, int(s)).z == 0u) break;
      gatherCluster(s, pr, nr);
    }
    for (; k < partEnd; ++k) gatherSurfel(senderAt(k), pr, nr, receiverArea);
  }
  for (uint b = 0u; kTableHere && b < kBins; ++b) imageStore(gathered, int(tableBase + b), vec4(gatheredHere[b], 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r), vec4(vectorX, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 1u), vec4(vectorY, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 2u), vec4(vectorZ, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 3u), vec4(slopeX, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 4u), vec4(slopeY, 0.0));
  imageStore(gatheredVector, int(kArVectorTexels * r + 5u), vec4(slopeZ, 0.0));
}

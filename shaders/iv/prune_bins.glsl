// The prune's bins (prune_bins.comp): a leaf's nearest key and covered solid angle per bin, in
// shared memory or its workgroup's global slot, merged with a static leaf's static entries; the
// gaps between a surface's elements closed; what a survivor gives (form factor, proximity,
// environment through the uncovered part).
// Included by prune_bins.comp after its bindings, specialization constants and shared memory.

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
// Whether the leaf sees the nodes from its object's rest pose (common.glsl's nodeTurn, nodeShift):
// its bins are then fixed to its object.
bool posed = false;

// What bin b holds: the nearest key and the covered solid angle (in 1/kCoverageUnit of the bin),
// the filed senders merged with the leaf's static entry; staticCovered is that entry's share.
struct Bin {
  uint64_t key;
  uint covered;
  uint staticCovered;
  int staticEntry;
  float staticDistance2;
};

// The leaf's static entry for bin i of its static mask word `word`, or −1: none, or past a static
// pass that overflowed (the frame is then redone).
int staticEntryIn(uvec2 word, uint i) {
  const uint bit = 1u << i, e = staticFirst + word.y + bitCount(word.x & (bit - 1u));
  return (word.x & bit) != 0u && e < push.staticCapacity ? int(e) : -1;
}
// The same for bin b, once markFiledBins has kept the words (staticWords); −1 where not merging.
int staticEntryOf(uint b) { return merging ? staticEntryIn(staticWords[b / 32u], b & 31u) : -1; }

// The covered solid angle of static entry e (−1: none, 0).
uint staticCoverageAt(int e) { return e >= 0 ? staticCoverageOf(loadParted(staticBins, uint(e)).x) : 0u; }

Bin binAt(uint slot, uint b) {
  Bin bin = Bin(loadBin(slot, b), loadCoverage(slot, b), 0u, -1, 0.0);
  int e = staticEntryOf(b);
  if (e < 0) return bin;
  const uint entry = uint(e);
  uint staticDepth = loadParted(staticDepths, entry).x;
  bin.key = min(bin.key, uint64_t(staticDepth) << 32 | loadParted(staticLinks, entry).x);
  bin.staticDistance2 = uintBitsToFloat(staticDepth & 0x7FFFFFFFu);  // less the fringe bit
  bin.staticCovered = staticCoverageAt(e);
  bin.staticEntry = e;
  bin.covered += bin.staticCovered;
  return bin;
}

// Covered solid angle of bin b: the frame's senders and the leaf's static entry, or that entry alone.
uint coverageAt(uint slot, uint b, bool staticOnly) {
  return (staticOnly ? 0u : loadCoverage(slot, b)) + staticCoverageAt(staticEntryOf(b));
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
// The neighbours' tests are bits that markFiledBins sets in one sweep (`halfCovered`: the filed
// senders with the leaf's static entries; `staticHalfCovered`: those entries alone), read one after
// another, not in a loop: lavapipe bounds the loop rounds a subgroup may run over all the leaves of
// its workgroup.
bool neighbourHalfCovered(uint b, ivec2 step, bool staticOnly) {
  const uint neighbour = neighbourBin(b, step), bit = 1u << (neighbour & 31u);
  return ((staticOnly ? staticHalfCovered[neighbour >> 5] : halfCovered[neighbour >> 5]) & bit) != 0u;
}
uint closedCoverage(uint b, uint covered, bool staticOnly) {
  if (covered == 0u || covered >= kCoverageUnit) return covered;
  return neighbourHalfCovered(b, ivec2(1, 0), staticOnly) && neighbourHalfCovered(b, ivec2(-1, 0), staticOnly) &&
                 neighbourHalfCovered(b, ivec2(0, 1), staticOnly) && neighbourHalfCovered(b, ivec2(0, -1), staticOnly)
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

// The environment's radiance in the leaf's bin b: the world's bins, as filtered over each, interpolated
// bilinearly at b's centre turned back into the world, so that a bin brighter than its neighbours (a
// sun) sends about its own light into the leaf's bins however they lie across it (the nearest world
// bin would send it into none or two). In a frame along the world's axes, b's centre is a world
// bin's: that bin's radiance alone. For odd N a bin the horizon cuts is read at the mean direction
// of its part above it (binTable), and so is every bin, alike.
vec3 environmentIn(uint b) {
  uvec4 bins;
  vec4 weights;
  const vec3 at = (kN & 1u) != 0u ? normalize(imageLoad(binTable, int(b)).xyz) : binDirection(b, kN);
  binTaps(transpose(nodeTurn) * at, kN, bins, weights);
  return weights.x * imageLoad(environment, int(bins.x)).rgb + weights.y * imageLoad(environment, int(bins.y)).rgb +
         weights.z * imageLoad(environment, int(bins.z)).rgb + weights.w * imageLoad(environment, int(bins.w)).rgb;
}

// Adds the environment's radiance through the part `open` of bin b (its uncovered part, or how much
// that changed), cosine-weighted (0 below the horizon), to `light`, and to `turn` how that changes
// as the normal turns (columns r, g, b, each the turn's axis weighed: ∫ n × ω dω over the bin times
// the radiance seen).
void addEnvironmentThrough(vec3 n, uint b, float open, inout vec3 light, inout mat3 turn) {
  const vec3 along = imageLoad(binTable, int(b)).xyz;
  const float c = dot(n, along);
  if (!(c > 0.0)) return;
  const vec3 seen = environmentIn(b) * open;
  light += c * seen;
  turn += outerProduct(cross(n, along), seen);
}

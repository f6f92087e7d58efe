// A receiver's surviving links (gather, lobe_excess, lobe_links): its frame's, ranges[s] in
// leafLinks; then, for a static leaf, those pruned once against static senders, staticRanges[s] in
// staticLinks, less those whose bin the frame's senders override. Expects staticBins and overrides
// declared; with LINK_BATCHES also ranges, leafLinks, staticRanges, staticLinks and a push constant
// `push` with maskWords, and GL_KHR_shader_subgroup_ballot enabled.

// Whether static link i of receiver s stands (the frame's senders do not override its bin).
bool staticLinkStands(uint s, uint i, uint maskWords) {
  const uint bin = staticBinOf(loadParted(staticBins, i).x);
  return (imageLoad(overrides, int(s * maskWords + bin / 32u)).x & (1u << (bin & 31u))) == 0u;
}

#ifdef LINK_LANES
// Passes that weigh each link of a receiver (lobe_excess, reflect_receivers) take their
// workgroup's receivers one after another, its lanes walking each one's links together (lane l
// links l, l + kReceiverGroup, …). Neighbouring links lie in neighbouring bins, mostly on one
// surface, so the lanes take the same branches; lanes each on a receiver of their own ran every
// branch any one of their senders took, and waited on the longest list.
uint linkLane() { return gl_LocalInvocationID.x; }

shared vec3 laneSums[2][kReceiverGroup];
// a and b summed over the workgroup's lanes in lane order, in every lane; every lane calls it.
void sumLanes(inout vec3 a, inout vec3 b) {
  laneSums[0][linkLane()] = a, laneSums[1][linkLane()] = b;
  barrier();
  a = b = vec3(0.0);
  for (uint l = 0u; l < kReceiverGroup; ++l) a += laneSums[0][l], b += laneSums[1][l];
  barrier();
}

// The workgroup's receivers, from `start` (the first of the dispatch's), while below `count` (each
// read once).
#define FOR_GROUP_RECEIVERS(k, start, count) \
  for (uint k = (start) + groupIndex() * kReceiverGroup, k##End = min(k + kReceiverGroup, (count)); k < k##End; ++k)

#ifdef LINK_BATCHES
// A CPU device runs the body of a branch for all of a subgroup's lanes, masked, whichever take it:
// work that only the links of a few senders need, done in the walk, would cost it for every link.
// So walkLinksInBatches hands each standing link to visitLink, which does what every link needs and
// says whether the link needs more; those gather in a batch, in lane order, and a loop of their
// own hands them to batchedLink, a lane each. The pass defines both after including this.
bool visitLink(uvec2 link);
void batchedLink(uvec2 link);

const uint kLinkBatch = 32u * kReceiverGroup;
shared uvec2 linkBatch[kLinkBatch];
// Where the workgroup spans subgroups: the lanes that batched a link in a round, a word a round,
// three in turn, so that the word of the round after next is cleared while this round's is read.
shared uint batchedLanes[3];

// The lanes' writes to the batch seen by every lane; every lane calls it.
void batchBarrier() {
  if (groupInOneSubgroup) {
    subgroupMemoryBarrierShared();
    subgroupBarrier();
  } else {
    barrier();
  }
}

// Adds link to the batch where `batch`; `batched` (the same in every lane) grows by the lanes that
// did. Every lane calls it, `round` counting its calls.
void batchLink(bool batch, uvec2 link, inout uint batched, inout uint round) {
  uint before, count;
  if (groupInOneSubgroup) {
    const uvec4 lanes = subgroupBallot(batch);
    before = subgroupBallotExclusiveBitCount(lanes), count = subgroupBallotBitCount(lanes);
  } else {
    const uint word = round++ % 3u, lane = linkLane();
    if (batch) atomicOr(batchedLanes[word], 1u << lane);
    if (lane == 0u) batchedLanes[(word + 1u) % 3u] = 0u;
    barrier();
    const uint lanes = batchedLanes[word];
    before = bitCount(lanes & ((1u << lane) - 1u)), count = bitCount(lanes);
  }
  if (batch) linkBatch[batched + before] = link;
  batched += count;
}

// Receiver s's standing links, through visitLink and batchedLink; every lane calls it.
void walkLinksInBatches(uint s) {
  if (!groupInOneSubgroup) {
    if (linkLane() < 3u) batchedLanes[linkLane()] = 0u;
    barrier();
  }
  uint round = 0u;
  const uvec2 range = imageLoad(ranges, int(s)).xy, staticRange = imageLoad(staticRanges, int(s)).xy;
  const uint end = range.x + range.y, staticEnd = staticRange.x + staticRange.y;
  uint next = range.x, nextStatic = staticRange.x;
  while (next < end || nextStatic < staticEnd) {
    uint batched = 0u;
    for (; next < end && batched + kReceiverGroup <= kLinkBatch; next += kReceiverGroup) {
      const uint i = next + linkLane();
      const uvec2 link = i < end ? loadParted(leafLinks, i).xy : uvec2(0u);
      batchLink(i < end && visitLink(link), link, batched, round);
    }
    for (; nextStatic < staticEnd && batched + kReceiverGroup <= kLinkBatch; nextStatic += kReceiverGroup) {
      const uint i = nextStatic + linkLane();
      const uvec2 link = i < staticEnd ? loadParted(staticLinks, i).xy : uvec2(0u);
      batchLink(i < staticEnd && staticLinkStands(s, i, push.maskWords) && visitLink(link), link, batched, round);
    }
    batchBarrier();
    for (uint j = linkLane(); j < batched; j += kReceiverGroup) batchedLink(linkBatch[j]);
    batchBarrier();  // read before the next batch overwrites it
  }
}
#endif
#endif

// A receiver's surviving links (gather, lobe_excess, lobe_links): its frame's, ranges[s] in
// leafLinks; then, for a static leaf, those pruned once against static senders, staticRanges[s] in
// staticLinks, less those whose bin the frame's senders override. Expects staticBins and overrides
// declared.

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
#endif

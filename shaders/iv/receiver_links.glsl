// A receiver's surviving links (gather, reflect_links): its frame's, ranges[s] in leafLinks; then,
// for a static leaf, those pruned once against static senders, staticRanges[s] in staticLinks, less
// those whose bin the frame's senders override. Expects staticBins and overrides declared.

// Whether static link i of receiver s stands (the frame's senders do not override its bin).
bool staticLinkStands(uint s, uint i, uint maskWords) {
  const uint bin = staticBinOf(loadParted(staticBins, i).x);
  return (imageLoad(overrides, int(s * maskWords + bin / 32u)).x & (1u << (bin & 31u))) == 0u;
}

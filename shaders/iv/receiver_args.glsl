// The receivers' dispatch sizes between the steps of a refinement round (docs/design.md §2.4),
// written by the last workgroup of the step before (select_receivers, refine_receivers) or by
// receiver_args.comp. The including shader declares `receiverCounts` and `receiverArgs`.

// A round starts with the candidates in list `source`: their dispatch size, list `target` emptied
// for the next round's, and the receivers listed from here on the round's.
void startRound(uint source, uint target) {
  receiverArgs[kArgsCandidates] = groupsFor(receiverCounts[source], kReceiverGroup);
  receiverCounts[target] = 0u;
  receiverCounts[kReceiverRound] = receiverCounts[kReceiverCount];
}

// The round's receivers listed: the dispatch sizes over the new ones (one prune batch after
// another: `batches` of `batch` receivers, `leavesPerGroup` a workgroup, at most `maxGroups`) and over
// every receiver.
void receiversListed(uint batch, uint leavesPerGroup, uint maxGroups, uint batches) {
  const uint all = receiverCounts[kReceiverCount], fresh = all - receiverCounts[kReceiverRound];
  receiverArgs[kArgsNewReceivers] = groupsFor(fresh, kReceiverGroup);
  receiverArgs[kArgsReceivers] = groupsFor(all, kReceiverGroup);
  for (uint b = 0u; b < batches; ++b) {
    const uint left = fresh > b * batch ? min(fresh - b * batch, batch) : 0u;
    receiverArgs[kArgsPruneBatches + b] =
        uvec4(min((left + leavesPerGroup - 1u) / leavesPerGroup, maxGroups), 1u, 1u, 0u);
  }
}

#include "engine/gi/iv/receivers.h"

#include <cmath>
#include <numeric>

#include "engine/gi/bins.h"
#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// --receiver-tol t bounds the interpolation's error: a sample may miss its prediction from the
// samples around it by t of its irradiance, and a node's support may reach kProximity·√t times the
// harmonic mean distance of what its receiver sees (irradiance changes over that distance, after
// Ward's irradiance cache; a linear interpolation's error grows with the square of the support).
constexpr float kProximity = 3.2f;
// No cell is larger than 1/kCellsAcross of the scene: the tests judge by samples, and a shadow's edge
// between samples spaced wider than that might go unseen.
constexpr float kCellsAcross = 8.0f;
// A sample darker than this share of the largest is judged against it (the tests judge by the direct
// light, to which the bounces add most where it is dark).
constexpr float kDirectFloor = 0.1f;

}  // namespace

Receivers::Receivers(const vk::Context& ctx, const Hierarchy& h, const IvSettings& settings, IvBuffers& b,
                     vk::Allocations& allocations)
    : settings_(settings),
      b_(b),
      surfelCount_(uint32_t(h.leafOfSurfel.size())),
      nodeCount_(uint32_t(h.nodes.size())),
      levels_(h.levels()),
      groupCount_(uint32_t(h.groups.size())),
      rootCount_(uint32_t(h.roots.size())),
      largestCell_(h.size / kCellsAcross),
      args_(shaderProgram(ctx, "receiver_args")),
      select_(shaderProgram(ctx, "select_receivers")),
      refine_(shaderProgram(ctx, "refine_receivers")),
      roles_(shaderProgram(ctx, "receiver_roles")),
      reach_(shaderProgram(ctx, "receiver_reach")),
      neighbours_(shaderProgram(ctx, "neighbour_lists")),
      weights_(shaderProgram(ctx, "interpolation_weights")),
      seen_(shaderProgram(ctx, "seen_nodes")) {
  const size_t nodes = h.nodes.size(), surfels = surfelCount_;
  vk::Allocations* tally = &allocations;
  b.representatives = vk::makeBuffer(ctx, h.representatives, vk::Memory::Device, tally);
  b.levelStarts = vk::makeBuffer(ctx, h.levelStart, vk::Memory::Device, tally);
  b.receiverCounts = vk::Buffer(ctx, gpu::kReceiverSlots * sizeof(uint32_t), vk::Memory::Host, tally);
  b.receiverArgs = vk::deviceArray<glm::uvec4>(ctx, gpu::kArgsPruneBatches + std::max<size_t>(surfels, 1), allocations);
  b.receivers = vk::deviceArray<uint32_t>(ctx, surfels, allocations);
  b.receiverRadius = vk::deviceArray<uint32_t>(ctx, surfels, allocations);
  b.tapCounts = vk::deviceArray<uint32_t>(ctx, surfels, allocations);
  b.taps = vk::deviceArray<gpu::InterpolationTap>(ctx, surfels * gpu::kInterpolationTaps, allocations);
  b.gathered = vk::deviceArray<glm::vec4>(ctx, surfels, allocations);
  b.rotationGradients = vk::deviceArray<glm::vec4>(ctx, 3 * surfels, allocations);
  b.proximity = vk::deviceArray<float>(ctx, surfels, allocations);
  const bool refines = !everySurfel();
  b.candidatesA = vk::deviceArray<uint32_t>(ctx, refines ? nodes : 0, allocations);
  b.candidatesB = vk::deviceArray<uint32_t>(ctx, refines ? nodes : 0, allocations);
  b.reach = vk::deviceArray<glm::vec2>(ctx, refines ? nodes : 0, allocations);
  b.needs = vk::deviceArray<float>(ctx, refines ? nodes : 0, allocations);
  b.presences = vk::deviceArray<float>(ctx, refines ? nodes : 0, allocations);
  b.seenNodes = vk::deviceArray<uint32_t>(ctx, guidedByView() ? nodes : 0, allocations);
  b.roles = vk::deviceArray<float>(ctx, refines ? nodes : 0, allocations);
  b.groups = vk::makeBuffer(ctx, refines ? h.groups : std::vector<uint32_t>{}, vk::Memory::Device, tally);
  b.groupOfSurfel = vk::makeBuffer(ctx, refines ? h.groupOfSurfel : std::vector<uint32_t>{}, vk::Memory::Device, tally);
  b.neighbourCounts = vk::deviceArray<uint32_t>(ctx, refines ? h.groups.size() : 0, allocations);
  b.neighbours = vk::deviceArray<uint32_t>(ctx, refines ? h.groups.size() * gpu::kGroupNeighbours : 0, allocations);
  roots_ = vk::makeBuffer(ctx, h.roots, vk::Memory::Device, tally);
  if (!refines) makeEverySurfelReceiver(ctx, b);
}

Receivers::Lists Receivers::listsOf(uint32_t round) {
  return round % 2 ? Lists{gpu::kReceiverCandidatesB, gpu::kReceiverCandidatesA}
                   : Lists{gpu::kReceiverCandidatesA, gpu::kReceiverCandidatesB};
}

const vk::Buffer& Receivers::listBuffer(uint32_t slot) const {
  return slot == gpu::kReceiverCandidatesA ? b_.candidatesA : b_.candidatesB;
}

gpu::ReceiverPush Receivers::push(Lists lists, const Prune::Batching& batching) const {
  return {.source = lists.in,
          .target = lists.out,
          .tolerance = *settings_.receiverTolerance,
          .proximity = kProximity * std::sqrt(*settings_.receiverTolerance),
          .nodeCount = nodeCount_,
          .surfelCount = surfelCount_,
          .floorShare = kDirectFloor,
          .groupCount = groupCount_,
          .largest = largestCell_,
          .unseenShare = followsView() ? 1.0f / settings_.unseenTolerance : 1.0f,
          .batch = batching.batch,
          .leavesPerGroup = batching.leavesPerGroup,
          .maxGroups = batching.maxGroups,
          .batches = batching.batches};
}

void Receivers::recordArgs(VkCommandBuffer cmd, uint32_t mode, Lists lists, const Prune::Batching& batching) const {
  args_.dispatch(cmd, {}, {{"receiverCounts", b_.receiverCounts}, {"receiverArgs", b_.receiverArgs}},
                 gpu::ReceiverArgsPush{.mode = mode,
                                       .source = lists.in,
                                       .target = lists.out,
                                       .batch = batching.batch,
                                       .leavesPerGroup = batching.leavesPerGroup,
                                       .maxGroups = batching.maxGroups,
                                       .batches = batching.batches});
}

void Receivers::makeEverySurfelReceiver(const vk::Context& ctx, IvBuffers& b) const {
  std::vector<uint32_t> all(surfelCount_);
  std::iota(all.begin(), all.end(), 0u);
  std::vector<gpu::InterpolationTap> own(size_t(surfelCount_) * gpu::kInterpolationTaps, {0u, 0u});
  const uint32_t one = 0x3F800000u;  // 1.0f
  for (uint32_t s = 0; s < surfelCount_; ++s) own[size_t(s) * gpu::kInterpolationTaps] = {s, one};
  b.receivers.upload(all);
  b.taps.upload(own);
  b.tapCounts.upload(std::vector<uint32_t>(surfelCount_, 1u));
  b.rotationGradients.upload(std::vector<glm::vec4>(3 * size_t(surfelCount_), glm::vec4(0.0f)));  // never turned
  std::vector<uint32_t> counts(gpu::kReceiverSlots, 0u);
  counts[gpu::kReceiverCount] = surfelCount_;
  b.receiverCounts.upload(counts);
  ctx.submitAndWait([&](VkCommandBuffer cmd) { recordArgs(cmd, gpu::kArgsListed, listsOf(0), {1, 1, 1, 0}); });
}

void Receivers::recordStart(VkCommandBuffer cmd) const {
  std::vector<uint32_t> counts(gpu::kReceiverSlots, 0u);
  counts[gpu::kReceiverCandidatesA] = rootCount_;
  vk::updateBuffer(cmd, b_.receiverCounts, 0, counts.size() * sizeof(uint32_t), counts.data());
  const glm::uvec4 candidates = gpu::groupsFor(counts[gpu::kReceiverCandidatesA], gpu::kReceiverGroup);
  vk::updateBuffer(cmd, b_.receiverArgs, gpu::kArgsCandidates * sizeof(glm::uvec4), sizeof(candidates), &candidates);
  vk::fillBuffer(cmd, b_.receiverRadius, gpu::kNotReceiver);
  vk::fillBuffer(cmd, b_.needs, 0u);
  vk::fillBuffer(cmd, b_.presences, 0u);
  vk::fillBuffer(cmd, b_.rotationGradients, 0u);  // each receiver's estimate writes its own
  if (rootCount_ > 0) vk::copyRegion(cmd, roots_, b_.candidatesA, {0, 0, rootCount_ * sizeof(uint32_t)});
  if (followsView()) {
    vk::fillBuffer(cmd, b_.seenNodes, 0u);
    seen_.dispatchItems(cmd, surfelCount_, b_.pool().with({{"shownSurfels", *shown_}, {"views", *camera_}}),
                        gpu::SeenPush{.surfelCount = surfelCount_, .leastSpread = senderBinSpread(settings_.bins)});
  }
}

void Receivers::recordSelect(VkCommandBuffer cmd, uint32_t round, const Prune::Batching& batching) const {
  const Lists lists = listsOf(round);
  select_.dispatchIndirect(cmd, b_.receiverArgs, gpu::kArgsCandidates * sizeof(glm::uvec4),
                           b_.pool().with({{"candidatesIn", listBuffer(lists.in)}}), push(lists, batching));
}

void Receivers::recordRefine(VkCommandBuffer cmd, uint32_t round, const Prune::Batching& batching) const {
  const Lists lists = listsOf(round);
  refine_.dispatchIndirect(
      cmd, b_.receiverArgs, gpu::kArgsCandidates * sizeof(glm::uvec4),
      b_.pool().with({{"candidatesIn", listBuffer(lists.in)}, {"candidatesOut", listBuffer(lists.out)}}),
      push(lists, batching));
}

void Receivers::recordWeights(VkCommandBuffer cmd, const Prune::Batching& batching) const {
  roles_.dispatchItems(cmd, nodeCount_, b_.pool(), push(listsOf(0)));
  reach_.dispatchItems(cmd, nodeCount_, b_.pool(), gpu::CountPush{.count = nodeCount_});
  const Lists none{gpu::kReceiverCandidatesA, gpu::kReceiverCandidatesB};
  neighbours_.dispatchItems(cmd, groupCount_, b_.pool(), push(none));
  recordArgs(cmd, gpu::kArgsStartRound, none, batching);  // fills are listed from here
  weights_.dispatchItems(cmd, surfelCount_, b_.pool(), push(none));
  recordArgs(cmd, gpu::kArgsListed, none, batching);
}

Receivers::Counts Receivers::counts() const {
  const auto c = b_.receiverCounts.read<uint32_t>(gpu::kReceiverSlots);
  return {c[gpu::kReceiverCount], c[gpu::kReceiverFills]};
}

}  // namespace ivgi::gi

#include "engine/gi/iv_solver.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "engine/gi/pass.h"
#include "engine/gi/shared.h"

namespace ivgi::gi {

namespace {

struct LevelPush {
  uint32_t first, count;
};
struct ArgsPush {
  uint32_t source, clear, slot, groupSize;
};
struct RefinePush {
  uint32_t source, target, capacity, linkCapacity;
  float epsilon, binSolidAngle;
};
struct PrunePush {
  uint32_t firstSurfel, endSurfel, linkCapacity, lightCount, environmentOn, staticCapacity;
};
struct GatherPush {
  uint32_t surfelCount, maskWords;
};
constexpr uint32_t kNoCounter = 0xFFFFFFFFu;
constexpr uint32_t kCounterLinks = 2, kCounterLeafLinks = 3, kCounterOverflow = 4, kCounterWorklistPeak = 5, kCounterSendersWalked = 6;
// Bits of the overflow counter (common.glsl).
constexpr uint32_t kOverflowWorklist = 1, kOverflowLinks = 2, kOverflowLeafLinks = 4, kOverflowLoopBudget = 8;
constexpr uint32_t kMinPruneGroups = 512;
constexpr uint32_t kPathChunk = 512;  // root-path senders prune_bins.comp gathers per round, and its queue of wide ones
constexpr uint32_t kStaticEmitters = 64;  // emitters a static leaf keeps for the frame's direct light (prune_bins.comp)
constexpr uint32_t kEmitterQueue = 256;   // emitters a leaf lists (prune_bins.comp), counted in its shared memory

uint32_t maskWordsFor(uint32_t n) { return (6 * n * n + 31) / 32; }

// prune_bins.comp's workgroup: whole subgroups of at least 8 invocations (its wide senders are filed
// 8 lanes apiece). lavapipe runs a workgroup's subgroups one after another on one thread, switching
// at every barrier, of which a leaf's prune has seven or more: at 6×16×16 bins a workgroup of one
// subgroup (8 lanes) pruned 4,756 surfels in 375–380 ms, 16, 32 and 64 lanes in 413–418, 423–436
// and 466–493 ms. But each subgroup has its own loop budget of 65,535 rounds (common.glsl), which
// the rounds of its workgroup's leaves, divided among its subgroups, must stay within: a leaf at
// 6×16×16 bins takes about a thousand on one subgroup (the budget ran out after 56–74 leaves), a
// finer leaf about N² times as many, a leaf with a long root path more (one of 42,496 senders at
// 63,457 surfels ran out alone). A workgroup starts with (N/16)² subgroups, or one per 16,384
// surfels at 6×16×16 bins (per 32,768 at 6×8×8: coarser bins, shorter root paths; a power of two),
// at most 8: the Cornell box needed 1 at 4,756 surfels, 2 at 17,574 and 4 at 63,457 (2 at 6×8×8
// bins), and 8 at 6×64×64 bins. When one ran out the frame is redone with twice as many. (Unaware
// of the budget, workgroups of 124 leaves at 63k surfels lost ~60 % of the survivors: the "desync"
// of earlier notes.)
uint32_t firstPruneSubgroups(uint32_t n, uint32_t surfels) {
  const uint64_t perSurfels = (uint64_t(surfels) * n + 16 * 16384 - 1) / (16 * 16384);
  return std::clamp<uint32_t>(std::max<uint64_t>(n * n / (16 * 16), std::bit_ceil(perSurfels)), 1u, 8u);
}
uint32_t maxPruneGroupSize(const vk::Context& ctx) {
  const VkPhysicalDeviceLimits& limits = ctx.limits();
  return std::min({256u, limits.maxComputeWorkGroupSize[0], limits.maxComputeWorkGroupInvocations});
}
uint32_t pruneGroupSize(const vk::Context& ctx, uint32_t subgroups) {
  return std::min(std::max(ctx.subgroupSize(), 8u) * subgroups, maxPruneGroupSize(ctx));
}
constexpr uint32_t kLeavesPerGroup = 8;  // a prune workgroup's leaves per dispatch, unless the settings say

// Specialization constants of prune_bins.comp.
std::vector<uint32_t> pruneConstants(uint32_t n, bool sharedBins, bool staticPass, uint32_t groupSize) {
  return {n, sharedBins ? 1u : 0u, sharedBins ? 6 * n * n : 1u, maskWordsFor(n), kPathChunk, staticPass ? 1u : 0u, kStaticEmitters, kEmitterQueue,
          groupSize};
}

// The room an array that grows with a count gets: a quarter more, so that the next frames'
// changes fit.
uint32_t withMargin(uint32_t needed) { return uint32_t(std::min<uint64_t>(uint64_t(needed) * 5 / 4 + 1024, 0xFFFFFFF0u)); }

vk::Buffer counterBuffer(const vk::Context& ctx) {  // zero: a set never linked has not overflowed
  vk::Buffer counters(ctx, 8 * sizeof(uint32_t), vk::Memory::Host);
  counters.upload(std::vector<uint32_t>(8, 0u));
  return counters;
}

template <class T>
vk::Buffer deviceArray(const vk::Context& ctx, size_t count) {
  return vk::Buffer(ctx, std::max<size_t>(count, 1) * sizeof(T), vk::Memory::Device);
}

}  // namespace

std::vector<GpuLight> worldLights(const scene::Scene& scene, const scene::Pose& pose) {
  std::vector<GpuLight> out;
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].light < 0) continue;
    const scene::Light& l = scene.lights[scene.nodes[i].light];
    const glm::mat4& m = pose.world[i];
    glm::vec3 dir = -glm::vec3(m[2]);
    float len = glm::length(dir);
    dir = len > 0 ? dir / len : glm::vec3(0, 0, -1);
    float type = l.type == scene::Light::Type::Directional ? 0.0f : (l.type == scene::Light::Type::Point ? 1.0f : 2.0f);
    out.push_back({glm::vec4(glm::vec3(m[3]), type), glm::vec4(dir, l.range), glm::vec4(l.color * l.intensity, 0.0f),
                   glm::vec4(std::cos(l.outerCone), std::cos(l.innerCone), 0.0f, 0.0f)});
  }
  return out;
}

IvSetup makeIvSetup(const scene::Scene& scene, const scene::Geometry& g, const IvSettings& settings, std::optional<int> animation) {
  auto rest = scene::surfelsOnHost(g, scene::animateOnHost(g, g.frameInputs(scene, scene::evaluatePose(scene, -1, 0.0f))));
  IvSetup setup{buildHierarchy(g, rest), settings, {}};
  if (animation) markMovingObjects(setup, scene, g, *animation);
  return setup;
}

void markMovingObjects(IvSetup& setup, const scene::Scene& scene, const scene::Geometry& g, int animation) {
  std::vector<bool> moving = scene::movingInstances(scene, g, animation);
  setup.objectMoves.clear();
  for (uint32_t instance : setup.hierarchy.rootInstance) setup.objectMoves.push_back(moving[instance]);
}

std::vector<glm::vec4> IvSolver::binTable(uint32_t n) {
  std::vector<glm::vec4> table(6 * n * n);
  for (uint32_t b = 0; b < table.size(); ++b) table[b] = glm::vec4(glm::normalize(binDirection(b, n)), binSolidAngle(b, n));
  return table;
}

bool IvSolver::binsFitShared(const vk::Context& ctx, uint32_t n) {
  // bins and coverage, mask and word starts, partial sums (of the largest workgroup), the chunk of
  // root-path senders and its wide ones, the emitter queue and its sorted copy (prune_bins.comp)
  uint64_t bytes = uint64_t(6) * n * n * (8 + 4) + uint64_t(maskWordsFor(n)) * 8 + maxPruneGroupSize(ctx) * 16 + 16 + kPathChunk * 8 + 4 + kEmitterQueue * 8 + 4;
  return ctx.sharedInt64Atomics() && bytes <= ctx.limits().maxComputeSharedMemorySize;
}

uint32_t IvSolver::maskWords() const { return maskWordsFor(settings_.bins); }

IvSolver::IvSolver(const vk::Context& ctx, const scene::Geometry& g, const IvSetup& setup)
    : ctx_(ctx),
      hierarchy_(setup.hierarchy),
      settings_(setup.settings),
      surfelCount_(uint32_t(g.surfels.size())),
      nodeCount_(uint32_t(setup.hierarchy.nodes.size())),
      sharedBins_(binsFitShared(ctx, setup.settings.bins)),
      pruneSubgroups_(firstPruneSubgroups(setup.settings.bins, uint32_t(g.surfels.size()))),
      refit_(ctx, "refit"),
      linkArgs_(ctx, "link_args"),
      refine_(ctx, "refine_links"),
      countLinks_(ctx, "count_links"),
      scanCounts_(ctx, "scan_counts"),
      scatterLinks_(ctx, "scatter_links"),
      emit_(ctx, "emit"),
      gather_(ctx, "gather"),
      pullUp_(ctx, "pull_up") {
  const IvSettings& settings = setup.settings;
  const Hierarchy& h = setup.hierarchy;
  if (settings.bins < 1 || settings.bins > 64) throw vk::VulkanError("--bins must be 1 to 64");
  makePrunePasses();
  if (!settings.environment.empty() && settings.environment.size() != 6 * settings.bins * settings.bins)
    throw vk::VulkanError("environment table does not match the bins");
  if (!setup.objectMoves.empty() && setup.objectMoves.size() != h.roots.size()) throw vk::VulkanError("objectMoves does not match the hierarchy");
  // Pairs of two static objects are linked and pruned once, but only when something else moves.
  auto moves = [&](size_t root) { return setup.objectMoves.empty() || setup.objectMoves[root]; };
  bool anyMoves = false, anyStatic = false;
  for (size_t r = 0; r < h.roots.size(); ++r) (moves(r) ? anyMoves : anyStatic) = true;
  // A static leaf keeps a mask word pair per 32 bins; where those exceed what one binding can
  // address (many surfels at many bins), every object is relinked instead.
  const uint64_t maskBytes = uint64_t(surfelCount_) * maskWords() * sizeof(glm::uvec2);
  const bool split = anyMoves && anyStatic && maskBytes <= ctx.limits().maxStorageBufferRange;
  for (size_t a = 0; a < h.roots.size(); ++a)
    for (size_t b = 0; b < h.roots.size(); ++b) {
      auto& pairs = (split && !moves(a) && !moves(b) ? staticSet_ : frameSet_).rootPairs;
      pairs.insert(pairs.end(), {h.roots[a], h.roots[b]});
    }
  std::vector<uint32_t> leafMoves(surfelCount_, 1u);
  if (split) {  // a node moves with its root; parents are numbered before their children
    std::vector<bool> nodeMoves(nodeCount_, false);
    for (size_t r = 0; r < h.roots.size(); ++r) nodeMoves[h.roots[r]] = moves(r);
    for (uint32_t node = 0; node < nodeCount_; ++node)
      if (h.nodes[node].parent >= 0) nodeMoves[node] = nodeMoves[uint32_t(h.nodes[node].parent)];
    for (uint32_t s = 0; s < surfelCount_; ++s) leafMoves[s] = nodeMoves[h.leafOfSurfel[s]] ? 1u : 0u;
  }
  tree_ = vk::makeBuffer(ctx, h.nodes);
  leafOfSurfel_ = vk::makeBuffer(ctx, h.leafOfSurfel);
  leafMoves_ = vk::makeBuffer(ctx, leafMoves);
  albedo_ = vk::makeBuffer(ctx, g.surfelAlbedo);
  emission_ = vk::makeBuffer(ctx, g.surfelEmission);
  binTable_ = vk::makeBuffer(ctx, binTable(settings.bins));
  environment_ = vk::makeBuffer(ctx, settings.environment.empty() ? std::vector<glm::vec4>{glm::vec4(0)} : settings.environment);
  lights_ = vk::Buffer(ctx, sizeof(GpuLight), vk::Memory::Host);
  nodes_ = deviceArray<NodeState>(ctx, nodeCount_);
  args_ = vk::Buffer(ctx, 4 * sizeof(glm::uvec4), vk::Memory::Device);
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    set->roots = vk::makeBuffer(ctx, set->rootPairs.empty() ? std::vector<uint32_t>{0, 0} : set->rootPairs);
    set->counters = counterBuffer(ctx);
    set->counts = deviceArray<uint32_t>(ctx, set->rootPairs.empty() ? 0 : nodeCount_);
    set->starts = deviceArray<uint32_t>(ctx, set->rootPairs.empty() ? 0 : nodeCount_ + 1);
    // 30.7 links a node in the Cornell box at 17,574 surfels, 32.5 at 63,457 (6×16×16 bins), 41 at
    // 10k surfels and 6×64×64 bins (more bins refine further).
    set->linkCapacity = set->rootPairs.empty() ? 0 : 48 * nodeCount_ + 1024;
    set->leafLinkCapacity = firstLeafLinkGuess(*set, leafMoves);
  }
  ranges_ = deviceArray<glm::uvec2>(ctx, surfelCount_);
  external_ = deviceArray<glm::vec4>(ctx, surfelCount_);
  radiosityA_ = deviceArray<glm::vec4>(ctx, nodeCount_);
  radiosityB_ = deviceArray<glm::vec4>(ctx, nodeCount_);
  irradiance_ = deviceArray<glm::vec4>(ctx, surfelCount_);
  // What a static leaf keeps between frames; with nothing static, empty ranges and one-word stand-ins.
  const size_t masks = split ? maskBytes / sizeof(glm::uvec2) : 0;
  staticRanges_ = deviceArray<glm::uvec2>(ctx, surfelCount_);
  staticMasks_ = deviceArray<glm::uvec2>(ctx, masks);
  overrides_ = deviceArray<uint32_t>(ctx, masks);
  staticEnvironment_ = deviceArray<glm::vec4>(ctx, split ? surfelCount_ : 0);
  staticEmitters_ = deviceArray<uint32_t>(ctx, split ? size_t(surfelCount_) * kStaticEmitters : 0);
  staticEmitterCounts_ = deviceArray<uint32_t>(ctx, split ? surfelCount_ : 0);
  staticCorrection_ = deviceArray<glm::vec4>(ctx, split ? surfelCount_ : 0);
  if (sharedBins_) {
    globalBins_ = vk::Buffer(ctx, 16, vk::Memory::Device);
    globalCoverage_ = vk::Buffer(ctx, 16, vk::Memory::Device);
  } else {
    uint64_t slots = uint64_t(pruneGroups()) * 6 * settings.bins * settings.bins;
    globalBins_ = vk::Buffer(ctx, slots * 8, vk::Memory::Device);
    globalCoverage_ = vk::Buffer(ctx, slots * 4, vk::Memory::Device);
  }
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, staticRanges_.handle(), 0, VK_WHOLE_SIZE, 0u);
    clearGlobalBins(cmd);
  });
  // The refinement's widest level held 6.8 pairs a node in the Cornell box, 8.4 in the furnace and
  // 11 in Fox.gltf: 16 a node seldom needs a second try.
  worklistCapacity_ = std::max<uint32_t>(uint32_t(std::max(staticSet_.rootPairs.size(), frameSet_.rootPairs.size()) / 2), 16 * nodeCount_ + 1024);
  if (!linkArraysRefusal(linkArrays()).empty())  // the guess does not fit the device: start small, grow to what the frame counts
    for (LinkSet* set : {&staticSet_, &frameSet_})
      set->leafLinkCapacity = set->rootPairs.empty() ? 0 : surfelCount_ * std::min(6 * settings.bins * settings.bins, 128u) + 1024;
  allocateLinks();
}

// A first guess at a set's surviving links, so that the first frame is not pruned twice (once to
// count them): a leaf the set prunes in full keeps about the bins of its hemisphere, 3N² (703 a
// static leaf in the Cornell box at 4,756 surfels, 826 in the closed furnace at 16 bins, 12,468 at
// 64 bins; fewer in an open scene, whose surplus the first frame gives back); a static leaf merging
// the frame's senders re-emits only the bins they touch, N²/2 (66 a leaf there, about 670 at 64
// bins); plus the usual margin.
uint32_t IvSolver::firstLeafLinkGuess(const LinkSet& set, const std::vector<uint32_t>& leafMoves) const {
  if (set.rootPairs.empty()) return 0;
  const uint64_t hemisphere = 3ull * settings_.bins * settings_.bins, merged = hemisphere / 6;
  uint64_t guess = 0;
  for (uint32_t moves : leafMoves) guess += &set == &staticSet_ ? (moves ? 0 : hemisphere) : (moves ? hemisphere : merged);
  return withMargin(uint32_t(std::min<uint64_t>(guess, 0xFFFFFFF0u)));
}

void IvSolver::makePrunePasses() {
  const uint32_t groupSize = pruneGroupSize(ctx_, pruneSubgroups_);
  pruneStatic_.emplace(ctx_, "prune_bins", pruneConstants(settings_.bins, sharedBins_, true, groupSize));
  pruneFrame_.emplace(ctx_, "prune_bins", pruneConstants(settings_.bins, sharedBins_, false, groupSize));
}

uint32_t IvSolver::pruneGroups() const {
  const uint32_t leaves = leavesPerGroup();
  uint32_t groups = std::min(std::max(surfelCount_, 1u), std::max(kMinPruneGroups, (surfelCount_ + leaves - 1) / leaves));
  if (!sharedBins_) {  // every workgroup owns a slot of 6·N² bins in one buffer within the device's range
    uint64_t slotBytes = uint64_t(6) * settings_.bins * settings_.bins * 8;  // the larger of the two slot arrays
    groups = std::min<uint32_t>(groups, uint32_t(std::max<uint64_t>(1, std::min<uint64_t>(ctx_.limits().maxStorageBufferRange, 512ull << 20) / slotBytes)));
  }
  return settings_.pruneGroups > 0 ? std::min(groups, settings_.pruneGroups) : groups;
}

uint32_t IvSolver::leavesPerGroup() const { return settings_.pruneLeaves > 0 ? settings_.pruneLeaves : kLeavesPerGroup; }
uint32_t IvSolver::pruneBatch() const { return pruneGroups() * leavesPerGroup(); }

uint32_t IvSolver::leafLinksHeld(const LinkSet& set) const {
  return std::min(set.leafLinkCapacity, set.counters.read<uint32_t>(8)[kCounterLeafLinks]);
}

std::vector<IvSolver::LinkArray> IvSolver::linkArrays() {
  // The leaf links are texels in prune_bins.comp and gather.comp; the rest storage buffers.
  std::vector<LinkArray> arrays = {{&worklistA_, worklistCapacity_, 8, false, "refinement worklist", nullptr},
                                   {&worklistB_, worklistCapacity_, 8, false, "refinement worklist", nullptr},
                                   {&leafLinks_, frameSet_.leafLinkCapacity, 8, true, "leaf links", &frameSet_},
                                   {&staticLinks_, staticSet_.leafLinkCapacity, 8, true, "static leaf links", &staticSet_},
                                   {&staticBins_, staticSet_.leafLinkCapacity, 4, true, "static leaf links' bins", &staticSet_},
                                   {&staticDepths_, staticSet_.leafLinkCapacity, 4, true, "static leaf links' depths", &staticSet_}};
  for (LinkSet* set : {&staticSet_, &frameSet_})
    arrays.insert(arrays.end(), {{&set->links, set->linkCapacity, 8, false, "links", nullptr}, {&set->senders, set->linkCapacity, 4, false, "links", nullptr}});
  return arrays;
}

std::string IvSolver::linkArraysRefusal(const std::vector<LinkArray>& arrays) const {
  auto refusal = [](uint64_t bytes, const std::string& what, const char* limit, uint64_t limitBytes) {
    return "the iv solver needs " + std::to_string(bytes >> 20) + " MiB of " + what + ", above the device's " + limit + " of " +
           std::to_string(limitBytes >> 20) + " MiB: raise --eps or lower --bins";
  };
  const VkPhysicalDeviceLimits& limits = ctx_.limits();
  uint64_t total = allocatedBytes();  // once every array has its new size
  for (const LinkArray& a : arrays) {
    if (!a.texels && a.bytes() > limits.maxStorageBufferRange) return refusal(a.bytes(), a.what, "maxStorageBufferRange", limits.maxStorageBufferRange);
    if (a.texels && a.elements() > limits.maxTexelBufferElements)
      return refusal(a.bytes(), a.what, "maxTexelBufferElements", uint64_t(limits.maxTexelBufferElements) * a.elementBytes);
    if (a.bytes() > ctx_.maxAllocationBytes()) return refusal(a.bytes(), a.what, "maxMemoryAllocationSize", ctx_.maxAllocationBytes());
    total = total - a.buffer->size() + std::max<uint64_t>(a.bytes(), a.buffer->size());  // grows what it had
  }
  if (total > ctx_.deviceHeapBytes()) return refusal(total, "device memory in all", "memory heap", ctx_.deviceHeapBytes());
  return {};
}

void IvSolver::allocateLinks() {
  const std::vector<LinkArray> arrays = linkArrays();
  if (std::string why = linkArraysRefusal(arrays); !why.empty()) throw vk::VulkanError(why);
  for (const LinkArray& a : arrays) {
    if (a.buffer->size() >= a.bytes()) continue;  // keeps what it holds
    *a.buffer = vk::Buffer();  // before its successor: the two need not fit at once
    *a.buffer = vk::Buffer(ctx_, a.bytes(), vk::Memory::Device);
  }
}

void IvSolver::releaseUnusedLinks() {
  // The static set's surviving links are made once and never grow: they keep exactly their room,
  // and the links they were pruned from are not needed again. The frame's keep the margin, and
  // shrink only past a third unused, lest every frame reallocate.
  bool shrinks = splitsStatic() && staticLinked_ && staticSet_.linkCapacity > 0;
  if (shrinks) staticSet_.linkCapacity = 0;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->rootPairs.empty()) continue;
    const uint32_t used = leafLinksHeld(*set), fitted = set == &staticSet_ ? used : withMargin(used);
    if (set == &staticSet_ ? set->leafLinkCapacity > fitted : uint64_t(set->leafLinkCapacity) * 2 > uint64_t(fitted) * 3)
      set->leafLinkCapacity = fitted, shrinks = true;
  }
  if (!shrinks) return;
  for (const LinkArray& a : linkArrays()) {
    if (std::max(a.bytes(), vk::Buffer::kMinBytes) >= a.buffer->size()) continue;
    vk::Buffer kept(ctx_, a.bytes(), vk::Memory::Device);
    const uint64_t used = a.leafLinksOf ? leafLinksHeld(*a.leafLinksOf) : 0;
    if (used > 0)  // the surviving links it holds
      ctx_.submitAndWait([&](VkCommandBuffer cmd) {
        const VkBufferCopy region{0, 0, used * a.elementBytes};
        vkCmdCopyBuffer(cmd, a.buffer->handle(), kept.handle(), 1, &region);
      });
    *a.buffer = std::move(kept);
  }
}

void IvSolver::setLights(const std::vector<GpuLight>& lights) {
  if (lights_.size() < lights.size() * sizeof(GpuLight)) lights_ = vk::Buffer(ctx_, lights.size() * sizeof(GpuLight), vk::Memory::Host);
  lights_.upload(lights);
  lightCount_ = uint32_t(lights.size());
}

void IvSolver::recordLinks(VkCommandBuffer cmd, LinkSet& set) {
  uint32_t start[2] = {uint32_t(set.rootPairs.size() / 2), 0};
  vkCmdFillBuffer(cmd, set.counters.handle(), 0, VK_WHOLE_SIZE, 0);
  vkCmdFillBuffer(cmd, set.counts.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::barrier(cmd);
  vkCmdUpdateBuffer(cmd, set.counters.handle(), 0, sizeof(start), start);
  VkBufferCopy copy{0, 0, set.rootPairs.size() * sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, set.roots.handle(), worklistA_.handle(), 1, &copy);
  vk::barrier(cmd);
  // Each level refines at least one side of every pair: at most the two trees' depths.
  const uint32_t iterations = refineIterations();
  const float omega = settings_.kappa * 4.0f * kPi / float(6 * settings_.bins * settings_.bins);
  for (uint32_t it = 0; it < iterations; ++it) {
    uint32_t in = it % 2, out = 1 - in;
    linkArgs_.dispatch(cmd, {1, 1, 1}, {&set.counters, &args_}, ArgsPush{in, out, 0, 256});
    vk::barrier(cmd);
    refine_.dispatchIndirect(cmd, args_, 0, {&tree_, &nodes_, in ? &worklistB_ : &worklistA_, in ? &worklistA_ : &worklistB_, &set.links, &set.counters},
                             RefinePush{in, out, worklistCapacity_, set.linkCapacity, settings_.epsilon, omega});
    vk::barrier(cmd);
  }
  // Links sorted by receiver: count, scan, scatter.
  linkArgs_.dispatch(cmd, {1, 1, 1}, {&set.counters, &args_}, ArgsPush{kCounterLinks, kNoCounter, 1, 256});
  vk::barrier(cmd);
  countLinks_.dispatchIndirect(cmd, args_, sizeof(glm::uvec4), {&set.links, &set.counts, &set.counters}, set.linkCapacity);
  vk::barrier(cmd);
  scanCounts_.dispatch(cmd, {1, 1, 1}, {&set.counts, &set.starts}, nodeCount_);
  vk::barrier(cmd);
  scatterLinks_.dispatchIndirect(cmd, args_, sizeof(glm::uvec4), {&set.links, &set.counts, &set.senders, &set.counters, &radiosityA_}, set.linkCapacity);
  vk::barrier(cmd);
}

// Empty bins in every global-memory slot. Each leaf empties the bins it touched; a prune cut short
// (lavapipe's loop budget) may not have, so a redo starts from this.
void IvSolver::clearGlobalBins(VkCommandBuffer cmd) {
  vkCmdFillBuffer(cmd, globalBins_.handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  vkCmdFillBuffer(cmd, globalCoverage_.handle(), 0, VK_WHOLE_SIZE, 0u);
  globalBinsDirty_ = false;
}

void IvSolver::recordPrune(VkCommandBuffer cmd, const vk::Program& pass, LinkSet& set) {
  // Batches of at most leavesPerGroup() leaves a workgroup: one batch where the bins are shared
  // memory, several where each workgroup's global-memory slot limits how many there can be.
  const uint32_t groups = pruneGroups(), batch = pruneBatch();
  for (uint32_t first = 0; first < surfelCount_; first += batch) {
    pass.dispatch(cmd, pass.groupsFor(groups, 1),
                  {&tree_, &nodes_, &set.starts, &set.senders, &leafOfSurfel_, &binTable_, &globalBins_, &ranges_, &leafLinks_, &set.counters,
                   &external_, &lights_, &environment_, &globalCoverage_, &leafMoves_, &staticRanges_, &staticLinks_, &staticBins_, &staticDepths_,
                   &staticMasks_, &staticEnvironment_, &overrides_, &radiosityA_, &staticEmitters_, &staticEmitterCounts_, &staticCorrection_,
                   &staticSet_.counters},
                  PrunePush{first, std::min(surfelCount_, first + batch), set.leafLinkCapacity, lightCount_, settings_.environment.empty() ? 0u : 1u,
                            staticSet_.leafLinkCapacity});
    vk::barrier(cmd);
  }
}

void IvSolver::record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool relink) {
  const auto& levels = hierarchy_.levelStart;
  auto eachLevelBottomUp = [&](auto&& body) {
    for (size_t l = levels.size() - 1; l-- > 0;) {
      body(LevelPush{levels[l], levels[l + 1] - levels[l]});
      vk::barrier(cmd);
    }
  };
  // Emitted radiosity π·Le at the leaves, pulled up: the bounces start from it, and the prune
  // credits emitters through it (their direct light is the prune's, their links carry the rest).
  auto emitAndPullUp = [&] {
    emit_.dispatchItems(cmd, surfelCount_, {&leafOfSurfel_, &emission_, &radiosityA_}, surfelCount_);
    vk::barrier(cmd);
    eachLevelBottomUp([&](LevelPush level) { pullUp_.dispatchItems(cmd, level.count, {&tree_, &nodes_, &radiosityA_}, level); });
  };
  const bool relinking = relink || !linked_;
  if (relinking) {
    // The static set's links and bins, once; the frame's every time the geometry moved.
    const bool linkStatic = splitsStatic() && !staticLinked_;
    timedPass(cmd, timer, "refit", [&] {
      eachLevelBottomUp([&](LevelPush level) { refit_.dispatchItems(cmd, level.count, {&tree_, &surfels, &nodes_}, level); });
      emitAndPullUp();
    });
    staticPasses_ += linkStatic ? 1 : 0;
    timedPass(cmd, timer, "links", [&] {
      if (linkStatic) recordLinks(cmd, staticSet_);
      recordLinks(cmd, frameSet_);
    });
    timedPass(cmd, timer, "prune", [&] {
      if (globalBinsDirty_) clearGlobalBins(cmd), vk::barrier(cmd);
      if (linkStatic) recordPrune(cmd, *pruneStatic_, staticSet_);
      recordPrune(cmd, *pruneFrame_, frameSet_);
    });
    linked_ = staticLinked_ = true;
  }
  timedPass(cmd, timer, "bounces", [&] {
    if (!relinking) emitAndPullUp();
    for (uint32_t k = 0; k <= settings_.bounces; ++k) {
      vk::Buffer& in = k % 2 ? radiosityB_ : radiosityA_;
      vk::Buffer& out = k % 2 ? radiosityA_ : radiosityB_;
      gather_.dispatchItems(cmd, surfelCount_,
                            {&leafOfSurfel_, &ranges_, &leafLinks_, &external_, &albedo_, &emission_, &in, &out, &irradiance_, &staticRanges_,
                             &staticLinks_, &staticBins_, &overrides_, &frameSet_.counters, &staticSet_.counters},
                            GatherPush{surfelCount_, maskWords()});
      vk::barrier(cmd);
      eachLevelBottomUp([&](LevelPush level) { pullUp_.dispatchItems(cmd, level.count, {&tree_, &nodes_, &out}, level); });
    }
    finalRadiosity_ = settings_.bounces % 2 ? 0 : 1;
  });
}

uint32_t IvSolver::refineIterations() const { return 2 * (hierarchy_.maxDepth() + 1) + 1; }

bool IvSolver::growIfOverflowed() {
  bool overflowed = false, budgetSpent = false;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->rootPairs.empty()) continue;
    auto c = set->counters.read<uint32_t>(8);
    if (uint32_t left = c[refineIterations() % 2]; left != 0)  // pairs still unrefined after the last level: a bug
      throw vk::VulkanError("iv link creation left " + std::to_string(left) + " pairs unrefined after " + std::to_string(refineIterations()) + " levels");
    if (c[kCounterOverflow] == 0) continue;
    if (c[kCounterOverflow] & kOverflowWorklist) worklistCapacity_ = std::max(worklistCapacity_, withMargin(c[kCounterWorklistPeak]));
    if (c[kCounterOverflow] & kOverflowLinks) set->linkCapacity = std::max(set->linkCapacity, withMargin(c[kCounterLinks]));
    if (c[kCounterOverflow] & kOverflowLeafLinks) set->leafLinkCapacity = std::max(set->leafLinkCapacity, withMargin(c[kCounterLeafLinks]));
    budgetSpent |= (c[kCounterOverflow] & kOverflowLoopBudget) != 0;
    overflowed = true;
    if (set == &staticSet_) staticLinked_ = false;  // a frame set's overflow leaves the static links whole
  }
  if (budgetSpent) {  // a prune workgroup ran out of loop rounds: twice the subgroups share them
    if (pruneGroupSize(ctx_, pruneSubgroups_) == maxPruneGroupSize(ctx_))
      throw vk::VulkanError("iv: pruning a leaf takes more loop rounds than this device allows a workgroup of " +
                            std::to_string(maxPruneGroupSize(ctx_)) + " invocations (lavapipe: 65,535 a subgroup); use fewer --bins or a larger --eps");
    pruneSubgroups_ *= 2;
    makePrunePasses();
    globalBinsDirty_ = !sharedBins_;  // the leaves cut short may have left their bins
  }
  if (overflowed) allocateLinks(), linked_ = false, ++framesRedone_;
  return overflowed;
}

IvStats IvSolver::stats() const {
  IvStats s;
  s.nodes = nodeCount_;
  s.levels = hierarchy_.levels();
  s.sharedBins = sharedBins_;
  s.pruneBatches = (surfelCount_ + pruneBatch() - 1) / pruneBatch();
  s.pruneGroupSize = pruneGroupSize(ctx_, pruneSubgroups_);
  s.framesRedone = framesRedone_, s.staticPasses = staticPasses_;
  for (const LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->rootPairs.empty()) continue;
    auto c = set->counters.read<uint32_t>(8);
    s.links += c[kCounterLinks];
    s.leafLinks += c[kCounterLeafLinks];
    const uint64_t walked = uint64_t(c[kCounterSendersWalked + 1]) << 32 | c[kCounterSendersWalked];
    if (set == &staticSet_) s.staticLinks = c[kCounterLinks], s.staticLeafLinks = c[kCounterLeafLinks], s.staticSendersWalked = walked;
    else s.sendersWalked = walked;
  }
  s.bytes = allocatedBytes();
  return s;
}

uint64_t IvSolver::allocatedBytes() const {
  uint64_t bytes = 0;
  for (const LinkSet* set : {&staticSet_, &frameSet_})
    for (const vk::Buffer* b : {&set->roots, &set->counters, &set->links, &set->counts, &set->starts, &set->senders}) bytes += b->size();
  for (const vk::Buffer* b : {&tree_, &leafOfSurfel_, &leafMoves_, &albedo_, &emission_, &binTable_, &environment_, &lights_, &nodes_, &args_,
                              &worklistA_, &worklistB_, &globalBins_, &globalCoverage_, &ranges_, &leafLinks_, &overrides_, &external_,
                              &radiosityA_, &radiosityB_, &irradiance_, &staticRanges_, &staticLinks_, &staticBins_, &staticDepths_, &staticMasks_,
                              &staticEnvironment_, &staticEmitters_, &staticEmitterCounts_, &staticCorrection_})
    bytes += b->size();
  return bytes;
}

std::vector<std::vector<IvSolver::LeafLink>> IvSolver::leafLinks() const {
  auto ranges = ranges_.read<glm::uvec2>(surfelCount_);
  auto all = leafLinks_.read<LeafLink>(leafLinksHeld(frameSet_));
  std::vector<std::vector<LeafLink>> out(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s)
    for (uint32_t k = ranges[s].x; k < ranges[s].x + ranges[s].y && k < all.size(); ++k) out[s].push_back(all[k]);
  if (!splitsStatic()) return out;
  auto staticRanges = staticRanges_.read<glm::uvec2>(surfelCount_);
  auto staticLinks = staticLinks_.read<LeafLink>(leafLinksHeld(staticSet_));
  auto staticBins = staticBins_.read<uint32_t>(leafLinksHeld(staticSet_));
  auto overrides = overrides_.read<uint32_t>(size_t(surfelCount_) * maskWords());
  for (uint32_t s = 0; s < surfelCount_; ++s)
    for (uint32_t k = staticRanges[s].x; k < staticRanges[s].x + staticRanges[s].y && k < staticLinks.size(); ++k) {
      uint32_t bin = staticBinOf(staticBins[k]);
      if (!(overrides[size_t(s) * maskWords() + bin / 32] & (1u << (bin & 31)))) out[s].push_back(staticLinks[k]);
    }
  return out;
}

std::vector<IvSolver::NodeState> IvSolver::nodeStates() const { return nodes_.read<NodeState>(nodeCount_); }

std::vector<glm::vec4> IvSolver::leafRadiosity() const {
  auto nodes = (finalRadiosity_ ? radiosityB_ : radiosityA_).read<glm::vec4>(nodeCount_);
  std::vector<glm::vec4> out(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s) out[s] = nodes[hierarchy_.leafOfSurfel[s]];
  return out;
}

}  // namespace ivgi::gi

#include "engine/gi/ar/solver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "engine/core/errors.h"
#include "engine/gi/ar/divergence.h"
#include "engine/gi/bins.h"
#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// Iterations recorded in a frame's first submission and in each more: the host judges them after
// each submission, so the frame runs up to a submission's worth past its tolerance. A warm start
// begins near its solution: its first submission is the two iterations that can show it settled.
constexpr uint32_t kIterationSteps = 4, kWarmFirstSteps = 2;

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// Per node, the emission of the surfels under it that outshine the scene's mean emission (zero
// where none does). Link creation gathers their light at each surfel, since the light of a
// concentrated source is what changes fastest across a receiver; a scene that glows evenly (the
// furnace) has none.
std::vector<glm::vec4> brightEmitters(const Hierarchy& h, const std::vector<glm::vec4>& emission) {
  const auto luminance = [](glm::vec4 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  double mean = 0;
  for (const glm::vec4& e : emission) mean += luminance(e);
  mean /= double(std::max<size_t>(emission.size(), 1));
  std::vector<glm::vec4> bright(h.nodes.size(), glm::vec4(0.0f));
  for (size_t i = h.nodes.size(); i-- > 0;) {  // children are numbered after their parents
    const gpu::TreeNode& t = h.nodes[i];
    if (t.childCount == 0 && luminance(emission[size_t(t.surfel)]) > mean) bright[i] = emission[size_t(t.surfel)];
    if (t.parent >= 0) bright[size_t(t.parent)] = glm::max(bright[size_t(t.parent)], bright[i]);
  }
  return bright;
}

}  // namespace

uint64_t ArSolver::tableBytes(uint64_t nodes, uint64_t surfels, uint32_t dirs, bool chained) {
  return (2 * nodes + (chained ? 2 : 1) * surfels) * 6ull * dirs * dirs * sizeof(glm::vec4);
}

ArSolver::ArSolver(const vk::Context& ctx, const scene::Geometry& g, Hierarchy hierarchy, const ArSettings& settings,
                   const std::vector<bool>& objectMoves)
    : ctx_(ctx),
      hierarchy_(std::move(hierarchy)),
      settings_((validate(settings), settings)),
      surfelCount_(uint32_t(g.surfels.size())),
      nodeCount_(uint32_t(hierarchy_.nodes.size())),
      refit_(ctx),
      linkCreation_(ctx),
      iteration_(ctx, hierarchy_, settings, b_, staticSet_, frameSet_, g, allocations_),
      sortSenders_(shaderProgram(ctx, "ar_sort_senders", {.constants = {{"kDirs", settings.dirs}}})),
      sortLongSenders_(shaderProgram(ctx, "ar_sort_long_senders", {.constants = {{"kDirs", settings.dirs}}})),
      queueArgs_(shaderProgram(ctx, "queue_args")),
      orderReceivers_(shaderProgram(ctx, "ar_order_receivers")),
      reflect_(shaderProgram(ctx, "ar_reflect", {.constants = {{"kDirs", settings.dirs}}})) {
  const uint32_t n = settings_.dirs, bins = 6 * n * n;
  // A receiver's senders are sorted by a key of a link's kind (0 to kArPieces) above its sender's node.
  static_assert(gpu::kArPieces < (1u << (31 - gpu::kArKindShift)));
  if (nodeCount_ > (1u << gpu::kArKindShift))
    throw SettingsError("the ar solver takes at most " + std::to_string(1u << gpu::kArKindShift) +
                        " nodes, and this scene makes " + std::to_string(nodeCount_) +
                        ": a smaller --tessellate makes fewer");
  // The tables first: they are what limits ar (as the paper says), so a refusal names --dirs.
  const VkPhysicalDeviceLimits& limits = ctx.limits();
  const bool chained = settings_.chained();
  const uint64_t tables = tableBytes(nodeCount_, surfelCount_, n, chained);
  const uint64_t largest = uint64_t(std::max(nodeCount_, surfelCount_)) * bins;
  // Device memory holds the tables while it can (a fifth kept for the rest); past it the largest go
  // to host memory, which the device reads across its bus. Refused only where host memory cannot
  // hold them either, or where one table passes what the device allows one allocation or view.
  const uint64_t surfelTable = uint64_t(surfelCount_) * bins * sizeof(glm::vec4),
                 nodeTable = uint64_t(nodeCount_) * bins * sizeof(glm::vec4);
  std::vector<uint64_t> tableSizes = {surfelTable, nodeTable, nodeTable};  // incident, gathered, intensity
  if (chained) tableSizes.push_back(surfelTable);                          // startIncident
  std::vector<size_t> bySize(tableSizes.size());
  std::iota(bySize.begin(), bySize.end(), 0);
  std::stable_sort(bySize.begin(), bySize.end(), [&](size_t a, size_t b) { return tableSizes[a] > tableSizes[b]; });
  uint64_t onDevice = tables;
  std::vector<vk::Memory> tableMemory(tableSizes.size(), vk::Memory::Device);
  for (size_t k : bySize)
    if (onDevice * 5 > deviceBudget() * 4) tableMemory[k] = vk::Memory::Host, onDevice -= tableSizes[k];
  const uint64_t hostHeld = ctx.hostHeapIsDeviceHeap() ? tables : tables - onDevice;
  const double overDevice = std::max(double(largest) / limits.maxTexelBufferElements,
                                     double(largest * sizeof(glm::vec4)) / double(ctx.maxAllocationBytes())),
               overHost = double(hostHeld) / double(ctx.hostHeapBytes()) * 1.25, over = std::max(overDevice, overHost);
  if (over > 1.0)
    throw SettingsError("the ar solver needs " + mib(tables) + " of directional tables (" + std::to_string(bins) +
                        " bins for each of " + std::to_string(nodeCount_) + " nodes and " +
                        std::to_string(surfelCount_) + " surfels), more than " +
                        (overHost > overDevice ? "the device's and the host's memory hold"
                                               : "the device allows in one allocation or texel buffer") +
                        ": --dirs " + std::to_string(std::max(1u, uint32_t(n / std::sqrt(over)))) +
                        " would fit (the tables grow as N^2)");
  vk::Allocations* tally = &allocations_;
  b_.scene = SceneBuffers(ctx, g, hierarchy_, n, BinFrame::World, settings_.environment, objectMoves, {}, allocations_);
  noteUnresolvedRoughness(g, tableBinSpread(n), "ar", "--dirs " + std::to_string(n));
  b_.brightEmitters = vk::makeBuffer(ctx, brightEmitters(hierarchy_, g.surfelEmission), vk::Memory::Device, tally);
  b_.args = vk::Buffer(ctx, 4 * sizeof(glm::uvec4), vk::Memory::Device, tally);
  b_.gathered = vk::Buffer(ctx, nodeTable, tableMemory[1], tally);
  b_.gatheredVector =
      vk::Buffer(ctx, uint64_t(nodeCount_) * gpu::kArVectorTexels * sizeof(glm::vec4), vk::Memory::Device, tally);
  b_.intensity = vk::Buffer(ctx, nodeTable, tableMemory[2], tally);
  b_.gatherOrder = vk::Buffer(ctx, nodeCount_ * sizeof(uint32_t), vk::Memory::Device, tally);
  b_.longSorts = vk::Buffer(ctx, (nodeCount_ + 1) * sizeof(uint32_t), vk::Memory::Device, tally);
  b_.exitance = vk::Buffer(ctx, nodeCount_ * sizeof(glm::vec4), vk::Memory::Device, tally);
  b_.incident = vk::Buffer(ctx, surfelTable, tableMemory[0], tally);
  b_.radiance = vk::Buffer(ctx, surfelCount_ * sizeof(glm::vec4), vk::Memory::Device, tally);
  b_.irradiance = vk::Buffer(ctx, surfelCount_ * sizeof(glm::vec4), vk::Memory::Device, tally);
  if (chained) {
    b_.startIncident = vk::Buffer(ctx, surfelTable, tableMemory[3], tally);
    b_.startRadiance = vk::Buffer(ctx, b_.radiance.size(), vk::Memory::Device, tally);
    b_.startIrradiance = vk::Buffer(ctx, b_.irradiance.size(), vk::Memory::Device, tally);
  }
  b_.gatherFlags = vk::makeBuffer(ctx, std::vector<uint32_t>(4, 0u), vk::Memory::Host, tally);
  sumGroups_ = iteration_.sumGroups();
  b_.sums =
      vk::Buffer(ctx, uint64_t(kIterationSteps) * sumGroups_ * sizeof(gpu::IterationSum), vk::Memory::Host, tally);

  // Every object with every other and with itself (ar cannot leave out a pair that moves less);
  // the pairs of two static objects linked once where something else moves.
  assignRootPairs(hierarchy_, objectMoves, mixesStaticAndMoving(objectMoves, hierarchy_.roots.size()), staticSet_,
                  frameSet_);
  // Nodes per object, whose pairs' links a set's room is guessed from.
  std::vector<uint32_t> rootOf(nodeCount_), objectNodes(nodeCount_, 0);
  for (uint32_t node = 0; node < nodeCount_; ++node) {  // parents are numbered before their children
    const int32_t parent = hierarchy_.nodes[node].parent;
    rootOf[node] = parent < 0 ? node : rootOf[uint32_t(parent)];
    ++objectNodes[rootOf[node]];
  }
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    set->allocateLists(ctx, nodeCount_, tally);
    // Both sides link, and wide receivers split too: a few times iv's links a node, shared out
    // between the sets by their pairs' nodes.
    uint64_t pairNodes = 0;
    for (size_t i = 0; i < set->rootPairs.size(); ++i) pairNodes += objectNodes[set->rootPairs[i]];
    const uint64_t allPairNodes = 2 * uint64_t(hierarchy_.roots.size()) * nodeCount_;
    set->linkCapacity = set->empty() ? 1 : uint32_t(96 * pairNodes * nodeCount_ / allPairNodes + 1024);
  }
  worklistCapacity_ =
      std::max<uint32_t>(uint32_t(hierarchy_.roots.size() * hierarchy_.roots.size()), 24 * nodeCount_ + 1024);
  allocateLinks();
}

void ArSolver::allocateLinks() {
  const VkPhysicalDeviceLimits& limits = ctx_.limits();
  const uint32_t most = std::max({staticSet_.linkCapacity, frameSet_.linkCapacity, worklistCapacity_});
  if (most > limits.maxTexelBufferElements || uint64_t(most) * 8 > ctx_.maxAllocationBytes())
    throw SettingsError("the ar solver needs " + std::to_string(most) + " links, more than the device holds: --eps " +
                        std::to_string(settings_.epsilon * 2.0f * float(most) / limits.maxTexelBufferElements) +
                        " would fit (links grow about as 1/eps)");
  vk::Allocations* tally = &allocations_;
  auto grow = [&](vk::Buffer& buffer, uint64_t bytes) {  // in host memory past the device's room
    if (buffer.size() >= bytes) return;
    buffer = vk::Buffer();  // before its successor: the two need not fit at once
    const bool fits = allocations_.deviceBytes() + bytes <= deviceBudget();
    buffer = vk::Buffer(ctx_, bytes, fits ? vk::Memory::Device : vk::Memory::Host, tally);
  };
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    grow(set->links, uint64_t(set->linkCapacity) * 8);
    grow(set->senders, uint64_t(set->linkCapacity) * 4);
  }
  grow(b_.worklistA, uint64_t(worklistCapacity_) * 8);
  grow(b_.worklistB, uint64_t(worklistCapacity_) * 8);
  if (allocations_.deviceBytes() > deviceBudget())
    throw SettingsError("the ar solver needs " + mib(allocations_.deviceBytes()) + " of device memory, above " +
                        (settings_.memoryBudget ? "--max-memory" : "the device's memory heap") +
                        ", besides what it holds in host memory: a coarser --tessellate or a smaller --dirs would fit");
  uint64_t host = 0;
  for (const vk::Buffer* b : {&b_.incident, &b_.startIncident, &b_.gathered, &b_.intensity, &staticSet_.links,
                              &staticSet_.senders, &frameSet_.links, &frameSet_.senders, &b_.worklistA, &b_.worklistB})
    host += b->memory() == vk::Memory::Host ? b->size() : 0;
  if (host > 0 && !saidHostMemory_) {
    saidHostMemory_ = true;
    std::fprintf(
        stderr,
        "ivgi: ar: the tables and links do not fit in %s: %.1f MiB of them are in host memory, which the "
        "device reads across its bus (slower); a smaller --dirs keeps them on the device\n",
        settings_.memoryBudget ? ("--max-memory of " + mib(settings_.memoryBudget)).c_str() : "the device's memory",
        double(host) / (1 << 20));
  }
}

uint64_t ArSolver::deviceBudget() const { return ctx_.deviceBudget(settings_.memoryBudget); }

int ArSolver::chainStart(int frame) const { return frame - frame % int(settings_.restartEvery); }

void ArSolver::beginFrame(int frame) {
  frame_ = frame;
  warm_ = frame > 0 && frame != chainStart(frame) && solved_ == frame - 1;
  redoing_ = false;
}

bool ArSolver::useDirectLight(const vk::Buffer& surfelDirect, const vk::Buffer& surfelArrival, bool withEnvironment) {
  b_.scene.takeDirectLight(surfelDirect, surfelArrival, withEnvironment);
  // The emitters' light no longer travels over links: none is taken down to the receivers' surfels.
  b_.brightEmitters =
      vk::makeBuffer(ctx_, std::vector<glm::vec4>(nodeCount_, glm::vec4(0.0f)), vk::Memory::Device, &allocations_);
  return true;
}

void ArSolver::setLights(const std::vector<gpu::PunctualLight>& lights) {
  b_.scene.setLights(ctx_, lights, allocations_);
}

uint32_t ArSolver::iterationLimit() const {
  if (cap_) return cap_;
  return settings_.iterations ? *settings_.iterations : kMaxIterations;
}

void ArSolver::record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool geometryMoved) {
  reused_ = !geometryMoved && linked_ && standing_;
  if (reused_) return;
  shownWarm_ = warm_;
  vk::fillBuffer(cmd, b_.gatherFlags, 0u);
  // A frame redone over the links it made (its iteration damped or capped, its lists walked in more
  // chunks) keeps them: only one that ran out of link room links again.
  if ((geometryMoved && !redoing_) || !linked_) {
    timedPass(cmd, timer, "refit", [&] { refit_.record(cmd, b_.scene, surfels); });
    timedPass(cmd, timer, "links", [&] {
      if (!staticLinked_ && !staticSet_.empty()) recordLinks(cmd, staticSet_);
      recordLinks(cmd, frameSet_);
      orderReceivers_.dispatch(cmd, orderReceivers_.groupsFor(nodeCount_, gpu::kArGatherGroup),
                               b_.pool().with({{"staticStarts", staticSet_.starts}, {"starts", frameSet_.starts}}),
                               gpu::CountPush{.count = nodeCount_});
    });
    linked_ = staticLinked_ = true;
  }
  recordStart(cmd, timer);
  solved_ = -1;  // until this frame stands
  if (!cap_) diverged_ = false;
  recorded_ = judged_ = 0;
  done_ = false;
  residuals_.clear(), negatives_.clear();
  recordIterations(cmd, timer, std::min(warm_ ? kWarmFirstSteps : kIterationSteps, iterationLimit()));
}

void ArSolver::recordStart(VkCommandBuffer cmd, vk::PassTimer& timer) {
  timedPass(cmd, timer, "local", [&] {
    if (!warm_) {
      vk::fillBuffer(cmd, b_.incident, 0u);
      // The first local pass reflects the depth maps' direct light where they give it (else zeros).
      vk::copyBuffer(cmd, b_.scene.surfelDirect(), b_.irradiance);
      vk::copyBuffer(cmd, b_.scene.emission, b_.radiance);
    } else if (redoing_) {
      vk::copyBuffer(cmd, b_.startIncident, b_.incident), vk::copyBuffer(cmd, b_.startRadiance, b_.radiance);
      vk::copyBuffer(cmd, b_.startIrradiance, b_.irradiance);
    } else {
      vk::copyBuffer(cmd, b_.incident, b_.startIncident), vk::copyBuffer(cmd, b_.radiance, b_.startRadiance);
      vk::copyBuffer(cmd, b_.irradiance, b_.startIrradiance);
    }
  });
}

void ArSolver::recordLinks(VkCommandBuffer cmd, LinkSet& set) {
  const float split = settings_.kappa * meanBinSolidAngle(settings_.dirs);
  const vk::Buffer& buried = &set == &staticSet_ ? b_.scene.nodeStillBuried : b_.scene.nodeBuried;
  // ar links the faces turned away too (bothSides), so iv's nodeFlags are not read: any stands in.
  const vk::Bindings pool = b_.pool().plus(vk::Bindings::pool({{"nodeFlags", b_.scene.nodeLeaves}}));
  linkCreation_.record(cmd, set, LinkWork{b_.args, b_.worklistA, b_.worklistB, b_.brightEmitters, buried, pool},
                       hierarchy_,
                       LinkCriteria{.epsilon = settings_.epsilon,
                                    .largeSender = split,
                                    .largeReceiver = split,
                                    .bothSides = true,
                                    .emitterReceiver = 0.0f,
                                    .receiverStaysWhole = false,
                                    .skipBuriedSenders = !settings_.linkBuriedSenders},
                       worklistCapacity_);
  // The senders in order: the short lists an invocation each, the long ones a workgroup each.
  vk::fillBuffer(cmd, b_.longSorts, 0u, 0, sizeof(uint32_t));
  const vk::Bindings sorting = b_.pool().with({{"starts", set.starts}, {"senders", set.senders}});
  sortSenders_.dispatchItems(cmd, nodeCount_, sorting, gpu::CountPush{.count = nodeCount_});
  constexpr uint32_t kLongSortArgs = 2;  // the slot in args after link creation's
  queueArgs_.dispatch(cmd, {1, 1, 1}, {{"queue", b_.longSorts}, {"args", b_.args}},
                      gpu::QueueArgsPush{.slot = kLongSortArgs});
  sortLongSenders_.dispatchIndirect(cmd, b_.args, kLongSortArgs * sizeof(glm::uvec4), sorting);
}

void ArSolver::recordIterations(VkCommandBuffer cmd, vk::PassTimer& timer, uint32_t steps) {
  const bool timedEach = timer.room() > 3 * steps + 16;  // else the whole submission is one pass
  auto body = [&] {
    for (uint32_t k = 0; k < steps; ++k) {
      const uint32_t i = recorded_ + k;
      const bool radianceStep = settings_.scheme == ArScheme::Symmetric || i % (gpu::kAntiradianceSteps + 1) == 0;
      iteration_.record(cmd, timer,
                        ArStep{.radianceStep = radianceStep,
                               .sumSlot = k,
                               .chunks = gatherChunks_,
                               .chunkLinks = chunkLinks(),
                               .damping = damping_,
                               .timed = timedEach});
    }
  };
  if (timedEach)
    body();
  else if (timer.room() > 0)
    timedPass(cmd, timer, "iterations", body);
  else
    body();
  recorded_ += steps;
}

void ArSolver::judge() const {
  if (judged_ == recorded_) return;
  const auto sums = b_.sums.read<gpu::IterationSum>(size_t(recorded_ - judged_) * sumGroups_);
  for (uint32_t k = 0; judged_ + k < recorded_; ++k) {
    double total = 0, change = 0, negative = 0;
    for (uint32_t g = 0; g < sumGroups_; ++g) {
      const gpu::IterationSum& s = sums[size_t(k) * sumGroups_ + g];
      total += s.total, change += s.change, negative += s.negative;
    }
    residuals_.push_back(total > 0 ? float(change / total) : (change > 0 ? 1.0f : 0.0f));
    negatives_.push_back(total > 0 ? float(negative / total) : 0.0f);
  }
  const std::ptrdiff_t fresh = recorded_ - judged_;  // the iterations just judged
  judged_ = recorded_;
  const std::optional<std::string> why =
      cap_ ? std::nullopt : divergence(residuals_, negatives_, size_t(fresh), damping_);
  if (why) {
    const auto best = std::min_element(residuals_.begin(), residuals_.end());
    if (damping_ == 1.0f) firstDivergence_ = *why;
    redo_ = done_ = true;
    if (damping_ > settings_.leastDamping) return void(damping_ *= 0.5f);
    cap_ = uint32_t(best - residuals_.begin()) + 1;
    diverged_ = true;
    char damped[80] = "";
    if (damping_ < 1.0f)
      std::snprintf(damped, sizeof damped, " undamped, and still grew with each step damped to %.3g", double(damping_));
    std::fprintf(stderr, "ivgi: ar: the iteration diverges (%s%s); the frame shows iteration %u, its best\n",
                 firstDivergence_.c_str(), damped, cap_);
    return;
  }
  if (recorded_ >= iterationLimit()) return void(done_ = true);
  if (settings_.iterations || cap_) return;
  // Converged once a whole cycle (an iteration; asymmetric: a radiance step and its antiradiance
  // steps) changed the irradiance by less than the tolerance.
  const size_t cycle = settings_.scheme == ArScheme::Symmetric ? 1 : gpu::kAntiradianceSteps + 1;
  if (residuals_.size() < cycle + 1) return;
  done_ = *std::max_element(residuals_.end() - cycle, residuals_.end()) < settings_.tolerance;
}

bool ArSolver::wantsMorePasses() const {
  if (reused_) return false;
  for (const LinkSet* set : {&staticSet_, &frameSet_})
    if (set->readCounters()[gpu::kCounterOverflow] != 0) return false;  // the frame is redone
  if (b_.gatherFlags.read<uint32_t>(1)[0] != 0) return false;           // a list too long: see frameMustBeRedone
  judge();
  return !done_;
}

void ArSolver::recordMorePasses(VkCommandBuffer cmd, vk::PassTimer& timer) {
  recordIterations(cmd, timer, std::min(nextSteps(), iterationLimit() - recorded_));
}

uint32_t ArSolver::nextSteps() const {
  // Iterating to the tolerance on the symmetric scheme, whose changes shrink about geometrically
  // (alternating between faster and slower steps): as many as the ratio over the last two steps
  // (one, after a warm start's first two) says are left, so that the frame stops soon after it
  // settles rather than up to a submission's worth past it. Too few cost a submission more, not
  // accuracy.
  if (settings_.iterations || cap_ || settings_.scheme != ArScheme::Symmetric || residuals_.size() < 2)
    return kIterationSteps;
  const size_t span = std::min<size_t>(2, residuals_.size() - 1);
  const double last = residuals_.back(), before = residuals_[residuals_.size() - 1 - span];
  if (!(last > 0.0 && last < before)) return kIterationSteps;
  const double left = std::ceil(std::log(settings_.tolerance / last) / (std::log(last / before) / double(span)));
  return uint32_t(std::clamp(left, 1.0, double(kIterationSteps)));
}

bool ArSolver::frameMustBeRedone() {
  redoing_ = !reused_ && mustRedo();
  if (redoing_) ++framesRedone_;
  return redoing_;
}

bool ArSolver::mustRedo() {
  bool grew = false;
  for (LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->empty()) continue;
    if (set->growLinks(set->refinedCounters(), worklistCapacity_)) {
      grew = true;
      if (set == &staticSet_) staticLinked_ = false;
    }
  }
  if (grew) {
    allocateLinks();
    linked_ = false;
    return true;
  }
  const uint32_t flags = b_.gatherFlags.read<uint32_t>(1)[0];
  if (flags & gpu::kArFlagUnsorted)
    throw SettingsError("the ar solver made a receiver node " + std::to_string(longestList()) +
                        " links, more than it orders on this device (" + std::to_string(gpu::kArSortedMost) +
                        "): a larger --kappa or --eps makes fewer");
  if (flags & gpu::kArFlagChunks) {  // a list longer than the global pass's chunks walked
    gatherChunks_ = (longestList() + chunkLinks() - 1) / chunkLinks();
    return true;
  }
  if (settings_.redoEachFrameOnce && !redoing_) return true;
  if (!redo_) return false;
  redo_ = false;
  return true;
}

void ArSolver::frameStands() {
  if (reused_) {  // the solution shown is still the frame's that solved it: its figures too
    solved_ = diverged_ ? -1 : frame_;
    return;
  }
  standing_ = true;
  if (damping_ < 1.0f && !diverged_)
    std::fprintf(stderr,
                 "ivgi: ar: the iteration diverges undamped (%s); with each step damped to %.3g it settled in %u "
                 "iterations\n",
                 firstDivergence_.c_str(), double(damping_), recorded_);
  solved_ = diverged_ ? -1 : frame_;
  cap_ = 0;
  frameDamping_ = damping_, damping_ = 1.0f;
}

void ArSolver::recordReflections(VkCommandBuffer cmd, vk::PassTimer& timer, glm::vec4 eye, const vk::Buffer& shown,
                                 const vk::Buffer& lobes) {
  timedPass(cmd, timer, "reflections", [&] {
    reflect_.dispatchItems(
        cmd, surfelCount_, b_.pool().with({{"surfelLobe", lobes}, {"shownSurfels", shown}}),
        gpu::LobePush{.eye = eye, .surfelCount = surfelCount_, .leastSpread = tableBinSpread(settings_.dirs)});
  });
}

std::vector<std::pair<std::string, double>> ArSolver::frameFigures() const {
  return {{"iterations", double(recorded_)},
          {"warm", shownWarm_ ? 1.0 : 0.0},
          {"residual", residuals_.empty() ? 0.0 : double(residuals_.back())},
          {"diverged", diverged_ ? 1.0 : 0.0},
          {"damping", double(frameDamping_)}};
}

uint32_t ArSolver::longestList() const {
  const std::vector<uint32_t> fixed = staticSet_.starts.read<uint32_t>(nodeCount_ + 1);
  const std::vector<uint32_t> frame = frameSet_.starts.read<uint32_t>(nodeCount_ + 1);
  uint32_t longest = 0;
  for (uint32_t node = 0; node < nodeCount_; ++node)
    longest = std::max(longest, fixed[node + 1] - fixed[node] + frame[node + 1] - frame[node]);
  return longest;
}

std::vector<std::vector<uint32_t>> ArSolver::senderLists(bool staticLinks) const {
  const LinkSet& set = staticLinks ? staticSet_ : frameSet_;
  const std::vector<uint32_t> starts = set.starts.read<uint32_t>(nodeCount_ + 1);
  const std::vector<uint32_t> senders = set.senders.read<uint32_t>(std::max(starts.back(), 1u));
  std::vector<std::vector<uint32_t>> lists(nodeCount_);
  for (uint32_t node = 0; node < nodeCount_; ++node)
    lists[node].assign(senders.begin() + starts[node], senders.begin() + starts[node + 1]);
  return lists;
}

ArStats ArSolver::stats() const {
  ArStats s;
  s.nodes = nodeCount_, s.levels = hierarchy_.levels();
  for (const LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->empty()) continue;
    const uint32_t links = set->readCounters()[gpu::kCounterLinks];
    s.links += links;
    if (set == &staticSet_) s.staticLinks = links;
  }
  s.longestList = longestList();
  s.gatherChunks = gatherChunks_;
  s.bytes = allocatedBytes();
  s.tableBytes = tableBytes(nodeCount_, surfelCount_, settings_.dirs, settings_.chained());
  s.iterations = recorded_;
  s.warm = warm_;
  s.residual = residuals_.empty() ? 0.0f : residuals_.back();
  s.negative = negatives_.empty() ? 0.0f : negatives_.back();
  s.diverged = diverged_;
  s.damping = frameDamping_;
  s.framesRedone = framesRedone_;
  s.residuals = residuals_;
  return s;
}

}  // namespace ivgi::gi

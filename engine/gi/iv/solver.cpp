#include "engine/gi/iv/solver.h"

#include <algorithm>
#include <bit>
#include <cstdio>

#include "engine/core/errors.h"
#include "engine/gi/bins.h"
#include "engine/gi/iv/creases.h"
#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// Bounces recorded in a frame's first submission, and in each more where they have not converged:
// steps past convergence run zero workgroups, so the first covers most scenes in one submission.
constexpr uint32_t kFirstBounceSteps = 8, kMoreBounceSteps = 32;

// The setup checked, with the receivers' tolerance settled for the device.
IvSetup validated(const vk::Context& ctx, IvSetup setup) {
  validate(setup.settings);
  setup.settings.receiverTolerance = receiverToleranceOn(setup.settings, ctx.info().type == "cpu");
  if (!setup.objectMoves.empty() && setup.objectMoves.size() != setup.hierarchy.roots.size())
    throw std::invalid_argument("IvSetup: objectMoves does not match the hierarchy");
  if (!setup.objectRigid.empty() &&
      (setup.objectRigid.size() != setup.hierarchy.roots.size() || setup.restPose.matrices.empty()))
    throw std::invalid_argument("IvSetup: objectRigid does not match the hierarchy, or has no rest pose");
  return setup;
}

}  // namespace

IvSetup makeIvSetup(const scene::Scene& scene, const scene::Geometry& g, const IvSettings& settings,
                    std::optional<int> animation) {
  IvSetup setup{restPoseHierarchy(scene, g), settings, {}};
  if (animation)
    markMovingObjects(setup, scene, g, *animation);
  else
    setup.restPose = g.frameInputs(scene, scene::evaluatePose(scene, -1, 0.0f));  // what the objects turn from
  return setup;
}

void markMovingObjects(IvSetup& setup, const scene::Scene& scene, const scene::Geometry& g, int animation) {
  const Hierarchy& h = setup.hierarchy;
  setup.objectMoves = movingRoots(h, scene, g, animation);
  setup.objectRigid = rigidRoots(h, scene, g, animation);
  setup.restPose = g.frameInputs(scene, scene::evaluatePose(scene, -1, 0.0f));
}

bool IvSolver::rigid(size_t root) const {
  return rigidOnceOn(settings_) && !setup_.objectRigid.empty() && setup_.objectRigid[root];
}

IvSolver::IvSolver(const vk::Context& ctx, const scene::Geometry& g, IvSetup setup)
    : ctx_(ctx),
      setup_(validated(ctx, std::move(setup))),
      settings_(setup_.settings),
      surfelCount_(uint32_t(g.surfels.size())),
      nodeCount_(uint32_t(setup_.hierarchy.nodes.size())),
      refit_(ctx),
      links_(ctx),
      prune_(ctx, settings_, surfelCount_, b_, staticSet_, frameSet_),
      bounces_(ctx, setup_.hierarchy, settings_, b_, staticSet_, frameSet_, g, allocations_),
      receivers_(ctx, setup_.hierarchy, settings_, b_, allocations_),
      room_(ctx, settings_, b_, staticSet_, frameSet_, allocations_) {
  const Hierarchy& h = setup_.hierarchy;
  // Pairs of two static objects are linked and pruned once, but only when something else moves.
  auto moves = [&](size_t root) { return setup_.objectMoves.empty() || setup_.objectMoves[root]; };
  // A static leaf keeps a mask word pair per 32 bins; where those exceed what one binding can
  // address (many surfels at many bins), every object is relinked instead.
  const uint64_t maskWords = uint64_t(surfelCount_) * gpu::maskWordsFor(settings_.bins);
  // Objects that move rigidly with the same world matrix move together: their pairs are rigid too.
  std::vector<int> rigidGroup(h.roots.size(), -1);
  for (size_t r = 0; r < h.roots.size(); ++r)
    if (rigid(r)) rigidGroup[r] = int(g.instances[h.rootInstance[r]].matrix), anyRigid_ = true;
  const bool split = (mixesStaticAndMoving(setup_.objectMoves, h.roots.size()) || anyRigid_) &&
                     maskWords * sizeof(glm::uvec2) <= ctx.limits().maxStorageBufferRange;
  anyRigid_ = anyRigid_ && split;
  assignRootPairs(h, setup_.objectMoves, split, staticSet_, frameSet_, anyRigid_ ? rigidGroup : std::vector<int>{});
  // Per node: whether it moves (with its root; without the split every object counts as moving),
  // whether its object's surface is closed, whether it moves rigidly, and its root. Parents are
  // numbered before their children, roots first. Then per root its pose, identity until a frame
  // sets it (setObjectMatrices).
  if (nodeCount_ >= 1u << (32u - gpu::kNodeRootShift))
    throw SettingsError("the scene's iv hierarchy has " + std::to_string(nodeCount_) +
                        " nodes, more than the solver can address: use a lower --tessellate");
  // Closed, its normals out: from outside, its faces turned away lie behind faces turned toward.
  const std::vector<bool> closedInstances = scene::closedInstances(g);
  auto closed = [&](size_t r) { return closedInstances[h.rootInstance[r]] && h.rootEncloses[r]; };
  poseBase_ = nodeCount_;
  std::vector<uint32_t> nodeFlags(size_t(nodeCount_) + gpu::kPoseWords * h.roots.size(), 0u);
  for (size_t r = 0; r < h.roots.size(); ++r) {
    if (h.roots[r] != r) throw std::logic_error("IvSolver: the hierarchy's roots are not its first nodes");
    nodeFlags[h.roots[r]] = (!split || moves(r) ? gpu::kNodeMoves : 0u) | (closed(r) ? gpu::kNodeClosed : 0u) |
                            (anyRigid_ && rigidGroup[r] >= 0 ? gpu::kNodeRigid : 0u) |
                            h.roots[r] << gpu::kNodeRootShift;
    objectMatrix_.push_back(g.instances[h.rootInstance[r]].matrix);
  }
  setObjectMatrices({});
  for (size_t w = 0; w < poses_.size(); ++w) nodeFlags[poseBase_ + w] = std::bit_cast<uint32_t>(poses_[w]);
  for (uint32_t node = 0; node < nodeCount_; ++node)
    if (h.nodes[node].parent >= 0) nodeFlags[node] = nodeFlags[uint32_t(h.nodes[node].parent)];
  // A node whose every surfel has a twin facing the other way in its place (an open double-sided
  // surface and its back) is closed too: its faces turned away lie behind their twins.
  std::vector<uint8_t> twinned(nodeCount_, 1);
  const std::vector<bool> twinnedSurfel = scene::twinnedSurfels(g);
  for (uint32_t s = 0; s < surfelCount_; ++s) twinned[h.leafOfSurfel[s]] = twinnedSurfel[s];
  for (uint32_t node = nodeCount_; node-- > 0;) {
    if (h.nodes[node].parent >= 0) twinned[uint32_t(h.nodes[node].parent)] &= twinned[node];
    if (twinned[node]) nodeFlags[node] |= gpu::kNodeClosed;
  }
  if (g.directionalBases)
    for (uint32_t s = 0; s < surfelCount_; ++s)
      if (gpu::baseLeavesByAngle(g.surfelBrdf[s])) nodeFlags[h.leafOfSurfel[s]] |= gpu::kNodeBaseByAngle;
  if (anyRigid_) keepRestPose(g, nodeFlags);
  std::vector<uint32_t> leafMoves(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s) leafMoves[s] = nodeFlags[h.leafOfSurfel[s]] & gpu::kNodeMoves;
  uploadScene(g, nodeFlags, split, maskWords);
  // Where still objects keep static links, their surfels by a crease gather those themselves.
  if (split && !receivers_.everySurfel()) {
    std::vector<bool> still(surfelCount_);
    for (uint32_t s = 0; s < surfelCount_; ++s) still[s] = !(nodeFlags[h.leafOfSurfel[s]] & gpu::kNodeMoves);
    creases_ = gi::creaseSurfels(scene::surfelsOnHost(g, scene::animateOnHost(g, setup_.restPose)), still);
    bounces_.setCreases(creases_, allocations_);
  }
  prune_.allocateBins(b_, allocations_);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    vk::fillBuffer(cmd, b_.staticRanges, 0u);
    prune_.clearBins(cmd);
  });
  // Where the receivers are chosen, a rigid leaf's links to itself are pruned the first time it is
  // one; where every surfel is a receiver, the static pass prunes them all at once.
  const bool rigidWhenListed = anyRigid_ && !receivers_.everySurfel();
  prune_.pruneRigidWhenListed(rigidWhenListed);
  room_.keepStaticGrowing(rigidWhenListed);
  room_.guess(leafMoves, nodeCount_);
  readLeafLinkViews();
  noteUnresolvedRoughness(g, senderBinSpread(settings_.bins), "iv", "--bins " + std::to_string(settings_.bins));
}

void IvSolver::readLeafLinkViews() {
  const uint32_t views = room_.leafLinkTexelViews();
  prune_.readTexelViews(views);
  bounces_.readTexelViews(views);
}

void IvSolver::uploadScene(const scene::Geometry& g, const std::vector<uint32_t>& nodeFlags, bool split,
                           uint64_t maskWords) {
  const vk::Context& ctx = ctx_;
  vk::Allocations* tally = &allocations_;
  using vk::deviceArray;
  // An object whose rest pose is kept (anyRigid_) finds there what it buries of itself.
  std::vector<bool> restBurial(setup_.hierarchy.roots.size());
  for (size_t r = 0; r < restBurial.size(); ++r) restBurial[r] = anyRigid_ && rigid(r);
  b_.scene = SceneBuffers(ctx, g, setup_.hierarchy, settings_.bins, BinFrame::Normal, settings_.environment,
                          setup_.objectMoves, restBurial, allocations_);
  b_.nodeFlags = vk::makeBuffer(ctx, nodeFlags, vk::Memory::Device, tally);
  b_.args = vk::Buffer(ctx, 4 * sizeof(glm::uvec4), vk::Memory::Device, tally);
  for (LinkSet* set : {&staticSet_, &frameSet_}) set->allocateLists(ctx, nodeCount_, tally);
  b_.ranges = deviceArray<gpu::LeafRange>(ctx, surfelCount_, allocations_);
  b_.externalLight = deviceArray<glm::vec4>(ctx, gpu::kExternalTexels * surfelCount_, allocations_);
  b_.nodeEmission = deviceArray<glm::vec4>(ctx, nodeCount_, allocations_);
  b_.radiosityA = deviceArray<glm::vec4>(ctx, nodeCount_, allocations_);
  b_.radiosityB = deviceArray<glm::vec4>(ctx, nodeCount_, allocations_);
  b_.irradiance = deviceArray<glm::vec4>(ctx, surfelCount_, allocations_);
  // What a static leaf keeps between frames; with nothing static, empty ranges and one-word stand-ins.
  const size_t masks = split ? maskWords : 0, statics = split ? surfelCount_ : 0;
  b_.staticRanges = deviceArray<gpu::LeafRange>(ctx, surfelCount_, allocations_);
  b_.staticMasks = deviceArray<glm::uvec2>(ctx, masks, allocations_);
  b_.overrides = deviceArray<uint32_t>(ctx, masks, allocations_);
  b_.staticLeaves = deviceArray<gpu::StaticLeaf>(ctx, statics, allocations_);
  b_.staticEmitters = deviceArray<uint32_t>(ctx, statics * gpu::kStaticEmitters, allocations_);
}

void IvSolver::keepRestPose(const scene::Geometry& g, const std::vector<uint32_t>& nodeFlags) {
  constexpr VkDeviceSize kSurfel = sizeof(gpu::Surfel);
  for (uint32_t s = 0; s < surfelCount_; ++s) {
    if (!(nodeFlags[setup_.hierarchy.leafOfSurfel[s]] & gpu::kNodeRigid)) continue;
    if (!rigidRuns_.empty() && rigidRuns_.back().srcOffset + rigidRuns_.back().size == s * kSurfel)
      rigidRuns_.back().size += kSurfel;
    else
      rigidRuns_.push_back({s * kSurfel, s * kSurfel, kSurfel});
  }
  restSurfels_ = vk::makeBuffer(ctx_, scene::surfelsOnHost(g, scene::animateOnHost(g, setup_.restPose)),
                                vk::Memory::Device, &allocations_);
  staticSurfels_ = vk::deviceArray<gpu::Surfel>(ctx_, surfelCount_, allocations_);
  restNodes_ = vk::deviceArray<gpu::NodeState>(ctx_, nodeCount_, allocations_);
}

void IvSolver::recordRestNodes(VkCommandBuffer cmd, const vk::Buffer& surfels) {
  vk::copyRegion(cmd, surfels, staticSurfels_, {0, 0, VkDeviceSize(surfelCount_) * sizeof(gpu::Surfel)});
  for (const VkBufferCopy& run : rigidRuns_) vk::copyRegion(cmd, restSurfels_, staticSurfels_, run);
  refit_.recordNodes(cmd, b_.scene, staticSurfels_);
  refit_.recordRestBurial(cmd, b_.scene, staticSurfels_);
  vk::copyRegion(cmd, b_.scene.nodes, restNodes_, {0, 0, VkDeviceSize(nodeCount_) * sizeof(gpu::NodeState)});
}

void IvSolver::setLights(const std::vector<gpu::PunctualLight>& lights) {
  b_.scene.setLights(ctx_, lights, allocations_);
}

// Per object: where it moves rigidly, its motion back to rest; and the axes its surfaces follow,
// at rest and turned as it stands (every object whose world matrix turns: the bins of a leaf pruned
// every frame turn with it as those of a leaf pruned once at rest do). `matrices` empty: at rest.
void IvSolver::setObjectMatrices(const std::vector<glm::mat4>& matrices) {
  poses_.assign(gpu::kPoseWords * objectMatrix_.size(), 0.0f);
  const Hierarchy& h = setup_.hierarchy;
  for (size_t r = 0; r < objectMatrix_.size(); ++r) {
    glm::mat4 back(1.0f);  // now → rest: M_rest · M_now⁻¹, a rigid motion where the object is rigid
    if (!matrices.empty() && !setup_.restPose.matrices.empty()) {
      const glm::mat4 m = setup_.restPose.matrices.at(objectMatrix_[r]) * glm::inverse(matrices.at(objectMatrix_[r]));
      // Its rotation made orthonormal again (the rigidity test allows a little drift).
      const glm::vec3 x = glm::normalize(glm::vec3(m[0])),
                      y = glm::normalize(glm::vec3(m[1]) - glm::dot(glm::vec3(m[1]), x) * x);
      back = glm::mat4(glm::mat3(x, y, glm::cross(x, y)));
      back[3] = m[3];
    }
    float* words = poses_.data() + gpu::kPoseWords * r;
    const glm::mat4 pose = anyRigid_ && rigid(r) ? back : glm::mat4(1.0f);
    for (uint32_t row = 0; row < 3; ++row)
      for (uint32_t col = 0; col < 4; ++col) words[4 * row + col] = pose[col][row];
    const glm::mat3 rest = glm::transpose(h.rootAxes.at(r)), now = glm::transpose(glm::mat3(back)) * rest;
    for (uint32_t k = 0; k < 3; ++k) {  // the rows x and z: the columns of the transposes
      words[gpu::kRestAxesWord + k] = rest[0][k], words[gpu::kRestAxesWord + 3 + k] = rest[2][k];
      words[gpu::kAxesWord + k] = now[0][k], words[gpu::kAxesWord + 3 + k] = now[2][k];
    }
  }
}

void IvSolver::record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool geometryMoved) {
  const Hierarchy& h = setup_.hierarchy;
  linkStatic_ = false;
  solvePending_ = solvesFrame(geometryMoved);
  reused_ = !solvePending_;
  if (reused_) return;
  // The objects' poses (vkCmdUpdateBuffer takes at most 65,536 bytes at once).
  for (size_t at = 0; at < poses_.size(); at += 16384) {
    const size_t words = std::min<size_t>(16384, poses_.size() - at);
    vk::updateBuffer(cmd, b_.nodeFlags, (poseBase_ + at) * 4, words * 4, poses_.data() + at);
  }
  linkStatic_ = splitsStatic() && !staticLinked_;
  timedPass(cmd, timer, "refit", [&] {
    if (linkStatic_ && anyRigid_) recordRestNodes(cmd, surfels);
    refit_.record(cmd, b_.scene, surfels);
    bounces_.recordEmission(cmd);
  });
  staticPasses_ += linkStatic_ ? 1 : 0;
  timedPass(cmd, timer, "links", [&] {
    const LinkWork work{b_.args, b_.worklistA, b_.worklistB, b_.nodeEmission, b_.scene.nodeBuried, b_.pool()};
    const LinkWork staticWork{b_.args,
                              b_.worklistA,
                              b_.worklistB,
                              b_.nodeEmission,
                              b_.scene.nodeStillBuried,
                              vk::Bindings::pool({{"nodes", staticNodes()}}).plus(b_.pool())};
    const LinkCriteria criteria{.epsilon = settings_.epsilon,
                                .largeSender = settings_.kappa * meanBinSolidAngle(settings_.bins),
                                .largeReceiver = 3.4e38f,
                                .bothSides = false,
                                .emitterReceiver = 3.4e38f,
                                .receiverStaysWhole = true,
                                .skipBuriedSenders = !settings_.linkBuriedSenders};
    if (linkStatic_) links_.record(cmd, staticSet_, staticWork, h, criteria, room_.worklistCapacity());
    links_.record(cmd, frameSet_, work, h, criteria, room_.worklistCapacity());
  });
  // Until a frame has stood in the link room, the links go in a submission of their own: a frame
  // whose links overflow is redone before it prunes (recordMorePasses() goes on once they fit).
  if (roomProven_) recordSolve(cmd, timer);
}

// The frame's solve once its links fit: the prune (the static set's once), the receivers and the
// first bounces.
void IvSolver::recordSolve(VkCommandBuffer cmd, vk::PassTimer& timer) {
  timedPass(cmd, timer, "prune", [&] {
    if (linkStatic_) prune_.recordStatic(cmd, staticNodes());
    if (receivers_.everySurfel()) prune_.recordFrame(cmd);
  });
  if (!receivers_.everySurfel()) recordReceivers(cmd, timer);
  linked_ = staticLinked_ = true;
  solvePending_ = false;
  recordFirstBounces(cmd, timer);
}

void IvSolver::recordFirstBounces(VkCommandBuffer cmd, vk::PassTimer& timer) {
  timedPass(cmd, timer, "bounces", [&] {
    bounces_.recordStart(cmd, !receivers_.everySurfel());
    gathersRecorded_ = std::min(kFirstBounceSteps, bounces_.maxGathers());
    bounces_.recordSteps(cmd, 0, gathersRecorded_);
  });
}

void IvSolver::recordReceivers(VkCommandBuffer cmd, vk::PassTimer& timer) {
  const Prune::Batching batching = prune_.batching();
  timedPass(cmd, timer, "receivers", [&] { receivers_.recordStart(cmd); });
  // Each round's new receivers are pruned, rigid ones still unpruned first against the static set.
  const auto pruneListed = [&] {
    timedPass(cmd, timer, "prune", [&] {
      if (prune_.rigidWhenListed()) prune_.recordStaticReceivers(cmd, staticNodes());
      prune_.recordReceivers(cmd);
    });
  };
  for (uint32_t round = 0; round < receivers_.rounds(); ++round) {
    timedPass(cmd, timer, "receivers", [&] { receivers_.recordSelect(cmd, round, batching); });
    pruneListed();
    timedPass(cmd, timer, "receivers", [&] {
      bounces_.recordEstimate(cmd);
      receivers_.recordRefine(cmd, round, batching);
    });
  }
  // Surfels that no receiver's support holds get receivers too (fills), which also gather the
  // estimate: the surfels sharing one take its light turned to their normals.
  timedPass(cmd, timer, "interpolation", [&] { receivers_.recordWeights(cmd, batching); });
  pruneListed();
  timedPass(cmd, timer, "receivers", [&] { bounces_.recordEstimate(cmd); });
}

bool IvSolver::overflowed() const {
  for (const LinkSet* set : {&staticSet_, &frameSet_})
    if (!set->empty() && set->readCounters()[gpu::kCounterOverflow] != 0) return true;
  return false;
}

bool IvSolver::wantsMorePasses() const {
  if (reused_ || overflowed()) return false;  // nothing ran, or the frame is redone
  if (solvePending_) return true;
  const gpu::BounceState s = bounces_.state();
  return s.done == 0 && s.gathers == gathersRecorded_ && gathersRecorded_ < bounces_.maxGathers();
}

void IvSolver::recordMorePasses(VkCommandBuffer cmd, vk::PassTimer& timer) {
  if (solvePending_) return recordSolve(cmd, timer);
  timedPass(cmd, timer, "bounces", [&] {
    const uint32_t steps = std::min(kMoreBounceSteps, bounces_.maxGathers() - gathersRecorded_);
    bounces_.recordSteps(cmd, gathersRecorded_, steps);
    gathersRecorded_ += steps;
  });
}

void IvSolver::recordReflections(VkCommandBuffer cmd, vk::PassTimer& timer, glm::vec4 eye, const vk::Buffer& shown,
                                 const vk::Buffer& lobes) {
  timedPass(cmd, timer, "reflections", [&] { bounces_.recordReflections(cmd, eye, shown, lobes); });
}

std::vector<std::pair<std::string, double>> IvSolver::frameFigures() const {
  const gpu::BounceState s = bounces_.state();
  return {{"bounces", double(s.gathers) - double(bounces_.directGathers())},
          {"bounceRemaining", settings_.bounces ? 0.0 : double(s.remaining)},
          {"diverged", double(s.diverged)},
          {"receivers", double(receivers_.counts().receivers)}};
}

bool IvSolver::frameMustBeRedone() {
  if (reused_) return false;  // nothing ran
  const LinkRoom::Overflow overflow = room_.grow(linkStatic_);
  if (!overflow.any) return false;
  roomProven_ = false;
  readLeafLinkViews();
  if (overflow.loopBudget) prune_.onLoopBudgetSpent();
  if (overflow.staticSet) staticLinked_ = false;
  linked_ = false;
  ++framesRedone_;
  return true;
}

void IvSolver::frameStands() {
  if (reused_) return;
  room_.releaseUnused(staticLinked_);
  roomProven_ = true;
  if (const uint64_t host = room_.hostBytes(); host > 0 && !saidHostMemory_) {
    saidHostMemory_ = true;
    std::fprintf(stderr,
                 "ivgi: iv: the links do not fit in %s: %.1f MiB of them are in host memory, which the device reads "
                 "across its bus (slower); a larger --eps or fewer --bins keep them on the device\n",
                 settings_.memoryBudget
                     ? ("--max-memory of " + std::to_string(settings_.memoryBudget >> 20) + " MiB").c_str()
                     : "the device's memory",
                 double(host) / (1 << 20));
  }
  if (const gpu::BounceState s = bounces_.state(); s.diverged)
    std::fprintf(stderr,
                 "ivgi: iv: the bounces diverge (bounce %u added over %g times the least light a bounce had added); "
                 "the frame shows it, stopped there; --receiver-tol 0 solves every surfel without interpolating\n",
                 s.gathers - 1, double(gpu::kDivergingGrowth));
}

IvStats IvSolver::stats() const {
  IvStats s;
  s.nodes = nodeCount_;
  s.levels = setup_.hierarchy.levels();
  s.sharedBins = prune_.sharedBins();
  s.pruneBatches = prune_.batches();
  s.pruneGroupSize = prune_.groupSize();
  s.framesRedone = framesRedone_, s.staticPasses = staticPasses_;
  for (const LinkSet* set : {&staticSet_, &frameSet_}) {
    if (set->empty()) continue;
    const std::vector<uint32_t> c = set->readCounters();
    s.links += c[gpu::kCounterLinks];
    s.leafLinks += c[gpu::kCounterLeafLinks];
    const auto count64 = [&c](uint32_t at) { return uint64_t(c[at + 1]) << 32 | c[at]; };
    if (set == &staticSet_)
      s.staticLinks = c[gpu::kCounterLinks], s.staticLeafLinks = c[gpu::kCounterLeafLinks],
      s.staticSendersWalked = count64(gpu::kCounterSendersWalked);
    else
      s.sendersWalked = count64(gpu::kCounterSendersWalked), s.mergedSendersWalked = count64(gpu::kCounterMergedWalked),
      s.rigidSendersWalked = count64(gpu::kCounterRigidWalked), s.rigidLeaves = c[gpu::kCounterRigidLeaves];
  }
  s.bytes = allocatedBytes();
  s.hostBytes = room_.hostBytes();
  const gpu::BounceState bounces = bounces_.state();
  s.bounces = bounces.gathers - 1;
  s.bounceRemaining = settings_.bounces ? 0.0f : bounces.remaining;
  const Receivers::Counts receivers = receivers_.counts();
  s.receivers = receivers.receivers, s.receiverFills = receivers.fills;
  return s;
}

std::vector<std::vector<IvSolver::LeafLink>> IvSolver::leafLinks() const {
  auto ranges = b_.ranges.read<gpu::LeafRange>(surfelCount_);
  auto all = b_.leafLinks.read<LeafLink>(frameSet_.leafLinksHeld());
  std::vector<std::vector<LeafLink>> out(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s)
    for (uint32_t k = ranges[s].first; k < ranges[s].first + ranges[s].count && k < all.size(); ++k)
      out[s].push_back(all[k]);
  if (!splitsStatic()) return out;
  const uint32_t maskWords = gpu::maskWordsFor(settings_.bins), held = staticSet_.leafLinksHeld();
  auto staticRanges = b_.staticRanges.read<gpu::LeafRange>(surfelCount_);
  auto staticLinks = b_.staticLinks.read<LeafLink>(held);
  auto staticBins = b_.staticBins.read<uint32_t>(held);
  auto overrides = b_.overrides.read<uint32_t>(size_t(surfelCount_) * maskWords);
  for (uint32_t s = 0; s < surfelCount_; ++s)
    for (uint32_t k = staticRanges[s].first;
         k < staticRanges[s].first + staticRanges[s].count && k < staticLinks.size(); ++k) {
      const uint32_t bin = gpu::staticBinOf(staticBins[k]);
      if (!(overrides[size_t(s) * maskWords + bin / 32] & (1u << (bin & 31)))) out[s].push_back(staticLinks[k]);
    }
  return out;
}

std::vector<uint32_t> IvSolver::receiverSurfels() const {
  auto list = b_.receivers.read<uint32_t>(receivers_.counts().receivers);
  std::sort(list.begin(), list.end());
  return list;
}

std::vector<uint32_t> IvSolver::fillSurfels() const {
  const Receivers::Counts counts = receivers_.counts();
  auto list = b_.receivers.read<uint32_t>(counts.receivers);  // the fills are listed last
  list.erase(list.begin(), list.end() - counts.fills);
  std::sort(list.begin(), list.end());
  return list;
}

std::vector<std::vector<IvSolver::Tap>> IvSolver::interpolationTaps() const {
  const auto counts = b_.tapCounts.read<uint32_t>(surfelCount_);
  const auto taps = b_.taps.read<gpu::InterpolationTap>(size_t(surfelCount_) * gpu::kInterpolationTaps);
  std::vector<std::vector<Tap>> out(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s)
    for (uint32_t t = 0; t < std::min(counts[s], gpu::kInterpolationTaps); ++t) {
      const gpu::InterpolationTap& tap = taps[size_t(s) * gpu::kInterpolationTaps + t];
      out[s].push_back({tap.receiver, std::bit_cast<float>(tap.weightBits)});
    }
  return out;
}

std::vector<gpu::NodeState> IvSolver::nodeStates() const { return b_.scene.nodes.read<gpu::NodeState>(nodeCount_); }

std::vector<glm::vec4> IvSolver::leafRadiosity() const {
  auto nodes = bounces_.solution(bounces_.state().gathers).read<glm::vec4>(nodeCount_);
  std::vector<glm::vec4> out(surfelCount_);
  for (uint32_t s = 0; s < surfelCount_; ++s) out[s] = nodes[setup_.hierarchy.leafOfSurfel[s]];
  return out;
}

}  // namespace ivgi::gi

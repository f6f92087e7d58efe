#include "engine/gi/iv/bounces.h"

#include "engine/gi/bins.h"
#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

constexpr uint32_t kGroupSize = 64;  // of interpolate.comp, pull_up.comp and bounce_tail.comp

glm::uvec4 argsOf(vk::Groups g) { return {g.x, g.y, g.z, 0u}; }

// The bounce's dispatch sizes (bounce_check.comp): gather, interpolation, pull-up; then the tail's.
constexpr uint32_t kPullUpArgs = 2, kBounceDispatches = 3;

}  // namespace

Bounces::Bounces(const vk::Context& ctx, const Hierarchy& h, const IvSettings& settings, const IvBuffers& b,
                 const LinkSet& staticSet, const LinkSet& frameSet, const scene::Geometry& g,
                 vk::Allocations& allocations)
    : ctx_(ctx),
      settings_(settings),
      b_(b),
      staticSet_(staticSet),
      frameSet_(frameSet),
      surfelCount_(uint32_t(h.leafOfSurfel.size())),
      nodeCount_(uint32_t(h.nodes.size())),
      glossy_(g.directionalLobes),
      metal_(g.directionalLobes && g.lobeDominatedMaterials),
      bases_(g.directionalBases),
      emit_(shaderProgram(ctx, "emit", vk::Specialization{.constants = {{"kSenderLobes", glossy_ ? 1u : 0u}}})),
      interpolate_(shaderProgram(ctx, "interpolate")),
      pullUp_(shaderProgram(ctx, "pull_up")),
      check_(shaderProgram(ctx, "bounce_check")),
      tail_(shaderProgram(ctx, "bounce_tail")) {
  makeLinkReaders();
  // The dispatch sizes of a whole bounce: the gather over the receivers (set each frame from how
  // many there are), the interpolation at every surfel, the pull-up over every node; and the
  // tail's, none until the check says otherwise.
  const vk::Groups interpolate = interpolate_.groupsFor(h.leafOfSurfel.size(), kGroupSize);
  interpolateGroups_ = interpolate.x * interpolate.y;
  const std::vector<glm::uvec4> full = {glm::uvec4(0u, 1u, 1u, 0u), argsOf(interpolate),
                                        argsOf(pullUp_.groupsFor(h.nodes.size(), kGroupSize)),
                                        glm::uvec4(0u, 1u, 1u, 0u)};
  fullArgs_ = vk::makeBuffer(ctx, full, vk::Memory::Device, &allocations);
  args_ = vk::Buffer(ctx, full.size() * sizeof(glm::uvec4), vk::Memory::Device, &allocations);
  sums_ = vk::Buffer(ctx, interpolateGroups_ * sizeof(gpu::BounceSum), vk::Memory::Device, &allocations);
  state_ = vk::Buffer(ctx, sizeof(gpu::BounceState), vk::Memory::Host, &allocations);
  change_ =
      vk::Buffer(ctx, std::max<size_t>(h.leafOfSurfel.size(), 1) * sizeof(glm::vec4), vk::Memory::Device, &allocations);
  receiverLobe_ = vk::Buffer(ctx, glossy_ ? change_.size() : 16, vk::Memory::Device, &allocations);
  receiverExcess_ = vk::Buffer(ctx, glossy_ ? change_.size() : 16, vk::Memory::Device, &allocations);
  // A scene with a metal's: what the first bounce's light sends along the metals' lobes.
  arrivalExcess_ = vk::Buffer(ctx, metal_ ? change_.size() : 16, vk::Memory::Device, &allocations);
  arrivalTaps_ = vk::Buffer(ctx, metal_ ? change_.size() / 4 : 16, vk::Memory::Device, &allocations);
  receiverArrival_ =
      vk::Buffer(ctx, metal_ ? change_.size() * 2 * gpu::kArrivalClasses : 16, vk::Memory::Device, &allocations);
  senderArrival_ =
      vk::Buffer(ctx, metal_ ? std::max<uint64_t>(nodeCount_, 1) * 2 * gpu::kArrivalLobes * sizeof(glm::vec4) : 16,
                 vk::Memory::Device, &allocations);
  stillGathered_ = vk::Buffer(ctx, change_.size(), vk::Memory::Device, &allocations);
  setCreases({}, allocations);
  if (!metal_) return;
  // Inner nodes and the leaves whose lobe does not dominate send all evenly (α 0); the others write theirs.
  ctx.submitAndWait([&](VkCommandBuffer cmd) { vk::fillBuffer(cmd, senderArrival_, 0u); });
  markArrival_.emplace(ctx, "mark_arrival", shaderCode("mark_arrival"));
  sendArrival_.emplace(ctx, "send_arrival", shaderCode("send_arrival"));
}

void Bounces::setCreases(const std::vector<uint32_t>& surfels, vk::Allocations& allocations) {
  creaseCount_ = uint32_t(surfels.size());
  creaseSurfels_ =
      vk::makeBuffer(ctx_, surfels.empty() ? std::vector<uint32_t>{0u} : surfels, vk::Memory::Device, &allocations);
  std::vector<uint32_t> flags(std::max<size_t>(surfelCount_, 1), 0u);
  for (uint32_t s : surfels) flags[s] = 1u;
  surfelCrease_ = vk::makeBuffer(ctx_, flags, vk::Memory::Device, &allocations);
  if (creaseCount_ > 0) makeLinkReaders();  // the gather then sums the still senders' light too
}

void Bounces::pullUp(VkCommandBuffer cmd, const vk::Buffer& radiosity, bool indirect) const {
  const vk::Bindings bindings = b_.pool().with({{"radiosity", radiosity}});
  const gpu::CountPush nodes{.count = nodeCount_};
  if (indirect)
    pullUp_.dispatchIndirect(cmd, args_, kPullUpArgs * sizeof(glm::uvec4), bindings, nodes);
  else
    pullUp_.dispatchItems(cmd, nodes.count, bindings, nodes);
}

void Bounces::recordEmission(VkCommandBuffer cmd) const {
  emit_.dispatchItems(cmd, surfelCount_, b_.pool().with({{"radiosity", b_.radiosityA}}),
                      gpu::CountPush{.count = surfelCount_});
  pullUp(cmd, b_.nodeEmission, false);
  if (b_.scene.emittersByMaps())
    pullUp(cmd, b_.radiosityA, false);
  else  // the bounces start from the emission alone
    vk::copyBuffer(cmd, b_.nodeEmission, b_.radiosityA);
}

void Bounces::recordStart(VkCommandBuffer cmd, bool estimated) const {
  vk::fillBuffer(cmd, state_, 0u);
  // The irradiance before the first gather: the depth maps' direct light where they give it, else
  // zeros (the first gather's change is then all of it).
  vk::copyBuffer(cmd, b_.scene.surfelDirect(), b_.irradiance);
  vk::copyRegion(cmd, b_.receiverArgs, fullArgs_, {gpu::kArgsReceivers * sizeof(glm::uvec4), 0, sizeof(glm::uvec4)});
  vk::copyBuffer(cmd, fullArgs_, args_);
  if (metal_)
    recordArrival(cmd, estimated);
  else if (!estimated)
    recordLobeExcess(cmd, gpu::kArgsReceivers, 0u);
}

vk::Bindings Bounces::lobeBindings() const {
  return b_.pool().plus(vk::Bindings::pool({{"radiosityA", b_.radiosityA},
                                            {"arrivalLobes", senderArrival_},
                                            {"receiverArrival", receiverArrival_},
                                            {"arrivalExcess", arrivalExcess_},
                                            {"arrivalTaps", arrivalTaps_}}));
}

void Bounces::recordLobeExcess(VkCommandBuffer cmd, uint32_t args, uint32_t newOnly) const {
  if (!lobeExcess_) return;
  lobeExcess_->dispatchIndirect(cmd, b_.receiverArgs, args * sizeof(glm::uvec4),
                                lobeBindings().with({{"lobeExcess", receiverExcess_}}), gatherPush(newOnly));
}

void Bounces::recordArrival(VkCommandBuffer cmd, bool estimated) const {
  const vk::Bindings bindings = lobeBindings();
  const size_t receiversArgs = gpu::kArgsReceivers * sizeof(glm::uvec4);
  vk::fillBuffer(cmd, arrivalTaps_, 0u);
  markArrival_->dispatchItems(cmd, surfelCount_, bindings, gatherPush(0u));
  arrivalLobes_->dispatchIndirect(cmd, b_.receiverArgs, receiversArgs, bindings, gatherPush(0u));
  sendArrival_->dispatchItems(cmd, surfelCount_, bindings, gatherPush(0u));
  // Both lobes' excess at once, the direct light's and the first bounce's; the first bounce's alone
  // where the estimates left the direct light's.
  lobeExcessBoth_->dispatchIndirect(cmd, b_.receiverArgs, receiversArgs,
                                    bindings.with({{"lobeExcess", receiverExcess_}}), gatherPush(0u, false, estimated));
}

vk::Bindings Bounces::gatherBindings(const vk::Buffer& in) const {
  return b_.pool().with({{"radiosityIn", in},
                         {"frameCounters", frameSet_.counters},
                         {"staticCounters", staticSet_.counters},
                         {"lobeExcess", receiverExcess_},
                         {"arrivalExcess", arrivalExcess_},
                         {"stillGathered", stillGathered_}});
}

gpu::GatherPush Bounces::gatherPush(uint32_t newOnly, bool arrival, bool directKnown) const {
  return {.maskWords = gpu::maskWordsFor(settings_.bins),
          .newOnly = newOnly,
          .emittersByMaps = b_.scene.emittersByMaps() ? 1u : 0u,
          .largestBin = 4.0f / float(settings_.bins * settings_.bins),
          .leastSpread = senderBinSpread(settings_.bins),
          .poseBase = b_.scene.nodeCount,
          .arrival = arrival ? 1u : 0u,
          .surfelCount = surfelCount_,
          .directKnown = directKnown ? 1u : 0u};
}

void Bounces::recordEstimate(VkCommandBuffer cmd) const {
  recordLobeExcess(cmd, gpu::kArgsNewReceivers, 1u);
  gather_->dispatchIndirect(cmd, b_.receiverArgs, gpu::kArgsNewReceivers * sizeof(glm::uvec4),
                            gatherBindings(b_.radiosityA), gatherPush(1u));
}

void Bounces::recordSteps(VkCommandBuffer cmd, uint32_t first, uint32_t steps) const {
  const gpu::BounceCheckPush check{.groups = interpolateGroups_,
                                   .dispatches = kBounceDispatches,
                                   .maxGathers = maxGathers(),
                                   .tolerance = settings_.bounces ? -1.0f : settings_.bounceTolerance};
  const gpu::InterpolatePush surfels{.surfelCount = surfelCount_};
  for (uint32_t k = first; k < first + steps; ++k) {
    const vk::Buffer& in = solution(k);
    const vk::Buffer& out = solution(k + 1);
    // What the metals' lobes send of the light the first gather brings arrives from the second on.
    gather_->dispatchIndirect(cmd, args_, 0, gatherBindings(in), gatherPush(0u, metal_ && k >= 1));
    if (creaseCount_ > 0)
      gatherCreases_->dispatchItems(cmd, creaseCount_,
                                    b_.pool().with({{"radiosityIn", in},
                                                    {"frameCounters", frameSet_.counters},
                                                    {"staticCounters", staticSet_.counters},
                                                    {"stillGathered", stillGathered_},
                                                    {"creaseSurfels", creaseSurfels_},
                                                    {"bounceStates", state_}}),
                                    gpu::CountPush{.count = creaseCount_});
    interpolate_.dispatchIndirect(cmd, args_, sizeof(glm::uvec4),
                                  b_.pool().with({{"radiosityIn", in},
                                                  {"radiosityOut", out},
                                                  {"frameCounters", frameSet_.counters},
                                                  {"staticCounters", staticSet_.counters},
                                                  {"bounceSums", sums_},
                                                  {"irradianceChange", change_},
                                                  {"stillGathered", stillGathered_},
                                                  {"surfelCrease", surfelCrease_}}),
                                  surfels);
    pullUp(cmd, out, true);
    check_.dispatch(cmd, {},
                    {{"bounceSums", sums_}, {"bounceStates", state_}, {"fullArgs", fullArgs_}, {"bounceArgs", args_}},
                    check);
    tail_.dispatchIndirect(cmd, args_, kBounceDispatches * sizeof(glm::uvec4),
                           b_.pool().with({{"bounceStates", state_}, {"irradianceChange", change_}}), surfels);
  }
}

void Bounces::recordReflections(VkCommandBuffer cmd, glm::vec4 eye, const vk::Buffer& shown,
                                const vk::Buffer& lobes) const {
  const gpu::LobePush push{.eye = eye,
                           .surfelCount = surfelCount_,
                           .maskWords = gpu::maskWordsFor(settings_.bins),
                           .leastSpread = senderBinSpread(settings_.bins)};
  const vk::Bindings bindings = b_.pool().plus(vk::Bindings::pool({{"radiosityA", b_.radiosityA},
                                                                   {"radiosityB", b_.radiosityB},
                                                                   {"bounceStates", state_},
                                                                   {"receiverLobe", receiverLobe_},
                                                                   {"shownSurfels", shown}}));
  markTaps_->dispatchItems(cmd, surfelCount_, bindings, push);
  reflectReceivers_->dispatchIndirect(cmd, b_.receiverArgs, gpu::kArgsReceivers * sizeof(glm::uvec4), bindings, push);
  reflectSurfels_->dispatchItems(cmd, surfelCount_, bindings.with({{"surfelLobe", lobes}}), push);
}

void Bounces::makeLinkReaders() {
  const vk::Specialization views{.constants = {{"texelViews", texelViews_}, {"kSenderLobes", glossy_ ? 1u : 0u}}};
  gather_.emplace(ctx_, "gather", shaderCode("gather"),
                  vk::Specialization{.constants = {{"texelViews", texelViews_},
                                                   {"kSenderLobes", glossy_ ? 1u : 0u},
                                                   {"kCreases", creaseCount_ > 0 ? 1u : 0u}}});
  gatherCreases_.emplace(ctx_, "gather_creases", shaderCode("gather_creases"),
                         vk::Specialization{.constants = {{"texelViews", texelViews_}}});
  markTaps_.emplace(ctx_, "mark_taps", shaderCode("mark_taps"));
  reflectReceivers_.emplace(ctx_, "reflect_receivers", shaderCode("reflect_receivers"),
                            vk::Specialization{.constants = {{"texelViews", texelViews_},
                                                             {"kSenderLobes", glossy_ ? 1u : 0u},
                                                             {"kBasesByAngle", bases_ ? 1u : 0u}}});
  reflectSurfels_.emplace(ctx_, "reflect_surfels", shaderCode("reflect_surfels"));
  if (!glossy_) return;
  lobeExcess_.emplace(ctx_, "lobe_excess", shaderCode("lobe_excess"), views);
  if (!metal_) return;
  const vk::Specialization both{.constants = {{"texelViews", texelViews_}, {"kSenderLobes", 1u}, {"kArrival", 1u}}};
  lobeExcessBoth_.emplace(ctx_, "lobe_excess", shaderCode("lobe_excess"), both);
  arrivalLobes_.emplace(ctx_, "arrival_lobes", shaderCode("arrival_lobes"),
                        vk::Specialization{.constants = {{"texelViews", texelViews_}}});
}

void Bounces::readTexelViews(uint32_t views) {
  if (views == texelViews_) return;
  texelViews_ = views;
  makeLinkReaders();
}

}  // namespace ivgi::gi

#include "engine/gi/iv/bounces.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

constexpr uint32_t kGroupSize = 64;  // of interpolate.comp, pull_up.comp and bounce_tail.comp

glm::uvec4 argsOf(vk::Groups g) { return {g.x, g.y, g.z, 0u}; }

// The bounce's dispatch sizes (bounce_check.comp): gather, interpolation, pull-up; then the tail's.
constexpr uint32_t kPullUpArgs = 2, kBounceDispatches = 3;

}  // namespace

Bounces::Bounces(const vk::Context& ctx, const Hierarchy& h, vk::Allocations& allocations)
    : ctx_(ctx),
      emit_(shaderProgram(ctx, "emit")),
      interpolate_(shaderProgram(ctx, "interpolate")),
      pullUp_(shaderProgram(ctx, "pull_up")),
      check_(shaderProgram(ctx, "bounce_check")),
      tail_(shaderProgram(ctx, "bounce_tail")) {
  makeGather();
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
}

uint32_t Bounces::maxGathers(const IvSettings& settings) {
  return (settings.bounces ? *settings.bounces : kMaxBounces) + 1;
}

void Bounces::pullUp(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const vk::Buffer& radiosity,
                     bool indirect) const {
  const vk::Bindings bindings = b.pool().with({{"radiosity", radiosity}});
  const gpu::CountPush nodes{uint32_t(h.nodes.size())};
  if (indirect)
    pullUp_.dispatchIndirect(cmd, args_, kPullUpArgs * sizeof(glm::uvec4), bindings, nodes);
  else
    pullUp_.dispatchItems(cmd, nodes.count, bindings, nodes);
  vk::barrier(cmd);
}

void Bounces::recordEmission(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  emit_.dispatchItems(cmd, surfels, b.pool().with({{"radiosity", b.nodeEmission}}), gpu::CountPush{surfels});
  vk::barrier(cmd);
  pullUp(cmd, b, h, b.nodeEmission, false);
  vk::copyBuffer(cmd, b.nodeEmission, b.radiosityA);
  vk::barrier(cmd);
}

void Bounces::recordStart(VkCommandBuffer cmd, const IvBuffers& b) const {
  vkCmdFillBuffer(cmd, state_.handle(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, b.irradiance.handle(), 0, VK_WHOLE_SIZE, 0u);  // the first gather's change is all of it
  const VkBufferCopy gather{gpu::kArgsReceivers * sizeof(glm::uvec4), 0, sizeof(glm::uvec4)};
  vkCmdCopyBuffer(cmd, b.receiverArgs.handle(), fullArgs_.handle(), 1, &gather);
  vk::barrier(cmd);
  vk::copyBuffer(cmd, fullArgs_, args_);
  vk::barrier(cmd);
}

void Bounces::recordEstimate(VkCommandBuffer cmd, const IvBuffers& b, const LinkSet& staticSet, const LinkSet& frameSet,
                             const IvSettings& settings) const {
  gather_->dispatchIndirect(cmd, b.receiverArgs, gpu::kArgsNewReceivers * sizeof(glm::uvec4),
                            b.pool().with({{"radiosityIn", b.nodeEmission},
                                           {"frameCounters", frameSet.counters},
                                           {"staticCounters", staticSet.counters}}),
                            gpu::GatherPush{gpu::maskWordsFor(settings.bins), 1u, 0u});
  vk::barrier(cmd);
}

void Bounces::recordSteps(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const LinkSet& staticSet,
                          const LinkSet& frameSet, const IvSettings& settings, uint32_t first, uint32_t steps) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  const gpu::BounceCheckPush check{interpolateGroups_, kBounceDispatches, maxGathers(settings),
                                   settings.bounces ? -1.0f : settings.bounceTolerance};
  for (uint32_t k = first; k < first + steps; ++k) {
    const vk::Buffer& in = k % 2 ? b.radiosityB : b.radiosityA;
    const vk::Buffer& out = k % 2 ? b.radiosityA : b.radiosityB;
    gather_->dispatchIndirect(
        cmd, args_, 0,
        b.pool().with(
            {{"radiosityIn", in}, {"frameCounters", frameSet.counters}, {"staticCounters", staticSet.counters}}),
        gpu::GatherPush{gpu::maskWordsFor(settings.bins), 0u, 0u});
    vk::barrier(cmd);
    interpolate_.dispatchIndirect(cmd, args_, sizeof(glm::uvec4),
                                  b.pool().with({{"radiosityIn", in},
                                                 {"radiosityOut", out},
                                                 {"frameCounters", frameSet.counters},
                                                 {"staticCounters", staticSet.counters},
                                                 {"bounceSums", sums_},
                                                 {"irradianceChange", change_}}),
                                  gpu::InterpolatePush{surfels});
    vk::barrier(cmd);
    pullUp(cmd, b, h, out, true);
    check_.dispatch(cmd, {},
                    {{"bounceSums", sums_}, {"bounceStates", state_}, {"fullArgs", fullArgs_}, {"bounceArgs", args_}},
                    check);
    vk::barrier(cmd);
    tail_.dispatchIndirect(cmd, args_, kBounceDispatches * sizeof(glm::uvec4),
                           b.pool().with({{"bounceStates", state_}, {"irradianceChange", change_}}),
                           gpu::InterpolatePush{surfels});
    vk::barrier(cmd);
  }
}

void Bounces::makeGather() {
  gather_.emplace(ctx_, "gather", shaderCode("gather"), vk::Specialization{.constants = {{"texelViews", texelViews_}}});
}

void Bounces::readTexelViews(uint32_t views) {
  if (views == texelViews_) return;
  texelViews_ = views;
  makeGather();
}

}  // namespace ivgi::gi

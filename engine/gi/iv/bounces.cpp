#include "engine/gi/iv/bounces.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

constexpr uint32_t kGroupSize = 64;  // of gather.comp and pull_up.comp

glm::uvec4 argsOf(vk::Groups g) { return {g.x, g.y, g.z, 0u}; }

}  // namespace

Bounces::Bounces(const vk::Context& ctx, const Hierarchy& h, vk::Allocations& allocations)
    : emit_(shaderProgram(ctx, "emit")),
      gather_(shaderProgram(ctx, "gather")),
      pullUp_(shaderProgram(ctx, "pull_up")),
      check_(shaderProgram(ctx, "bounce_check")) {
  // The dispatch sizes of a whole bounce: the gather over the surfels, then one pull-up a level.
  const vk::Groups gather = gather_.groupsFor(h.leafOfSurfel.size(), kGroupSize);
  gatherGroups_ = gather.x * gather.y;
  std::vector<glm::uvec4> full = {argsOf(gather)};
  for (uint32_t l = 0; l < h.levels(); ++l)
    full.push_back(argsOf(pullUp_.groupsFor(h.levelStart[l + 1] - h.levelStart[l], kGroupSize)));
  fullArgs_ = vk::makeBuffer(ctx, full, vk::Memory::Device, &allocations);
  args_ = vk::Buffer(ctx, full.size() * sizeof(glm::uvec4), vk::Memory::Device, &allocations);
  sums_ = vk::Buffer(ctx, gatherGroups_ * sizeof(gpu::BounceSum), vk::Memory::Device, &allocations);
  state_ = vk::Buffer(ctx, sizeof(gpu::BounceState), vk::Memory::Host, &allocations);
}

uint32_t Bounces::maxGathers(const IvSettings& settings) {
  return (settings.bounces ? *settings.bounces : kMaxBounces) + 1;
}

void Bounces::pullUp(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const vk::Buffer& radiosity,
                     bool indirect) const {
  forEachLevelBottomUp(cmd, h, [&](gpu::LevelPush level) {
    const vk::Bindings bindings = b.pool().with({{"radiosity", radiosity}});
    if (!indirect) return pullUp_.dispatchItems(cmd, level.count, bindings, level);
    const uint32_t index =
        uint32_t(std::find(h.levelStart.begin(), h.levelStart.end(), level.first) - h.levelStart.begin());
    pullUp_.dispatchIndirect(cmd, args_, (1 + index) * sizeof(glm::uvec4), bindings, level);
  });
}

void Bounces::recordEmission(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  emit_.dispatchItems(cmd, surfels, b.pool().with({{"radiosity", b.radiosityA}}), gpu::CountPush{surfels});
  vk::barrier(cmd);
  pullUp(cmd, b, h, b.radiosityA, false);
}

void Bounces::recordStart(VkCommandBuffer cmd) const {
  vkCmdFillBuffer(cmd, state_.handle(), 0, VK_WHOLE_SIZE, 0u);
  const VkBufferCopy all{0, 0, fullArgs_.size()};
  vkCmdCopyBuffer(cmd, fullArgs_.handle(), args_.handle(), 1, &all);
  vk::barrier(cmd);
}

void Bounces::recordSteps(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const LinkSet& staticSet,
                          const LinkSet& frameSet, const IvSettings& settings, uint32_t first, uint32_t steps) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  const gpu::BounceCheckPush check{gatherGroups_, h.levels(), maxGathers(settings),
                                   settings.bounces ? -1.0f : settings.bounceTolerance};
  for (uint32_t k = first; k < first + steps; ++k) {
    const vk::Buffer& in = k % 2 ? b.radiosityB : b.radiosityA;
    const vk::Buffer& out = k % 2 ? b.radiosityA : b.radiosityB;
    gather_.dispatchIndirect(cmd, args_, 0,
                             b.pool().with({{"radiosityIn", in},
                                            {"radiosityOut", out},
                                            {"frameCounters", frameSet.counters},
                                            {"staticCounters", staticSet.counters},
                                            {"bounceSums", sums_}}),
                             gpu::GatherPush{surfels, gpu::maskWordsFor(settings.bins)});
    vk::barrier(cmd);
    pullUp(cmd, b, h, out, true);
    check_.dispatch(cmd, {},
                    {{"bounceSums", sums_}, {"bounceStates", state_}, {"fullArgs", fullArgs_}, {"bounceArgs", args_}},
                    check);
    vk::barrier(cmd);
  }
}

}  // namespace ivgi::gi

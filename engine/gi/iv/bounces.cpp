#include "engine/gi/iv/bounces.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Bounces::Bounces(const vk::Context& ctx)
    : emit_(shaderProgram(ctx, "emit")),
      gather_(shaderProgram(ctx, "gather")),
      pullUp_(shaderProgram(ctx, "pull_up")) {}

void Bounces::pullUp(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const vk::Buffer& radiosity) const {
  forEachLevelBottomUp(cmd, h, [&](gpu::LevelPush level) {
    pullUp_.dispatchItems(cmd, level.count, b.pool().with({{"radiosity", radiosity}}), level);
  });
}

void Bounces::recordEmission(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  emit_.dispatchItems(cmd, surfels, b.pool().with({{"radiosity", b.radiosityA}}), gpu::CountPush{surfels});
  vk::barrier(cmd);
  pullUp(cmd, b, h, b.radiosityA);
}

uint32_t Bounces::record(VkCommandBuffer cmd, const IvBuffers& b, const Hierarchy& h, const LinkSet& staticSet,
                         const LinkSet& frameSet, const IvSettings& settings) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size());
  for (uint32_t k = 0; k <= settings.bounces; ++k) {
    const vk::Buffer& in = k % 2 ? b.radiosityB : b.radiosityA;
    const vk::Buffer& out = k % 2 ? b.radiosityA : b.radiosityB;
    gather_.dispatchItems(cmd, surfels,
                          b.pool().with({{"radiosityIn", in},
                                         {"radiosityOut", out},
                                         {"frameCounters", frameSet.counters},
                                         {"staticCounters", staticSet.counters}}),
                          gpu::GatherPush{surfels, gpu::maskWordsFor(settings.bins)});
    vk::barrier(cmd);
    pullUp(cmd, b, h, out);
  }
  return settings.bounces % 2 ? 0 : 1;
}

}  // namespace ivgi::gi

#include "engine/gi/ar/iteration.h"

namespace ivgi::gi {

ArIteration::ArIteration(const vk::Context& ctx, const Hierarchy& h, const ArSettings& settings, const ArBuffers& b,
                         const LinkSet& staticLinks, const LinkSet& frameLinks, const scene::Geometry& g,
                         vk::Allocations& allocations)
    : b_(b),
      staticLinks_(staticLinks),
      frameLinks_(frameLinks),
      surfelCount_(uint32_t(h.leafOfSurfel.size())),
      firstBackSurfel_(uint32_t(g.surfels.size() - g.backSurfels)),
      nodeCount_(uint32_t(h.nodes.size())),
      bins_(6 * settings.dirs * settings.dirs),
      local_(shaderProgram(ctx, "ar_local",
                           {.constants = {{"kDirs", settings.dirs},
                                          {"kSenderLobes", g.directionalLobes ? 1u : 0u},
                                          {"kBasesByAngle", g.directionalBases ? 1u : 0u}}})),
      pullUp_(shaderProgram(ctx, "ar_pull_up", {.constants = {{"kDirs", settings.dirs}}})),
      gather_(
          shaderProgram(ctx, "ar_gather",
                        {.constants = {{"kDirs", settings.dirs},
                                       {"kSenderLobes", g.directionalLobes ? 1u : 0u},
                                       {"kBasesByAngle", g.directionalBases ? 1u : 0u},
                                       {"kTableHereMost", settings.gatherTableHereMost ? settings.gatherTableHereMost
                                                                                       : gpu::kArGatherTableHere}}})),
      sumDown_(shaderProgram(ctx, "ar_sum_down", {.constants = {{"kDirs", settings.dirs}}})),
      incident_(shaderProgram(ctx, "ar_incident", {.constants = {{"kDirs", settings.dirs}}})) {
  std::vector<uint32_t> inner;
  for (const NodeRange& level : levelsBottomUp(h)) {
    const uint32_t first = uint32_t(inner.size());
    for (uint32_t n = level.first; n < level.first + level.count; ++n)
      if (h.nodes[n].childCount) inner.push_back(n);
    if (inner.size() > first) innerLevels_.push_back({first, uint32_t(inner.size()) - first});
  }
  innerNodes_ =
      vk::makeBuffer(ctx, inner.empty() ? std::vector<uint32_t>{0u} : inner, vk::Memory::Device, &allocations);
}

uint32_t ArIteration::sumGroups() const {
  const vk::Groups g = incident_.groupsFor(surfelCount_, incident_.localSizeX());
  return g.x * g.y;
}

void ArIteration::record(VkCommandBuffer cmd, vk::PassTimer& timer, const ArStep& step) const {
  auto pass = [&](const char* name, auto&& body) {
    if (step.timed)
      timedPass(cmd, timer, name, body);
    else
      body();
  };
  const vk::Bindings levels = b_.pool().with({{"innerNodes", innerNodes_}});
  pass("local", [&] {
    local_.dispatchItems(cmd, surfelCount_, b_.pool(),
                         gpu::ArLocalPush{.surfelCount = surfelCount_,
                                          .firstBackSurfel = firstBackSurfel_,
                                          .updateRadiance = step.radianceStep ? 1u : 0u,
                                          .emittersByMaps = b_.scene.emittersByMaps() ? 1u : 0u});
    for (const NodeRange& level : innerLevels_)
      pullUp_.dispatchItems(cmd, uint64_t(level.count) * bins_, levels,
                            gpu::ArLevelPush{.firstInner = level.first, .innerCount = level.count});
  });
  pass("global", [&] {
    const vk::Bindings links = b_.pool().with({{"staticStarts", staticLinks_.starts},
                                               {"staticSenders", staticLinks_.senders},
                                               {"starts", frameLinks_.starts},
                                               {"senders", frameLinks_.senders}});
    for (uint32_t chunk = 0; chunk < step.chunks; ++chunk)  // each going on where the one before stopped
      gather_.dispatchItems(cmd, nodeCount_, links,
                            gpu::ArGatherPush{.nodeCount = nodeCount_,
                                              .chunk = chunk,
                                              .chunks = step.chunks,
                                              .chunkLinks = step.chunkLinks,
                                              .emittersByMaps = b_.scene.emittersByMaps() ? 1u : 0u});
  });
  pass("incident", [&] {
    for (auto level = innerLevels_.rbegin(); level != innerLevels_.rend(); ++level)  // the top first
      sumDown_.dispatchItems(cmd, level->count, levels,
                             gpu::ArLevelPush{.firstInner = level->first, .innerCount = level->count});
    incident_.dispatchItems(cmd, surfelCount_, b_.pool(),
                            gpu::ArIncidentPush{.surfelCount = surfelCount_,
                                                .sumSlot = step.sumSlot,
                                                .lightCount = b_.scene.lightCount,
                                                .environmentOn = b_.scene.environmentOn ? 1u : 0u,
                                                .emittersByMaps = b_.scene.emittersByMaps() ? 1u : 0u,
                                                .damping = step.damping});
  });
}

}  // namespace ivgi::gi

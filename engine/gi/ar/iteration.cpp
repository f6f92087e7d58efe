#include "engine/gi/ar/iteration.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

ArIteration::ArIteration(const vk::Context& ctx, const Hierarchy& h, const ArSettings& settings,
                         vk::Allocations& allocations)
    : local_(shaderProgram(ctx, "ar_local", {.constants = {{"kDirs", settings.dirs}}})),
      pullUp_(shaderProgram(ctx, "ar_pull_up", {.constants = {{"kDirs", settings.dirs}}})),
      gather_(
          shaderProgram(ctx, "ar_gather",
                        {.constants = {{"kDirs", settings.dirs},
                                       {"kTableHereMost", settings.gatherTableHereMost ? settings.gatherTableHereMost
                                                                                       : gpu::kArGatherTableHere}}})),
      sumDown_(shaderProgram(ctx, "ar_sum_down", {.constants = {{"kDirs", settings.dirs}}})),
      incident_(shaderProgram(ctx, "ar_incident", {.constants = {{"kDirs", settings.dirs}}})) {
  std::vector<uint32_t> inner;
  for (const gpu::LevelPush& level : levelsBottomUp(h)) {
    const uint32_t first = uint32_t(inner.size());
    for (uint32_t n = level.first; n < level.first + level.count; ++n)
      if (h.nodes[n].childCount) inner.push_back(n);
    if (inner.size() > first) innerLevels_.push_back({first, uint32_t(inner.size()) - first});
  }
  innerNodes_ =
      vk::makeBuffer(ctx, inner.empty() ? std::vector<uint32_t>{0u} : inner, vk::Memory::Device, &allocations);
}

uint32_t ArIteration::sumGroups(uint32_t surfelCount) const {
  const vk::Groups g = incident_.groupsFor(surfelCount, incident_.localSizeX());
  return g.x * g.y;
}

void ArIteration::record(VkCommandBuffer cmd, vk::PassTimer& timer, bool timed, const ArBuffers& b, const Hierarchy& h,
                         const LinkSet& staticLinks, const LinkSet& frameLinks, gpu::ArPush push, bool radianceStep,
                         uint32_t slot) const {
  const uint32_t surfels = uint32_t(h.leafOfSurfel.size()), nodes = uint32_t(h.nodes.size());
  const uint32_t bins = 6 * push.bins * push.bins;
  auto pass = [&](const char* name, auto&& body) {
    if (timed)
      timedPass(cmd, timer, name, body);
    else
      body(), vk::barrier(cmd);
  };
  pass("local", [&] {
    local_.dispatchItems(cmd, surfels, b.pool(), gpu::ArPush{surfels, push.bins, 0, radianceStep ? 1u : 0u});
    vk::barrier(cmd);
    for (const gpu::LevelPush& level : innerLevels_) {
      pullUp_.dispatchItems(cmd, uint64_t(level.count) * bins, b.pool().with({{"innerNodes", innerNodes_}}),
                            gpu::ArPush{level.count * bins, push.bins, level.first});
      vk::barrier(cmd);
    }
  });
  pass("global", [&] {
    for (uint32_t chunk = 0; chunk < push.chunks; ++chunk) {  // each going on where the one before stopped
      if (chunk) vk::barrier(cmd);
      gather_.dispatchItems(cmd, nodes,
                            b.pool().with({{"staticStarts", staticLinks.starts},
                                           {"staticSenders", staticLinks.senders},
                                           {"starts", frameLinks.starts},
                                           {"senders", frameLinks.senders}}),
                            gpu::ArPush{nodes, push.bins, chunk, 0, 0, 0, push.chunks, push.chunkLinks});
    }
  });
  pass("incident", [&] {
    for (auto level = innerLevels_.rbegin(); level != innerLevels_.rend(); ++level) {  // the top first
      sumDown_.dispatchItems(cmd, level->count, b.pool().with({{"innerNodes", innerNodes_}}),
                             gpu::ArPush{level->count, push.bins, level->first});
      vk::barrier(cmd);
    }
    push.count = surfels, push.first = slot;
    incident_.dispatchItems(cmd, surfels, b.pool(), push);
  });
}

}  // namespace ivgi::gi

#include "engine/gi/refit.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Refit::Refit(const vk::Context& ctx)
    : refit_(shaderProgram(ctx, "refit")), burial_(shaderProgram(ctx, "buried_surfels")) {}

void Refit::recordNodes(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const {
  refit_.dispatchItems(cmd, scene.surfelCount,
                       scene.pool().with({{"surfels", surfels}, {"climbLeaves", scene.leafOfSurfel}}),
                       gpu::CountPush{.count = scene.surfelCount});
}

void Refit::recordRestBurial(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& restSurfels) {
  if (scene.surfelCount)
    burial_.dispatchItems(
        cmd, scene.surfelCount, scene.pool().with({{"surfels", restSurfels}}),
        gpu::BurialPush{.surfelCount = scene.surfelCount, .rootCount = scene.rootCount, .atRest = 1u});
  shapesKnown_ = true;
}

void Refit::record(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) {
  const bool moversOnly = stillKnown_ && scene.anyStill();
  if (moversOnly) {
    if (scene.movingLeafCount)
      refit_.dispatchItems(cmd, scene.movingLeafCount,
                           scene.pool().with({{"surfels", surfels}, {"climbLeaves", scene.movingLeaves}}),
                           gpu::CountPush{.count = scene.movingLeafCount});
    vk::copyRegion(cmd, scene.nodeStillBuried, scene.nodeBuried,
                   {0, 0, VkDeviceSize(std::max(scene.nodeCount, 1u)) * sizeof(uint32_t)});
  } else {
    recordNodes(cmd, scene, surfels);
    vk::fillBuffer(cmd, scene.nodeBuried, 0u);
    vk::fillBuffer(cmd, scene.nodeStillBuried, 0u);
  }
  // Where nothing that moves may bury a still surfel, only the surfels that move are tested again.
  const bool listed = moversOnly && !scene.movingEncloses;
  const uint32_t items = listed ? scene.movingLeafCount : scene.surfelCount;
  if (items)
    burial_.dispatchItems(cmd, items, scene.pool().with({{"surfels", surfels}}),
                          gpu::BurialPush{.surfelCount = items,
                                          .rootCount = scene.rootCount,
                                          .stillKnown = moversOnly ? 1u : 0u,
                                          .listed = listed ? 1u : 0u,
                                          .shapesKnown = shapesKnown_ ? 1u : 0u});
  stillKnown_ = true;
}

}  // namespace ivgi::gi

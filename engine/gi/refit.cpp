#include "engine/gi/refit.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Refit::Refit(const vk::Context& ctx)
    : refit_(shaderProgram(ctx, "refit")), burial_(shaderProgram(ctx, "buried_surfels")) {}

void Refit::recordNodes(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const {
  refit_.dispatchItems(cmd, scene.nodeCount, scene.pool().with({{"surfels", surfels}}),
                       gpu::CountPush{.count = scene.nodeCount});
}

void Refit::record(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const {
  recordNodes(cmd, scene, surfels);
  vk::fillBuffer(cmd, scene.nodeBuried, 0u);
  vk::fillBuffer(cmd, scene.nodeStillBuried, 0u);
  burial_.dispatchItems(cmd, scene.surfelCount, scene.pool().with({{"surfels", surfels}}),
                        gpu::BurialPush{.surfelCount = scene.surfelCount, .rootCount = scene.rootCount});
}

}  // namespace ivgi::gi

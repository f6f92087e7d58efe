#include "engine/gi/refit.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Refit::Refit(const vk::Context& ctx) : program_(shaderProgram(ctx, "refit")) {}

void Refit::record(VkCommandBuffer cmd, const SceneBuffers& scene, const vk::Buffer& surfels) const {
  program_.dispatchItems(cmd, scene.nodeCount, scene.pool().with({{"surfels", surfels}}),
                         gpu::CountPush{.count = scene.nodeCount});
}

}  // namespace ivgi::gi

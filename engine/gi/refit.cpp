#include "engine/gi/refit.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Refit::Refit(const vk::Context& ctx) : program_(shaderProgram(ctx, "refit")) {}

void Refit::record(VkCommandBuffer cmd, const Hierarchy& h, const vk::Buffer& tree, const vk::Buffer& surfels,
                   const vk::Buffer& nodes) const {
  forEachLevelBottomUp(cmd, h, [&](gpu::LevelPush level) {
    program_.dispatchItems(cmd, level.count, {{"tree", tree}, {"surfels", surfels}, {"nodes", nodes}}, level);
  });
}

}  // namespace ivgi::gi

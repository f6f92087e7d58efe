#include "engine/gi/refit.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

Refit::Refit(const vk::Context& ctx) : program_(shaderProgram(ctx, "refit")) {}

void Refit::record(VkCommandBuffer cmd, const Hierarchy& h, const vk::Buffer& tree, const vk::Buffer& surfels,
                   const vk::Buffer& nodes, const vk::Buffer& arrivals) const {
  const uint32_t count = uint32_t(h.nodes.size());
  program_.dispatchItems(cmd, count, {{"tree", tree}, {"surfels", surfels}, {"nodes", nodes}, {"arrivals", arrivals}},
                         gpu::CountPush{count});
  vk::barrier(cmd);
}

}  // namespace ivgi::gi

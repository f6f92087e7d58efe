#include "engine/gi/raster.h"

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// The most 8×8-sample tiles one raster workgroup walks of each of its large triangles (raster.comp):
// 64 triangles' tiles and tile rows stay within lavapipe's loop budget of 65,535 (common.glsl).
constexpr uint32_t kTilesPerSlice = 448;

}  // namespace

Raster::Raster(const vk::Context& ctx, uint32_t triangleCount, vk::Allocations* tally, bool depthOnly)
    : triangleCount_(triangleCount),
      depthOnly_(depthOnly),
      slices_(shaderProgram(ctx, "raster_slices", {.constants = {{"kTilesPerSlice", kTilesPerSlice}}})),
      raster_(shaderProgram(ctx, "raster",
                            {.constants = {{"kTilesPerSlice", kTilesPerSlice}, {"kDepthOnly", depthOnly ? 1u : 0u}}})) {
  const vk::Groups groups = raster_.groupsFor(triangleCount, 64);
  args_ = vk::makeBuffer(ctx, std::vector<uint32_t>{groups.x, groups.y, 1u}, vk::Memory::Device, tally);
  unused_ = vk::Buffer(ctx, 16, vk::Memory::Device, tally);
}

void Raster::record(VkCommandBuffer cmd, const vk::Bindings& scene, const vk::Buffer& views, uint32_t viewCount,
                    glm::uvec2 size, const vk::Buffer& target, bool clear) const {
  const gpu::RasterPush push{.size = size, .triangleCount = triangleCount_, .viewCount = viewCount};
  if (clear) vk::fillBuffer(cmd, target, 0xFFFFFFFFu);
  vk::fillBuffer(cmd, args_, viewCount, 2 * sizeof(uint32_t), sizeof(uint32_t));  // a slice a view
  slices_.dispatchItems(cmd, triangleCount_, scene.with({{"views", views}, {"rasterArgs", args_}}), push);
  const vk::Buffer &keys = depthOnly_ ? unused_ : target, &depths = depthOnly_ ? target : unused_;
  raster_.dispatchIndirect(cmd, args_, 0, scene.with({{"views", views}, {"visibility", keys}, {"depths", depths}}),
                           push);
}

}  // namespace ivgi::gi

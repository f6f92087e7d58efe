#include "engine/gi/raster.h"

#include <stdexcept>
#include <string>

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// The most 8×8-sample tiles one raster workgroup walks of each of its large triangles (raster.comp):
// 64 triangles' tiles and tile rows stay within lavapipe's loop budget of 65,535 (common.glsl).
constexpr uint32_t kTilesPerSlice = 448;

}  // namespace

Raster::Raster(const vk::Context& ctx, uint32_t triangleCount, vk::Allocations* tally, bool depthOnly)
    : capacity_(triangleCount),
      triangleCount_(triangleCount),
      depthOnly_(depthOnly),
      slices_(shaderProgram(ctx, "raster_slices", {.constants = {{"kTilesPerSlice", kTilesPerSlice}}})),
      raster_(shaderProgram(ctx, "raster",
                            {.constants = {{"kTilesPerSlice", kTilesPerSlice}, {"kDepthOnly", depthOnly ? 1u : 0u}}})) {
  args_ = vk::Buffer(ctx, 3 * sizeof(uint32_t), vk::Memory::Device, tally);
  unused_ = vk::Buffer(ctx, 16, vk::Memory::Device, tally);
}

void Raster::setTriangleCount(uint32_t count) {
  if (count > capacity_)
    throw std::logic_error("Raster: " + std::to_string(count) + " triangles, made for " + std::to_string(capacity_));
  triangleCount_ = count;
}

void Raster::record(VkCommandBuffer cmd, const vk::Bindings& scene, const vk::Buffer& views, uint32_t viewCount,
                    glm::uvec2 size, const vk::Buffer& target, bool clear, uint32_t firstView) const {
  const gpu::RasterPush push{
      .size = size, .triangleCount = triangleCount_, .viewCount = viewCount, .firstView = firstView};
  if (clear) vk::fillBuffer(cmd, target, 0xFFFFFFFFu);
  const vk::Groups groups = raster_.groupsFor(triangleCount_, 64);
  const uint32_t args[3] = {groups.x, groups.y, viewCount};  // a slice a view, until raster_slices counts
  vk::updateBuffer(cmd, args_, 0, sizeof args, args);
  slices_.dispatchItems(cmd, triangleCount_, scene.with({{"views", views}, {"rasterArgs", args_}}), push);
  const vk::Buffer &keys = depthOnly_ ? unused_ : target, &depths = depthOnly_ ? target : unused_;
  raster_.dispatchIndirect(cmd, args_, 0, scene.with({{"views", views}, {"visibility", keys}, {"depths", depths}}),
                           push);
}

}  // namespace ivgi::gi

#include "engine/gi/raster.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// The most 8×8-sample tiles one raster workgroup walks of the large triangles it draws into its
// views (raster.comp), a loop round each: 64 triangles in each view, with their small triangles'
// walks, stay within lavapipe's loop budget of 65,535 (common.glsl).
constexpr uint32_t kLargeTilesPerGroup = 64 * 896;

// The views one raster workgroup draws where it draws many (a light's depth maps): a small
// triangle's corners, read once for them all, are most of what drawing it into a view costs.
constexpr uint32_t kViewsPerGroup = 8;

// raster.comp's kDraw: every triangle; those whose material's alpha takes nothing away (alphaMode
// MASK or BLEND); those whose material's alpha does, each sample tested.
constexpr uint32_t kDrawAll = 0, kDrawUncut = 1, kDrawCutting = 2;

}  // namespace

Raster::Raster(const vk::Context& ctx, uint32_t triangleCount, vk::Allocations* tally, bool depthOnly,
               uint32_t maxViews, bool cutouts, bool viewsOnHost)
    : capacity_(triangleCount),
      triangleCount_(triangleCount),
      maxViews_(maxViews),
      depthOnly_(depthOnly),
      viewsPerGroup_(maxViews > 1 ? kViewsPerGroup : 1),
      tilesPerSlice_(kLargeTilesPerGroup / (64 * viewsPerGroup_)),
      drawnBounds_(shaderProgram(ctx, "drawn_bounds")),
      drawnViews_(shaderProgram(ctx, "drawn_views", {.constants = {{"kViewsPerGroup", viewsPerGroup_}}})),
      slices_(shaderProgram(ctx, "raster_slices",
                            {.constants = {{"kTilesPerSlice", tilesPerSlice_}, {"kViewsPerGroup", viewsPerGroup_}}})),
      raster_(shaderProgram(ctx, "raster",
                            {.constants = {{"kTilesPerSlice", tilesPerSlice_},
                                           {"kDepthOnly", depthOnly ? 1u : 0u},
                                           {"kDraw", cutouts ? kDrawUncut : kDrawAll},
                                           {"kViewsPerGroup", viewsPerGroup_}}})) {
  if (cutouts)
    rasterCutting_.emplace(ctx, "raster", shaderCode("raster"),
                           vk::Specialization{.constants = {{"kTilesPerSlice", tilesPerSlice_},
                                                            {"kDepthOnly", depthOnly ? 1u : 0u},
                                                            {"kDraw", kDrawCutting},
                                                            {"kViewsPerGroup", viewsPerGroup_}}});
  box_ = vk::Buffer(ctx, 6 * sizeof(uint32_t), vk::Memory::Device, tally);
  viewList_ = vk::Buffer(ctx, (1 + uint64_t(maxViews)) * sizeof(uint32_t),
                         viewsOnHost ? vk::Memory::Host : vk::Memory::Device, tally);
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
  if (viewCount > maxViews_)
    throw std::logic_error("Raster: " + std::to_string(viewCount) + " views, made for " + std::to_string(maxViews_));
  const bool cull = viewCount > 1;  // one view is the camera's, which sees the scene
  const gpu::RasterPush push{.size = size,
                             .triangleCount = triangleCount_,
                             .viewCount = viewCount,
                             .firstView = firstView,
                             .cull = cull ? 1u : 0u};
  if (clear) vk::fillBuffer(cmd, target, 0xFFFFFFFFu);
  const vk::Groups groups = raster_.groupsFor(triangleCount_, 64);
  const uint32_t args[3] = {groups.x, groups.y, 0};  // z: the views drawn (drawn_views), their slices (raster_slices)
  vk::updateBuffer(cmd, args_, 0, sizeof args, args);
  const vk::Bindings buffers =
      vk::Bindings::pool({{"views", views}, {"drawnBox", box_}, {"drawnViews", viewList_}, {"rasterArgs", args_}})
          .plus(scene);
  if (cull) {
    vk::fillBuffer(cmd, box_, 0xFFFFFFFFu, 0, 3 * sizeof(uint32_t));  // min: the largest
    vk::fillBuffer(cmd, box_, 0u, 3 * sizeof(uint32_t), 3 * sizeof(uint32_t));
    drawnBounds_.dispatchItems(cmd, triangleCount_, buffers, push);
  }
  drawnViews_.dispatch(cmd, {}, buffers, push);
  slices_.dispatchItems(cmd, triangleCount_, buffers, push);
  const vk::Buffer &keys = depthOnly_ ? unused_ : target, &depths = depthOnly_ ? target : unused_;
  const vk::Bindings targets = buffers.with({{"visibility", keys}, {"depths", depths}});
  raster_.dispatchIndirect(cmd, args_, 0, targets, push);
  if (rasterCutting_) rasterCutting_->dispatchIndirect(cmd, args_, 0, targets, push);
}

uint32_t Raster::viewsDrawn() const { return uint32_t(drawnViewList().size()); }

std::vector<uint32_t> Raster::drawnViewList() const {
  std::vector<uint32_t> list = viewList_.read<uint32_t>(1 + size_t(maxViews_));
  const uint32_t count = std::min(list[0], maxViews_);
  return {list.begin() + 1, list.begin() + 1 + count};
}

}  // namespace ivgi::gi

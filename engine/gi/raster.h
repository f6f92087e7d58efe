#pragma once
// The raster (shaders/frame/drawn_bounds.comp, drawn_views.comp, raster_slices.comp, raster.comp):
// the nearest triangle at every sample of one or more views, as 64-bit depth and triangle keys, the
// views one after another in the target. The camera's view is one; a light's depth maps are the
// faces of a cube around each of its samples. Where it draws many views, those that the triangles'
// bounding box cannot reach are left out.
#include <optional>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/program.h"
#include "shaders/interface.h"

namespace ivgi::gi {

class Raster {
 public:
  // `depthOnly`: the target holds each sample's nearest depth as 32-bit float bits (depth maps);
  // else 64-bit depth and triangle keys. `maxViews`: the most views one record draws. `cutouts`:
  // some material's alpha takes its surface away (alphaMode MASK or BLEND), and a sample there is
  // not covered. `viewsOnHost`: the list of views drawn kept in host memory, read without a
  // submission (drawnViewList).
  Raster(const vk::Context& ctx, uint32_t triangleCount, vk::Allocations* tally, bool depthOnly = false,
         uint32_t maxViews = 1, bool cutouts = false, bool viewsOnHost = false);

  // The triangles the next records draw: the first `count` of the scene's, at most as many as made for.
  void setTriangleCount(uint32_t count);

  // Rasterizes the triangles (`world`, `triangles` from `scene`) into `target`: `viewCount` views of
  // `size` samples each from `firstView` on, whose cameras `views` holds (a view whose near is
  // negative is skipped and left empty). `clear`: the whole target emptied first; else the triangles
  // go over what it holds.
  void record(VkCommandBuffer cmd, const vk::Bindings& scene, const vk::Buffer& views, uint32_t viewCount,
              glm::uvec2 size, const vk::Buffer& target, bool clear = true, uint32_t firstView = 0) const;

  // How many views the last record drew into (read back; for tests).
  uint32_t viewsDrawn() const;
  // The views the last record drew into, in no order (read back once its submission has finished).
  std::vector<uint32_t> drawnViewList() const;

 private:
  uint32_t capacity_, triangleCount_, maxViews_;
  bool depthOnly_;
  uint32_t viewsPerGroup_;  // raster.comp's kViewsPerGroup
  uint32_t tilesPerSlice_;  // its kTilesPerSlice: of each large triangle in one view
  vk::Program drawnBounds_, drawnViews_, slices_, raster_;
  std::optional<vk::Program> rasterCutting_;  // the triangles whose material cuts them, where any does
  vk::Buffer box_;                            // the triangles' bounding box (drawn_bounds)
  vk::Buffer viewList_;                       // how many views are drawn, then which (drawn_views)
  vk::Buffer args_;    // the raster's dispatch: its x and y for the triangles, its z counted by raster_slices
  vk::Buffer unused_;  // bound where the shader's other target is not written
};

}  // namespace ivgi::gi

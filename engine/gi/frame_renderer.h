#pragma once
// One frame on the GPU, as the list of passes of design.md §2 that this stage of ivgi has:
// animate → surfels → rasterise → resolve. Scene data is uploaded once; per frame only the
// matrices and morph weights go up and the image channels come down.
#include <string>
#include <vector>

#include <memory>
#include <optional>

#include "engine/gi/hierarchy.h"
#include "engine/gi/iv_solver.h"
#include "engine/gi/shared.h"
#include "engine/image/frame_image.h"
#include "engine/scene/camera.h"
#include "engine/scene/geometry.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

struct ImageSettings {
  uint32_t width = 640, height = 360;
  uint32_t samples = 1;  // supersampling: samples × samples per pixel
};

// Why this image cannot be rendered on this device (empty when it can).
std::string checkImageSettings(const vk::Context& ctx, const ImageSettings& s);

struct FrameResult {
  image::FrameChannels channels;
  std::vector<vk::PassTime> passTimes;
};

class FrameRenderer {
 public:
  FrameRenderer(const vk::Context& ctx, const scene::Geometry& geometry, const ImageSettings& image, std::optional<IvSetup> iv = {});

  // `lights`: the punctual lights in world space; `geometryMoved`: whether the solver must refit and
  // relink (false only for static geometry after the first frame).
  FrameResult render(const scene::FrameInputs& inputs, const scene::CameraView& view, const std::vector<GpuLight>& lights = {},
                     bool geometryMoved = true);
  const IvSolver* solver() const { return solver_.get(); }

  // Results of the last frame's geometry passes (for tests and later solvers).
  std::vector<scene::WorldVertex> worldVertices() const;
  std::vector<scene::Surfel> surfels() const;
  uint64_t bytesAllocated() const { return bytes_; }

 private:
  vk::Buffer& track(vk::Buffer&& b);

  const vk::Context& ctx_;
  ImageSettings image_;
  uint32_t vertexCount_, triangleCount_, surfelCount_;
  uint64_t bytes_ = 0;
  std::vector<vk::Buffer> owned_;

  // Scene data, uploaded once.
  vk::Buffer *vertices_, *instances_, *morphDeltas_, *triangles_, *uvs_, *materials_, *textures_, *texels_;
  vk::Buffer *surfelSources_, *surfelVertices_, *surfelTriangles_;
  // Per frame.
  vk::Buffer *matrices_, *morphWeights_, *world_, *surfels_, *visibility_;
  vk::Buffer *radiance_, *albedo_, *normalDepth_, *emission_;
  vk::Buffer *vertexSurfel_, *unlitIrradiance_;

  std::unique_ptr<IvSetup> iv_;
  std::unique_ptr<IvSolver> solver_;

  vk::Program animate_, surfelUpdate_, raster_, resolve_;
  vk::PassTimer timer_;
};

}  // namespace ivgi::gi

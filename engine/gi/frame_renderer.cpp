#include "engine/gi/frame_renderer.h"

#include <algorithm>

#include "engine/gi/pass.h"

namespace ivgi::gi {

namespace {

// The most 8×8-sample tiles one raster workgroup walks (raster.comp): about 35,000 loop rounds a
// subgroup, within lavapipe's budget of 65,535 (common.glsl).
constexpr uint32_t kRasterTilesPerSlice = 32768;

// Raster workgroups per triangle: the slices of tile rows that bounds as large as the image need.
uint32_t rasterSlices(glm::uvec2 samples) {
  const uint32_t columns = (samples.x + 7) / 8, rows = (samples.y + 7) / 8, rowsPerSlice = std::max(1u, kRasterTilesPerSlice / columns);
  return (rows + rowsPerSlice - 1) / rowsPerSlice;
}

struct ImagePush {
  GpuCamera camera;
  glm::uvec2 size;
  uint32_t count;  // raster: triangles; resolve: samples per axis
  uint32_t unused = 0;
};

// Surfel of each vertex (welded vertices share one), -1 for vertices without one.
std::vector<int32_t> vertexSurfels(const scene::Geometry& g) {
  std::vector<int32_t> out(g.vertices.size(), -1);
  for (size_t s = 0; s < g.surfels.size(); ++s)
    for (uint32_t k = 0; k < g.surfels[s].vertexCount; ++k) out[g.surfelVertices[g.surfels[s].firstVertex + k]] = int32_t(s);
  return out;
}

}  // namespace

std::string checkImageSettings(const vk::Context& ctx, const ImageSettings& s) {
  const auto& lim = ctx.limits();
  if (s.width == 0 || s.height == 0) return "image size " + std::to_string(s.width) + "x" + std::to_string(s.height) + " is empty";
  if (s.samples == 0 || s.samples > 16) return "supersampling must be 1 to 16 samples per axis";
  if (s.width > lim.maxImageDimension2D || s.height > lim.maxImageDimension2D)
    return "image size " + std::to_string(s.width) + "x" + std::to_string(s.height) + " exceeds the device limit of " +
           std::to_string(lim.maxImageDimension2D) + " pixels per side";
  uint64_t samples = uint64_t(s.width) * s.height * s.samples * s.samples;
  if (samples * 8 > lim.maxStorageBufferRange || uint64_t(s.width) * s.height * 16 > lim.maxStorageBufferRange)
    return "image of " + std::to_string(s.width) + "x" + std::to_string(s.height) + " with " + std::to_string(s.samples) +
           "x" + std::to_string(s.samples) + " samples needs buffers above the device's maxStorageBufferRange (" +
           std::to_string(lim.maxStorageBufferRange >> 20) + " MiB)";
  return {};
}

vk::Buffer& FrameRenderer::track(vk::Buffer&& b) {
  bytes_ += b.size();
  owned_.push_back(std::move(b));
  return owned_.back();
}

FrameRenderer::FrameRenderer(const vk::Context& ctx, const scene::Geometry& g, const ImageSettings& image, std::optional<IvSetup> iv)
    : ctx_(ctx),
      image_(image),
      vertexCount_(uint32_t(g.vertices.size())),
      triangleCount_(uint32_t(g.triangles.size())),
      surfelCount_(uint32_t(g.surfels.size())),
      animate_(ctx, "animate"),
      surfelUpdate_(ctx, "surfels"),
      raster_(ctx, "raster", {kRasterTilesPerSlice}),
      resolve_(ctx, "resolve", {g.textures.empty() ? 0u : 1u, iv ? 1u : 0u}),
      timer_(ctx) {
  if (std::string why = checkImageSettings(ctx, image); !why.empty()) throw vk::VulkanError(why);
  owned_.reserve(32);  // pointers into owned_ stay valid
  using vk::Memory;
  vertices_ = &track(vk::makeBuffer(ctx, g.vertices));
  instances_ = &track(vk::makeBuffer(ctx, g.instances));
  morphDeltas_ = &track(vk::makeBuffer(ctx, g.morphDeltas));
  triangles_ = &track(vk::makeBuffer(ctx, g.triangles));
  uvs_ = &track(vk::makeBuffer(ctx, g.uvs));
  materials_ = &track(vk::makeBuffer(ctx, g.materials));
  textures_ = &track(vk::makeBuffer(ctx, g.textures));
  texels_ = &track(vk::makeBuffer(ctx, g.texels));
  surfelSources_ = &track(vk::makeBuffer(ctx, g.surfels));
  surfelVertices_ = &track(vk::makeBuffer(ctx, g.surfelVertices));
  surfelTriangles_ = &track(vk::makeBuffer(ctx, g.surfelTriangles));

  matrices_ = &track(vk::Buffer(ctx, 0, Memory::Host));  // sized on the first frame
  morphWeights_ = &track(vk::Buffer(ctx, std::max<uint32_t>(g.morphWeightCount, 1) * sizeof(float), Memory::Host));
  world_ = &track(vk::Buffer(ctx, std::max<size_t>(vertexCount_, 1) * sizeof(scene::WorldVertex), Memory::Device));
  surfels_ = &track(vk::Buffer(ctx, std::max<size_t>(surfelCount_, 1) * sizeof(scene::Surfel), Memory::Device));
  uint64_t pixels = uint64_t(image.width) * image.height;
  visibility_ = &track(vk::Buffer(ctx, pixels * image.samples * image.samples * sizeof(uint64_t), Memory::Device));
  for (vk::Buffer** channel : {&radiance_, &albedo_, &normalDepth_, &emission_})
    *channel = &track(vk::Buffer(ctx, pixels * sizeof(glm::vec4), Memory::Host));
  vertexSurfel_ = &track(vk::makeBuffer(ctx, vertexSurfels(g)));
  unlitIrradiance_ = &track(vk::Buffer(ctx, 16, Memory::Device));
  if (iv) {
    iv_ = std::make_unique<IvSetup>(std::move(*iv));
    solver_ = std::make_unique<IvSolver>(ctx, g, *iv_);
  }
}

FrameResult FrameRenderer::render(const scene::FrameInputs& in, const scene::CameraView& view, const std::vector<GpuLight>& lights,
                                  bool geometryMoved) {
  if (matrices_->size() < in.matrices.size() * sizeof(glm::mat4)) {
    bytes_ -= matrices_->size();
    *matrices_ = vk::Buffer(ctx_, in.matrices.size() * sizeof(glm::mat4), vk::Memory::Host);
    bytes_ += matrices_->size();
  }
  matrices_->upload(in.matrices);
  morphWeights_->upload(in.morphWeights);
  if (solver_) solver_->setLights(lights);

  const glm::uvec2 size(image_.width, image_.height), fine = size * image_.samples;
  const GpuCamera camera = gpuCamera(view, float(image_.width) / float(image_.height));
  const vk::Buffer* irradiance = solver_ ? &solver_->irradiance() : unlitIrradiance_;
  bool redo = false;
  do ctx_.submitAndWait([&](VkCommandBuffer cmd) {
    timer_.reset(cmd);
    timedPass(cmd, timer_, "animate", [&] {
      animate_.dispatchItems(cmd, vertexCount_, {vertices_, instances_, morphDeltas_, matrices_, morphWeights_, world_}, vertexCount_);
    });
    timedPass(cmd, timer_, "surfels", [&] {
      surfelUpdate_.dispatchItems(cmd, surfelCount_, {surfelSources_, surfelVertices_, surfelTriangles_, triangles_, world_, surfels_},
                                  surfelCount_);
    });
    if (solver_) solver_->record(cmd, timer_, *surfels_, geometryMoved || redo);
    timedPass(cmd, timer_, "raster", [&] {
      vkCmdFillBuffer(cmd, visibility_->handle(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
      vk::barrier(cmd);
      vk::Groups groups = raster_.groupsFor(triangleCount_, 1);
      groups.z = rasterSlices(fine);
      raster_.dispatch(cmd, groups, {world_, triangles_, visibility_}, ImagePush{camera, fine, triangleCount_});
    });
    timedPass(cmd, timer_, "resolve", [&] {
      resolve_.dispatch(cmd, {(size.x + 7) / 8, (size.y + 7) / 8, 1},
                        {world_, triangles_, visibility_, uvs_, materials_, textures_, texels_, radiance_, albedo_, normalDepth_, emission_,
                         vertexSurfel_, irradiance},
                        ImagePush{camera, size, image_.samples});
    });
  });
  while ((redo = solver_ && solver_->growIfOverflowed()));
  if (solver_) solver_->releaseUnusedLinks();

  FrameResult result;
  result.passTimes = timer_.results();
  image::FrameChannels& c = result.channels;
  c.width = image_.width, c.height = image_.height;
  size_t pixels = size_t(image_.width) * image_.height;
  c.radiance = radiance_->read<glm::vec4>(pixels);
  c.albedo = albedo_->read<glm::vec4>(pixels);
  c.normalDepth = normalDepth_->read<glm::vec4>(pixels);
  c.emission = emission_->read<glm::vec4>(pixels);
  return result;
}

std::vector<scene::WorldVertex> FrameRenderer::worldVertices() const { return world_->read<scene::WorldVertex>(vertexCount_); }
std::vector<scene::Surfel> FrameRenderer::surfels() const { return surfels_->read<scene::Surfel>(surfelCount_); }

}  // namespace ivgi::gi

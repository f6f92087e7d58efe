#pragma once
// One frame on the GPU as its list of passes (docs/design.md §4): animate → surfels →
// the solver's passes (iv: refit → links → receivers and prune → bounces; ar: refit → links →
// iterations) → raster → resolve. Scene data is
// uploaded once; per frame only the matrices, morph weights and lights go up and the image channels
// come down.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/gi/direct_light.h"
#include "engine/gi/raster.h"
#include "engine/gi/solver.h"
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

// Throws SettingsError (naming --size or --supersample) when the image cannot be rendered on this
// device.
void validate(const ImageSettings& settings, const vk::Context& ctx);

struct FrameResult {
  image::FrameChannels channels;
  std::vector<vk::PassTime> passTimes;                        // a pass recorded more than once (or redone): summed
  std::vector<std::pair<std::string, double>> solverFigures;  // the solver's frameFigures()
  // After timePrograms(): per program, its dispatches' times summed and how many ran.
  std::vector<vk::PassTime> programTimes;
};

class FrameRenderer {
 public:
  // `solver`: the lighting method; none renders emission only. `directLight`: light the surfels
  // from the emitters through depth maps each frame (where something emits), `movingInstances`
  // saying which instances the animation can move (scene::movingInstances; empty: any may).
  FrameRenderer(const vk::Context& ctx, const scene::Geometry& geometry, const ImageSettings& image,
                std::unique_ptr<Solver> solver = nullptr,
                const std::optional<DirectLightSettings>& directLight = std::nullopt,
                const std::vector<bool>& movingInstances = {});
  ~FrameRenderer();

  // `lights`: the punctual lights in world space; `geometryMoved`: whether the geometry or the lights
  // moved since the last frame (false only where nothing does, after the first frame: the posed
  // surfels and the solution then stand); `frame`: the frame's number, for a solver that chains
  // frames (Solver::chainStart; negative: none).
  FrameResult render(const scene::FrameInputs& inputs, const scene::CameraView& view,
                     const std::vector<gpu::PunctualLight>& lights = {}, bool geometryMoved = true, int frame = -1);
  const Solver* solver() const { return solver_.get(); }
  const DirectLight* directLight() const { return direct_ ? &*direct_ : nullptr; }

  // Results of the last frame's geometry passes (for tests and later solvers).
  std::vector<scene::WorldVertex> worldVertices() const;
  std::vector<scene::Surfel> surfels() const;
  // Device memory of the frame's own buffers and of the solver's.
  uint64_t bytesAllocated() const;
  // From the next frame on, every dispatch is timed on its own too (a timestamp before and after
  // each), by program: FrameResult::programTimes.
  void timePrograms();
  // For tests: the reflections at every surfel, not only where the image reads them (mark_shown).
  void reflectEverySurfel() { reflectEverySurfel_ = true; }
  // After a frame with reflections, or whose solve followed the view: per surfel, what its image
  // read (gpu's kShown bits).
  std::vector<uint32_t> shownSurfels() const;

 private:
  // The frame's passes; false where the solver left its solve for later and the resolve with it.
  // `redo`: the frame is recorded again, its earlier runs' times kept (they are what it cost too).
  bool recordFrame(VkCommandBuffer cmd, const gpu::Camera& camera, bool geometryMoved, bool redo);
  void recordResolve(VkCommandBuffer cmd, const gpu::Camera& camera);
  vk::Bindings pool() const;  // every buffer by the name the shaders bind it under

  const vk::Context& ctx_;
  ImageSettings image_;
  uint32_t vertexCount_, triangleCount_, surfelCount_;
  vk::Allocations allocations_;  // before the buffers, which count themselves into it
  // Scene data, uploaded once.
  vk::Buffer vertices_, instances_, morphDeltas_, triangles_, uvs_, colors_, materials_, textures_, texels_,
      specularAlbedo_, pixelSpecular_, pixelTurn_;
  vk::Buffer surfelSources_, surfelVertices_, surfelTriangles_, surfelCoverage_, vertexSurfel_;
  // The vertices and surfels of the instances that can move (every one where none stays still):
  // once a frame has posed them all, the others stand.
  vk::Buffer movingVertices_, movingSurfels_;
  uint32_t movingVertexCount_ = 0, movingSurfelCount_ = 0;
  // Per frame.
  vk::Buffer matrices_, morphWeights_, world_, surfels_, visibility_, unlitIrradiance_;
  vk::Buffer shownIrradiance_;  // the solver's irradiance carried to each surfel's vertex (vertex_irradiance)
  // With the direct light per pixel: the surfels' direct light unshadowed, carried to their vertices,
  // and per pixel its share of the emitter samples' light (direct_pixels).
  vk::Buffer vertexUnshadowed_, pixelLights_;
  // Where the solver reflects the glossy lobes (reflections_): per surfel what its lobe reflects of
  // the indirect light toward the camera, and that carried to its vertex.
  vk::Buffer surfelLobe_, vertexLobe_;
  vk::Buffer shownSurfels_;   // and per surfel what the image reads of those (gpu's kShown bits)
  vk::Buffer noDirectLight_;  // bound for the direct light's buffers where there is none (never read)
  vk::Buffer view_;           // the camera, the raster's one view
  vk::Buffer radiance_, albedo_, normalDepth_, emission_, roughnessMetallic_;  // mapped: the image channels
  std::unique_ptr<Solver> solver_;
  bool directPerPixel_;  // the resolve adds the depth maps' direct light at each sample
  bool reflections_;     // the solver reflects the indirect light through the glossy lobes
  bool viewGuided_;      // the solver's receivers follow what the image shows
  bool posed_ = false;   // a frame posed the vertices and the surfels
  bool reflectEverySurfel_ = false;
  vk::Program animate_, surfelUpdate_, vertexIrradiance_, unshadowedToVertices_, lobesToVertices_, markShown_, markFit_,
      directPixels_, resolve_;
  Raster raster_;
  std::optional<DirectLight> direct_;
  vk::PassTimer timer_;
  std::optional<vk::PassTimer> programTimer_;  // timePrograms()
};

}  // namespace ivgi::gi

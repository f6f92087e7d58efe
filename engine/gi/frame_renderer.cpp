#include "engine/gi/frame_renderer.h"

#include <algorithm>

#include "engine/core/errors.h"
#include "engine/gi/pass.h"
#include "engine/scene/reflectance.h"

namespace ivgi::gi {

namespace {

// Whether the maps have something to light with: emitters or punctual lights.
bool somethingLights(const scene::Geometry& g, const DirectLightSettings& directLight) {
  return directLight.punctualLights > 0 || !directLight.environmentLights().empty() || emits(g);
}

// Whether the pixels of a frame of `g` look the depth maps' direct light up themselves: asked for, a
// solver to take the rest, and something lights.
bool directPerPixel(const scene::Geometry& g, bool solver, const std::optional<DirectLightSettings>& directLight) {
  return solver && directLight && directLight->perPixel && somethingLights(g, *directLight);
}

}  // namespace

void validate(const ImageSettings& s, const vk::Context& ctx) {
  const auto& lim = ctx.limits();
  const std::string size = "--size " + std::to_string(s.width) + "x" + std::to_string(s.height);
  if (s.width == 0 || s.height == 0) throw SettingsError(size + ": width and height must be at least 1");
  if (s.samples == 0 || s.samples > 16)
    throw SettingsError("--supersample " + std::to_string(s.samples) + ": must be 1 to 16");
  if (s.width > lim.maxImageDimension2D || s.height > lim.maxImageDimension2D)
    throw SettingsError(size + ": exceeds the device limit of " + std::to_string(lim.maxImageDimension2D) +
                        " pixels per side");
  const uint64_t samples = uint64_t(s.width) * s.height * s.samples * s.samples;
  if (samples * 8 > lim.maxStorageBufferRange || uint64_t(s.width) * s.height * 16 > lim.maxStorageBufferRange)
    throw SettingsError(size + " with " + std::to_string(s.samples) + "x" + std::to_string(s.samples) +
                        " samples needs buffers above the device's maxStorageBufferRange (" +
                        std::to_string(lim.maxStorageBufferRange >> 20) + " MiB)");
}

FrameRenderer::FrameRenderer(const vk::Context& ctx, const scene::Geometry& g, const ImageSettings& image,
                             std::unique_ptr<Solver> solver, const std::optional<DirectLightSettings>& directLight,
                             const std::vector<bool>& movingInstances)
    : ctx_(ctx),
      image_(image),
      vertexCount_(uint32_t(g.vertices.size())),
      triangleCount_(uint32_t(g.triangles.size())),
      surfelCount_(uint32_t(g.surfels.size())),
      solver_(std::move(solver)),
      directPerPixel_(directPerPixel(g, solver_ != nullptr, directLight)),
      reflections_(g.directionalLobes && solver_ && solver_->reflectsLobes()),
      viewGuided_(solver_ && solver_->guidedByView()),
      animate_(shaderProgram(ctx, "animate")),
      surfelUpdate_(shaderProgram(ctx, "surfels")),
      vertexIrradiance_(
          shaderProgram(ctx, "vertex_irradiance", {.constants = {{"kDirectPixels", directPerPixel_ ? 1u : 0u}}})),
      unshadowedToVertices_(shaderProgram(ctx, "vertex_irradiance")),
      lobesToVertices_(shaderProgram(ctx, "vertex_irradiance", {.constants = {{"kShownOnly", 1u}}})),
      markShown_(shaderProgram(ctx, "mark_shown")),
      markFit_(shaderProgram(ctx, "mark_fit")),
      directPixels_(shaderProgram(ctx, "direct_pixels",
                                  {.constants = {{"kTextured", g.textures.empty() ? 0u : 1u},
                                                 {"kColored", g.vertexColors ? 1u : 0u},
                                                 {"kGlossy", g.glossyMaterials ? 1u : 0u},
                                                 {"kNormalMapped", g.normalTextures ? 1u : 0u},
                                                 {"kBlendedMaps", g.blended ? 1u : 0u}}})),
      resolve_(shaderProgram(ctx, "resolve",
                             {.constants = {{"kTextured", g.textures.empty() ? 0u : 1u},
                                            {"kLit", solver_ ? 1u : 0u},
                                            {"kColored", g.vertexColors ? 1u : 0u},
                                            {"kDirectPixels", directPerPixel_ ? 1u : 0u},
                                            {"kGlossy", g.glossyMaterials ? 1u : 0u},
                                            {"kReflections", reflections_ ? 1u : 0u},
                                            {"kNormalMapped", g.normalTextures ? 1u : 0u}}})),
      raster_(ctx, triangleCount_, &allocations_, false, 1, g.cutouts),
      timer_(ctx) {
  validate(image, ctx);
  using vk::Memory;
  vk::Allocations* tally = &allocations_;
  auto upload = [&](const auto& items) { return vk::makeBuffer(ctx, items, Memory::Device, tally); };
  vertices_ = upload(g.vertices), instances_ = upload(g.instances), morphDeltas_ = upload(g.morphDeltas);
  triangles_ = upload(g.triangles), uvs_ = upload(g.uvs), materials_ = upload(g.materials);
  // The raster reads the colours' alpha where a material's alpha takes surface away.
  colors_ = upload(g.vertexColors || g.cutouts ? g.colors : std::vector<glm::vec4>{glm::vec4(1)});
  textures_ = upload(g.textures), texels_ = upload(g.texels);
  surfelSources_ = upload(g.surfels), surfelVertices_ = upload(g.surfelVertices),
  surfelTriangles_ = upload(g.surfelTriangles), surfelCoverage_ = upload(g.surfelCoverage);
  vertexSurfel_ = upload(scene::vertexSurfels(g));
  {
    auto moves = [&](uint32_t vertex) {
      return movingInstances.empty() || movingInstances.at(g.vertices[vertex].instance);
    };
    std::vector<uint32_t> vertices, surfels;
    for (uint32_t v = 0; v < vertexCount_; ++v)
      if (moves(v)) vertices.push_back(v);
    for (uint32_t s = 0; s < surfelCount_; ++s)
      if (moves(g.surfelVertices[g.surfels[s].firstVertex])) surfels.push_back(s);
    movingVertexCount_ = uint32_t(vertices.size()), movingSurfelCount_ = uint32_t(surfels.size());
    movingVertices_ = upload(vertices.empty() ? std::vector<uint32_t>{0u} : vertices);  // one stand-in, never read
    movingSurfels_ = upload(surfels.empty() ? std::vector<uint32_t>{0u} : surfels);
  }
  specularAlbedo_ = upload(g.glossyMaterials ? scene::SpecularAlbedo::table().texels() : std::vector<glm::vec4>(1));

  matrices_ = vk::Buffer(ctx, 0, Memory::Host, tally);  // sized on the first frame
  morphWeights_ = vk::Buffer(ctx, std::max<uint32_t>(g.morphWeightCount, 1) * sizeof(float), Memory::Host, tally);
  world_ = vk::Buffer(ctx, std::max<size_t>(vertexCount_, 1) * sizeof(scene::WorldVertex), Memory::Device, tally);
  surfels_ = vk::Buffer(ctx, std::max<size_t>(surfelCount_, 1) * sizeof(scene::Surfel), Memory::Device, tally);
  const uint64_t pixels = uint64_t(image.width) * image.height;
  visibility_ = vk::Buffer(ctx, pixels * image.samples * image.samples * sizeof(uint64_t), Memory::Device, tally);
  for (vk::Buffer* channel : {&radiance_, &albedo_, &normalDepth_, &emission_, &roughnessMetallic_})
    *channel = vk::Buffer(ctx, pixels * sizeof(glm::vec4), Memory::Host, tally);
  unlitIrradiance_ = vk::Buffer(ctx, 16, Memory::Device, tally);
  shownIrradiance_ =
      vk::Buffer(ctx, std::max<size_t>(solver_ ? surfelCount_ : 0, 1) * sizeof(glm::vec4), Memory::Device, tally);
  view_ = vk::Buffer(ctx, sizeof(gpu::Camera), Memory::Device, tally);
  const uint64_t pixelLightBytes = directPerPixel_ ? pixels * sizeof(gpu::PixelLight) : 16;
  if (pixelLightBytes > ctx.limits().maxStorageBufferRange)
    throw SettingsError("--direct pixels at --size " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + " needs " + std::to_string(pixelLightBytes >> 20) +
                        " MiB for the pixels' direct light, above the device's maxStorageBufferRange (" +
                        std::to_string(ctx.limits().maxStorageBufferRange >> 20) + " MiB)");
  pixelLights_ = vk::Buffer(ctx, pixelLightBytes, Memory::Device, tally);
  // Two texels a pixel (direct_pixels): its lobe's reflection of the emitter samples and of the
  // punctual lights. Smaller than pixelLights, so within the range the check above allowed.
  pixelSpecular_ = vk::Buffer(ctx, directPerPixel_ && g.glossyMaterials ? pixels * 2 * sizeof(glm::vec4) : 16,
                              Memory::Device, tally);
  // Two texels a pixel (direct_pixels, where a normal texture turns its light): its light's vectors.
  pixelTurn_ =
      vk::Buffer(ctx, directPerPixel_ && g.normalTextures ? pixels * 2 * sizeof(glm::vec4) : 16, Memory::Device, tally);
  vertexUnshadowed_ = vk::Buffer(ctx, directPerPixel_ ? shownIrradiance_.size() : 16, Memory::Device, tally);
  surfelLobe_ = vk::Buffer(ctx, reflections_ ? shownIrradiance_.size() : 16, Memory::Device, tally);
  vertexLobe_ = vk::Buffer(ctx, reflections_ ? shownIrradiance_.size() : 16, Memory::Device, tally);
  shownSurfels_ =
      vk::Buffer(ctx, reflections_ || viewGuided_ ? std::max<size_t>(surfelCount_, 1) * sizeof(uint32_t) : 16,
                 Memory::Device, tally);
  if (viewGuided_) solver_->useView(shownSurfels_, view_);
  noDirectLight_ = vk::Buffer(ctx, 16, Memory::Device, tally);
  if (directLight) {
    validate(*directLight);
    if (somethingLights(g, *directLight))
      direct_.emplace(ctx, g, emitterSamples(g, directLight->samples), movingInstances, *directLight, tally);
  }
  if (direct_ && solver_ &&
      !solver_->useDirectLight(direct_->surfelDirect(), direct_->surfelArrival(), direct_->lightsEnvironment()))
    throw SettingsError("this method cannot take the direct light from depth maps (iv and ar can)");
}

FrameRenderer::~FrameRenderer() {
  if (programTimer_ && ctx_.dispatchTimer() == &*programTimer_) ctx_.timeDispatches(nullptr);  // a frame cut short
}

void FrameRenderer::timePrograms() {
  constexpr uint32_t kMostDispatches = 16384;  // a frame's; any past them go untimed
  if (!programTimer_) programTimer_.emplace(ctx_, kMostDispatches);
}

uint64_t FrameRenderer::bytesAllocated() const {
  return allocations_.bytes() + (solver_ ? solver_->allocatedBytes() : 0);
}

vk::Bindings FrameRenderer::pool() const {
  return vk::Bindings::pool({{"vertices", vertices_},
                             {"instances", instances_},
                             {"morphDeltas", morphDeltas_},
                             {"triangles", triangles_},
                             {"uvs", uvs_},
                             {"colors", colors_},
                             {"materials", materials_},
                             {"textures", textures_},
                             {"texels", texels_},
                             {"surfelSources", surfelSources_},
                             {"surfelVertices", surfelVertices_},
                             {"surfelTriangles", surfelTriangles_},
                             {"surfelCoverage", surfelCoverage_},
                             {"vertexSurfel", vertexSurfel_},
                             {"movingVertices", movingVertices_},
                             {"movingSurfels", movingSurfels_},
                             {"matrices", matrices_},
                             {"morphWeights", morphWeights_},
                             {"world", world_},
                             {"surfels", surfels_},
                             {"visibility", visibility_},
                             {"surfelIrradiance", solver_ ? solver_->irradiance() : unlitIrradiance_},
                             // Without a solver nothing carries light to the vertices: never read.
                             {"surfelBuried", solver_ ? solver_->surfelBuried() : unlitIrradiance_},
                             {"vertexIrradiance", shownIrradiance_},
                             {"radiance", radiance_},
                             {"albedo", albedo_},
                             {"normalDepth", normalDepth_},
                             {"emission", emission_},
                             {"roughnessMetallic", roughnessMetallic_},
                             {"specularAlbedo", specularAlbedo_},
                             {"pixelSpecular", pixelSpecular_},
                             {"pixelTurn", pixelTurn_},
                             {"pixelLights", pixelLights_},
                             {"vertexUnshadowed", vertexUnshadowed_},
                             {"vertexLobe", vertexLobe_},
                             {"shownSurfels", shownSurfels_}})
      .plus(direct_ ? direct_->pool()
                    : vk::Bindings::pool({{"lightPoints", noDirectLight_},
                                          {"lightViews", noDirectLight_},
                                          {"lightDepth", noDirectLight_},
                                          {"surfelDirect", noDirectLight_},
                                          {"surfelUnshadowed", noDirectLight_}}));
}

bool FrameRenderer::recordFrame(VkCommandBuffer cmd, const gpu::Camera& camera, bool geometryMoved, bool redo) {
  const glm::uvec2 fine = glm::uvec2(image_.width, image_.height) * image_.samples;
  const vk::Bindings buffers = pool();
  timer_.reset(cmd, redo);
  if (programTimer_) {  // dispatches are timed from the reset to the frame's results
    programTimer_->reset(cmd, redo);
    ctx_.timeDispatches(&*programTimer_);
  }
  if (geometryMoved || !posed_) {  // else the posed vertices and the surfels stand from the frame before
    // After the first frame, only those of the objects that move.
    auto items = [&](uint32_t all, uint32_t moving) {
      return posed_ ? gpu::ListedPush{.count = moving, .listed = 1u} : gpu::ListedPush{.count = all, .listed = 0u};
    };
    const gpu::ListedPush vertices = items(vertexCount_, movingVertexCount_),
                          surfels = items(surfelCount_, movingSurfelCount_);
    timedPass(cmd, timer_, "animate", [&] { animate_.dispatchItems(cmd, vertices.count, buffers, vertices); });
    timedPass(cmd, timer_, "surfels", [&] { surfelUpdate_.dispatchItems(cmd, surfels.count, buffers, surfels); });
    posed_ = true;
  }
  if (direct_) direct_->record(cmd, timer_, buffers, geometryMoved);
  timedPass(cmd, timer_, "raster", [&] {
    vk::updateBuffer(cmd, view_, 0, sizeof camera, &camera);
    raster_.record(cmd, buffers, view_, 1, fine, visibility_);
  });
  // What the image shows, for the reflections and, where it follows the view, the solve.
  if (reflections_ || (viewGuided_ && solver_->solvesFrame(geometryMoved)))
    timedPass(cmd, timer_, "shown", [&] {
      vk::fillBuffer(cmd, shownSurfels_, 0u);
      const uint32_t samples = fine.x * fine.y;
      markShown_.dispatchItems(cmd, samples, buffers, gpu::CountPush{.count = samples});
      markFit_.dispatchItems(cmd, surfelCount_, buffers, gpu::CountPush{.count = surfelCount_});
    });
  if (solver_) solver_->record(cmd, timer_, surfels_, geometryMoved);
  if (solver_ && solver_->solvePending()) return false;
  recordResolve(cmd, camera);
  return true;
}

void FrameRenderer::recordResolve(VkCommandBuffer cmd, const gpu::Camera& camera) {
  const glm::uvec2 size(image_.width, image_.height);
  const vk::Bindings buffers = pool();
  const gpu::ResolvePush push{.camera = camera,
                              .size = size,
                              .samples = image_.samples,
                              .lightSamples = direct_ ? direct_->sampleCount() : 0u,
                              .shadowMap = direct_ ? direct_->resolution() : 0u,
                              .punctualLights = direct_ ? direct_->punctualCount() : 0u};
  const vk::Groups pixelGroups{(size.x + 7) / 8, (size.y + 7) / 8, 1};
  if (directPerPixel_)
    timedPass(cmd, timer_, "direct pixels", [&] {
      unshadowedToVertices_.dispatchItems(
          cmd, surfelCount_,
          buffers.with({{"surfelIrradiance", direct_->surfelUnshadowed()}, {"vertexIrradiance", vertexUnshadowed_}}),
          gpu::CountPush{.count = surfelCount_});
      directPixels_.dispatch(cmd, pixelGroups, buffers, push);
    });
  if (reflections_) {
    if (reflectEverySurfel_) timedPass(cmd, timer_, "reflections", [&] { vk::fillBuffer(cmd, shownSurfels_, ~0u); });
    solver_->recordReflections(cmd, timer_, gpu::cameraEye(camera), shownSurfels_, surfelLobe_);
    timedPass(cmd, timer_, "reflections", [&] {
      lobesToVertices_.dispatchItems(
          cmd, surfelCount_, buffers.with({{"surfelIrradiance", surfelLobe_}, {"vertexIrradiance", vertexLobe_}}),
          gpu::CountPush{.count = surfelCount_});
    });
  }
  timedPass(cmd, timer_, "resolve", [&] {
    if (solver_) vertexIrradiance_.dispatchItems(cmd, surfelCount_, buffers, gpu::CountPush{.count = surfelCount_});
    resolve_.dispatch(cmd, pixelGroups, buffers, push);
  });
}

FrameResult FrameRenderer::render(const scene::FrameInputs& in, const scene::CameraView& view,
                                  const std::vector<gpu::PunctualLight>& lights, bool geometryMoved, int frame) {
  if (matrices_.size() < in.matrices.size() * sizeof(glm::mat4))
    matrices_ = vk::Buffer(ctx_, in.matrices.size() * sizeof(glm::mat4), vk::Memory::Host, &allocations_);
  matrices_.upload(in.matrices);
  morphWeights_.upload(in.morphWeights);
  if (solver_) solver_->setLights(lights), solver_->setObjectMatrices(in.matrices), solver_->beginFrame(frame);
  const gpu::Camera camera = scene::gpuCamera(view, float(image_.width) / float(image_.height));
  if (direct_) direct_->setFrame(in, lights, camera);
  // A frame the solver could not finish (it ran out of room, its iteration diverged) is redone, and
  // its times are those of all its runs; one whose solver has more to do (its solve after its
  // links, bounces not converged) gets it, and the image is resolved again.
  auto solve = [&](bool moved, bool redo) {
    bool resolved = false;
    ctx_.submitAndWait([&](VkCommandBuffer cmd) { resolved = recordFrame(cmd, camera, moved, redo); });
    bool more = false;
    for (; solver_ && solver_->wantsMorePasses(); more = true)
      ctx_.submitAndWait([&](VkCommandBuffer cmd) { solver_->recordMorePasses(cmd, timer_); });
    return more || !resolved;
  };
  bool resolveAgain = solve(geometryMoved, false);
  while (solver_ && solver_->frameMustBeRedone()) resolveAgain = solve(true, true);
  if (resolveAgain) ctx_.submitAndWait([&](VkCommandBuffer cmd) { recordResolve(cmd, camera); });
  if (solver_) solver_->frameStands();

  FrameResult result;
  result.passTimes = timer_.results();
  if (programTimer_) {
    ctx_.timeDispatches(nullptr);
    result.programTimes = programTimer_->results();
  }
  if (solver_) result.solverFigures = solver_->frameFigures();
  image::FrameChannels& c = result.channels;
  c.width = image_.width, c.height = image_.height;
  const size_t pixels = size_t(image_.width) * image_.height;
  c.radiance = radiance_.read<glm::vec4>(pixels);
  c.albedo = albedo_.read<glm::vec4>(pixels);
  c.normalDepth = normalDepth_.read<glm::vec4>(pixels);
  c.emission = emission_.read<glm::vec4>(pixels);
  c.roughnessMetallic = roughnessMetallic_.read<glm::vec4>(pixels);
  return result;
}

std::vector<scene::WorldVertex> FrameRenderer::worldVertices() const {
  return world_.read<scene::WorldVertex>(vertexCount_);
}
std::vector<uint32_t> FrameRenderer::shownSurfels() const {
  return reflections_ || viewGuided_ ? shownSurfels_.read<uint32_t>(surfelCount_) : std::vector<uint32_t>{};
}
std::vector<scene::Surfel> FrameRenderer::surfels() const { return surfels_.read<scene::Surfel>(surfelCount_); }

}  // namespace ivgi::gi

#pragma once
// Direct light from depth maps (docs/design.md §2.5): points chosen over the emissive triangles by
// power, each with a cube of depth maps rasterized around it every frame, light the surfels (the
// first bounce's source) with their visibility resolved by the maps, not by a solver's bins.
#include <algorithm>
#include <optional>
#include <vector>

#include "engine/gi/raster.h"
#include "engine/scene/environment.h"
#include "engine/scene/geometry.h"
#include "engine/scene/map_meshes.h"
#include "engine/vk/buffer.h"
#include "engine/vk/program.h"
#include "engine/vk/timer.h"

namespace ivgi::gi {

struct DirectLightSettings {
  uint32_t samples = 128;     // points over the emitters
  uint32_t resolution = 128;  // a depth map's side, in texels (a cube of six a sample)
  // Each rigid instance drawn into the maps as simplified as their texels allow (scene::MapMeshes);
  // false: as modelled, for comparison.
  bool simplifiedMeshes = true;
  // The image's pixels look the maps up themselves (the resolve), the vertices carrying only the
  // rest of the irradiance; else the surfels' direct light is shown through their vertices.
  bool perPixel = false;
  // The scene's punctual lights, which the maps light too (each frame says where they are:
  // DirectLight::setFrame); not a choice but how many the frames bring.
  uint32_t punctualLights = 0;
  // The environment's light through the maps too: `environmentDirections` directions toward the
  // sky (Environment::sampleDirections), each a directional light with its own map over the scene,
  // sharing the pixels' interleaving with the emitter samples. None: the solver's bins carry it.
  std::optional<scene::Environment> environment;
  uint32_t environmentDirections = 0;

  // The directions the maps light the environment from (empty where it goes through the bins).
  std::vector<gpu::PunctualLight> environmentLights() const;
};
// Throws SettingsError for settings no frame can use (and the DirectLight for maps the device
// cannot hold).
void validate(const DirectLightSettings& settings);

// `count` points over the emissive triangles of `geometry`, chosen by power (area at rest × the
// emission's luminance, its texture's included: scene::emissionCells), stratified: the i-th takes
// the cell where the power's running sum crosses (i + ½)/count, and its place in the cell from
// where in the cell's share that falls and from a second, golden-ratio sequence; each glows with
// the emission where it lies. Empty where nothing emits.
std::vector<gpu::EmitterSample> emitterSamples(const scene::Geometry& geometry, uint32_t count);
// Whether some triangle emits (emitterSamples would give points), found without placing any.
bool emits(const scene::Geometry& geometry);

// The share of the surface's area (at rest) that emits. The maps suit emitters that are a small
// part of the scene (kMapsEmitterShare): a point sample stands for its share of the emitters' area
// and lights a receiver nearer than that share's size too little, so emitters that surround the
// receivers (a furnace, every wall emitting) are better left to the solver's own hierarchy, which
// takes their near field exactly.
double emissiveAreaShare(const scene::Geometry& geometry);
constexpr double kMapsEmitterShare = 0.1;
// The share of the scene's light that its emissive triangles give, by power at rest: π·L·A each
// (their luminance, textures included), against 4π·I for a point light, 2π(1 − cos θ_outer)·I
// for a spot and E·πr² for a directional light over the scene's bounding sphere (radius r). Where
// emitters that surround the receivers give no more than kBinsEmitterPower of it, the maps' shortfall
// near them moves the image by a small fraction of what the punctual lights' shadows gain at the
// pixels, and the maps stay the default.
double emitterPowerShare(const scene::Scene& scene, const scene::Geometry& geometry);
constexpr double kBinsEmitterPower = 0.1;

class DirectLight {
 public:
  // `samples` from emitterSamples(geometry), at least one unless `settings` names punctual lights
  // or the environment; `moving`: per instance of `geometry`, whether the animation can move it
  // (scene::movingInstances; empty: any may).
  DirectLight(const vk::Context& ctx, const scene::Geometry& geometry, std::vector<gpu::EmitterSample> samples,
              const std::vector<bool>& moving, const DirectLightSettings& settings, vk::Allocations* tally);

  // The frame: its pose (where the emitter samples and the instances are), its punctual lights in
  // world space (as many as the settings named), lit through the maps, and the camera (where the
  // pixels look a directional light's maps up, its cascades lie around it). Each instance is drawn
  // into the maps as simplified as the nearest light point's texels allow (chooseMeshes).
  void setFrame(const scene::FrameInputs& pose, const std::vector<gpu::PunctualLight>& lights,
                const gpu::Camera& camera);

  // Places the samples, rasterizes their depth maps and lights the surfels; `frame` holds the
  // frame's buffers (world, triangles, materials, surfels). Where the emitters cannot move, what
  // cannot move is rasterized once and each frame adds the moving triangles over it; where
  // nothing moved since the last frame (`geometryMoved` false), nothing is redone but a sun's
  // cascades where they followed the camera.
  void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Bindings& frame, bool geometryMoved);

  // Per surfel, its direct irradiance (rgb), after record(); and the same with every emitter sample
  // and environment direction seen (no shadows).
  const vk::Buffer& surfelDirect() const { return surfelDirect_; }
  const vk::Buffer& surfelUnshadowed() const { return surfelUnshadowed_; }
  // Where some lobe sends by direction (Geometry::directionalLobes), per surfel: the
  // luminance-weighted mean direction its direct light arrives from
  // (shaders/frame/direct_surfels.comp); else one element.
  const vk::Buffer& surfelArrival() const { return surfelArrival_; }
  // The points the pixels share out: the emitter samples, then the environment's directions.
  uint32_t sampleCount() const { return sampleCount_ + environmentCount_; }
  // How many of those each surfel's lookups stand for (DirectLightPush::surfelStride): where the
  // pixels look the maps up, about kSurfelMapPoints looked up; else every point.
  uint32_t surfelStride() const {
    return settings_.perPixel ? std::max(1u, sampleCount() / gpu::kSurfelMapPoints) : 1u;
  }
  bool lightsEnvironment() const { return environmentCount_ > 0; }
  uint32_t punctualCount() const { return settings_.punctualLights; }
  uint32_t resolution() const { return settings_.resolution; }
  // The triangles the maps were last drawn from, of those of the scene they stand for.
  std::pair<size_t, size_t> trianglesDrawn() const;
  // Of the maps' views, those the moving triangles were last drawn into (read back; none where
  // nothing moves), and how many the maps hold.
  std::pair<uint32_t, uint32_t> movingViewsDrawn() const;
  // How many surfels the last frame that drew the maps lit again (read back): every one, or where only
  // moving objects were drawn again, those whose light they can have changed.
  uint32_t surfelsLit() const;
  // The depth maps, view after view (resolution² floats each).
  const vk::Buffer& depthMaps() const { return depth_; }
  // The samples as the frame placed them, their views and depth maps, the surfels' direct light, by
  // the names the shaders that look them up bind them under (direct_light.glsl).
  vk::Bindings pool() const {
    return vk::Bindings::pool({{"lightPoints", points_},
                               {"lightViews", views_},
                               {"lightDepth", depth_},
                               {"surfelDirect", surfelDirect_},
                               {"surfelUnshadowed", surfelUnshadowed_},
                               {"surfelArrival", surfelArrival_}});
  }

 private:
  // The views of the directional lights (the environment's directions, the punctual ones): each
  // range's first view and how many.
  std::vector<std::pair<uint64_t, uint64_t>> directionalViewRanges() const;

  // Draws each part of the layers as simplified as the maps allow at the frame's `matrices`, and
  // places a directional light's cascades around `camera`.
  void chooseMeshes(const std::vector<glm::mat4>& matrices, const gpu::Camera& camera);
  // The spheres around the maps' origins and the moving objects (lightsSphere_, movingSphere_), from
  // the cubes' `origins` and the moving parts' spheres as placed (none of either: unknown); `widest`,
  // the largest part's radius.
  void placeChanges(const std::vector<glm::dvec3>& origins, const std::vector<glm::dvec4>& movingParts, double widest);
  // Makes the maps (`depth_`) the still ones (`staticDepth_`) again before the moving triangles are
  // drawn over them: all of them where `stillDrawn` (drawn again this frame), else the views the
  // moving triangles were drawn into last.
  void restoreStill(VkCommandBuffer cmd, bool stillDrawn);

  // The triangles one raster draws into the maps: its instances' meshes, the triangles drawn of them
  // (chosen each frame), and the buffer that holds those.
  struct Layer {
    Layer(const vk::Context& ctx, scene::MapMeshes meshes, uint32_t viewCount, vk::Allocations* tally,
          bool viewsOnHost = false);
    // Draws each part within `errors` (MapMeshes::draw); true where that changed the triangles.
    bool choose(const std::vector<float>& errors);
    void record(VkCommandBuffer cmd, const vk::Bindings& frame, const vk::Buffer& views, uint32_t viewCount,
                glm::uvec2 size, const vk::Buffer& target, bool clear = true, uint32_t firstView = 0) const;

    scene::MapMeshes meshes;
    std::vector<scene::Triangle> drawn;
    vk::Buffer triangles;
    Raster raster;
  };

  DirectLightSettings settings_;
  std::vector<gpu::PunctualLight> environment_;  // settings_.environmentLights(), sampled once
  uint32_t sampleCount_, environmentCount_, viewCount_, surfelCount_, vertexCount_;
  // Some light is directional (a punctual one or the environment's): its map covers the scene's bounds.
  bool directional_ = false;
  // The maps are drawn from all the triangles (`all_`), or where the emitters stand still from those
  // that can move (`moving_`) each frame over those that cannot (`still_`, into `staticDepth`,
  // drawn again only where their lights or their triangles change).
  bool splitsStatic_ = false, staticDrawn_ = false, lit_ = false;
  // On a CPU device, where copying the maps is a memcpy of every one on the host, only the views
  // the moving triangles were drawn into are made still again (restoreStill); `movingDrawn_`: they
  // were drawn into `depth_` over the still maps, and the raster's list says where.
  bool restoreViews_ = false, movingDrawn_ = false;
  // The punctual lights of the last frame (host-visible), and whether they moved since the
  // maps were drawn.
  std::vector<gpu::PunctualLight> lights_;
  bool lightsMoved_ = true;
  // Where the pixels look a directional punctual light up: the spheres its cascades cover, nested
  // around the camera, finest first (none without one, or where the pixels do not look the maps up).
  std::vector<glm::vec4> cascades_;
  bool cascadesMoved_ = false;  // since the maps were drawn
  // Spheres around the maps' origins and around the moving objects in this frame and where the
  // maps last drew them (none where the host cannot place them: a bending emitter or object, or a
  // directional light), which bound the surfels whose light a frame must find again.
  std::optional<glm::vec4> lightsSphere_, movingSphere_, drawnSphere_;
  // The surfels lit by the last frame that drew the maps: none (a sun's cascades alone were drawn),
  // all (`surfelsLit_` unused) or those counted.
  bool surfelsRelit_ = false, litChangedOnly_ = false;
  // Per emitter sample, its instance and its place in its primitive's space (the pose places it).
  std::vector<std::pair<uint32_t, glm::vec3>> samplePlaces_;
  std::vector<gpu::Instance> instances_;
  vk::Buffer samples_, points_, views_, depth_, staticDepth_, surfelDirect_, surfelUnshadowed_, surfelArrival_,
      surfelsLit_;
  // The lights drawn with a cube or one map: the environment's directions, then the frame's lights.
  vk::Buffer punctual_;
  vk::Buffer sceneBounds_;  // the scene's bounds in the frame (world_bounds), for directional lights
  vk::Program lightViews_, directSurfels_, worldBounds_;
  std::optional<Layer> all_, still_, moving_;
};

}  // namespace ivgi::gi

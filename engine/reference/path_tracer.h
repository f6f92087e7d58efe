#pragma once
// The reference (docs/design.md §2.3): an Embree CPU path tracer over the same world-space triangles,
// materials, lights and camera as the GPU methods. glTF's metallic-roughness BRDF
// (shaders/interface/brdf.h; surfaces reflect on both sides), emitters radiating from their front side, next-event
// estimation on emissive triangles and punctual lights combined with BSDF sampling by multiple importance sampling,
// environment light, Russian roulette. Each pixel's samples come from its own seeded stream, so the image does not
// depend on the thread count.
#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "engine/image/frame_image.h"
#include "engine/scene/camera.h"
#include "engine/scene/environment.h"
#include "engine/scene/geometry.h"
#include "shaders/interface.h"

namespace ivgi::reference {

struct PathSettings {
  uint32_t spp = 64;     // samples per pixel, spread uniformly over the pixel (box filter)
  int bounces = -1;      // indirect bounces, as iv counts them (0: direct light only); -1: until roulette ends the path
  uint32_t seed = 0;     // a different seed gives independent noise
  unsigned threads = 0;  // 0: every core
};

// Throws SettingsError naming the option when a setting is out of its range.
void validate(const PathSettings& settings);

// One frame's world: the triangles after animation, the punctual lights, the environment.
struct PathScene {
  const scene::Geometry* geometry = nullptr;
  std::vector<scene::WorldVertex> world;
  std::vector<gpu::PunctualLight> lights;
  std::optional<scene::Environment> environment;

  // The scene at `pose`: the host twin of the animate pass poses the triangles.
  static PathScene at(const scene::Scene& scene, const scene::Geometry& geometry, const scene::Pose& pose,
                      std::optional<scene::Environment> environment = std::nullopt);
};

class PathTracer {
 public:
  explicit PathTracer(PathScene scene);
  ~PathTracer();
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  // The frame as the rasteriser frames it (same camera, same pixel convention), every channel of
  // FrameChannels filled. `frame` enters the seeds. `rowsDone` (if given) counts finished rows for a
  // progress display.
  image::FrameChannels render(const scene::CameraView& view, uint32_t width, uint32_t height, uint32_t frame,
                              const PathSettings& settings, std::atomic<uint32_t>* rowsDone = nullptr) const;

  // Irradiance at point p with normal n (one-sided), estimated with `samples` paths: what the
  // analytic tests check the light transport against.
  glm::vec3 irradiance(glm::vec3 p, glm::vec3 n, uint32_t samples, const PathSettings& settings) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ivgi::reference

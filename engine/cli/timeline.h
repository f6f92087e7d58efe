#pragma once
// Which animation plays and how frame numbers map to its time.
#include <string>
#include <vector>

#include "engine/scene/camera.h"
#include "engine/scene/geometry.h"
#include "engine/scene/scene.h"

namespace ivgi::cli {

struct Timeline {
  int animation = -1;  // -1: static scene
  double start = 0.0;
  int lastFrame = 0;
  double time(int frame, double fps) const { return start + frame / fps; }
};

// The animation named by `choice` (name, index, "none"; empty: the first), at `fps` (checked:
// SettingsError).
Timeline timeline(const scene::Scene& scene, const std::string& choice, double fps);

// The view of each frame: the named camera (empty: the scene's first), or for a scene without one, a
// camera framing the union of the scene's bounds over (up to 16 of) `frames`.
class FrameCamera {
 public:
  FrameCamera(const scene::Scene& scene, const scene::Geometry& geometry, const Timeline& timeline, double fps,
              const std::string& camera, const std::vector<int>& frames, float aspect);
  scene::CameraView at(const scene::Pose& pose) const;
  std::string name() const;

 private:
  const scene::Scene& scene_;
  int node_ = -1;
  scene::CameraView framing_;
};

}  // namespace ivgi::cli

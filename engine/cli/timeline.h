#pragma once
// Which animation plays and how frame numbers map to its time.
#include <string>

#include "engine/scene/scene.h"

namespace ivgi::cli {

struct Timeline {
  int animation = -1;  // -1: static scene
  double start = 0.0;
  int lastFrame = 0;
  double time(int frame, double fps) const { return start + frame / fps; }
};

// The animation named by `choice` (name, index, "none"; empty: the first), at `fps`.
Timeline timeline(const scene::Scene& scene, const std::string& choice, double fps);

}  // namespace ivgi::cli

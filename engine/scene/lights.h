#pragma once
// The scene's punctual lights (KHR_lights_punctual) in world space at a pose, as both the GPU
// solvers and the path tracer read them; gpu::lightFalloff() gives their irradiance.
#include <vector>

#include "engine/scene/animation.h"
#include "engine/scene/scene.h"
#include "shaders/interface.h"

namespace ivgi::scene {

std::vector<gpu::PunctualLight> worldLights(const Scene& scene, const Pose& pose);
// How many there are (every pose has as many).
uint32_t punctualLightCount(const Scene& scene);

}  // namespace ivgi::scene

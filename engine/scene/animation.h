#pragma once
// glTF animation on the host: sampling keyframes (STEP, LINEAR with slerp, CUBICSPLINE), the pose of
// every node at time t, and world matrices. The per-vertex work runs on the GPU (gi/animate).
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <vector>

#include "engine/scene/scene.h"

namespace ivgi::scene {

// Spherical interpolation along the shorter arc, as the glTF spec defines it.
glm::quat slerp(glm::quat a, glm::quat b, float t);

// Value of `sampler` at time t (clamped to its key range), `components` floats into `out`.
void sampleAt(const Sampler& sampler, float t, bool isRotation, float* out);

struct Pose {
  std::vector<glm::vec3> translation, scale;
  std::vector<glm::quat> rotation;
  std::vector<std::vector<float>> weights;  // morph weights per node (empty when it has no morph targets)
  std::vector<glm::mat4> world;             // node to world
};

// Pose of all nodes at time t of `animation` (-1: rest pose).
Pose evaluatePose(const Scene& scene, int animation, float t);

// Whether `animation` moves any geometry or light (a mesh, light or joint node or one above it, or
// morph weights); false when it animates only cameras, or for -1.
bool animationMovesGeometry(const Scene& scene, int animation);
// Whether the animation moves any of the scene's cameras (a channel on one or on a node above it).
bool animationMovesCameras(const Scene& scene, int animation);

glm::mat4 localMatrix(const Node& node, glm::vec3 t, glm::quat r, glm::vec3 s);

}  // namespace ivgi::scene

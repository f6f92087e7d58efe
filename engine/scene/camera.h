#pragma once
// The view a frame is rendered from: a glTF camera (perspective or orthographic) at time t, or, for
// a scene without one, a default camera that frames the scene's bounds.
#include <glm/glm.hpp>

#include "engine/scene/animation.h"
#include "engine/scene/geometry.h"
#include "shaders/interface.h"

namespace ivgi::scene {

struct CameraView {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f}, right{1.0f, 0.0f, 0.0f}, up{0.0f, 1.0f, 0.0f};  // orthonormal
  float yfov = 0.7853982f;
  float znear = 0.01f, zfar = 0.0f;  // zfar 0: none
  bool orthographic = false;         // rays along forward from a plane, ymag its half height
  float ymag = 1.0f;
};

// View of the camera on `cameraNode` in `pose` (its node's scale is ignored, as glTF asks).
CameraView cameraView(const Scene& scene, const Pose& pose, int cameraNode);

// The view as the shaders take it, for an image of the given aspect (width / height).
gpu::Camera gpuCamera(const CameraView& view, float aspect);

// A 45° camera on the +Z side looking down -Z at the centre of `bounds`, far enough back to see the
// whole box at the given image aspect (width / height).
CameraView framingCamera(const Bounds& bounds, float aspect);

}  // namespace ivgi::scene

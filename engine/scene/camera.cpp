#include "engine/scene/camera.h"

#include <algorithm>
#include <cmath>

namespace ivgi::scene {

CameraView cameraView(const Scene& scene, const Pose& pose, int cameraNode) {
  const Camera& cam = scene.cameras[scene.nodes[cameraNode].camera];
  const glm::mat4& m = pose.world[cameraNode];
  CameraView v;
  v.origin = glm::vec3(m[3]);
  auto axis = [](glm::vec3 a, glm::vec3 fallback) {
    float len = glm::length(a);
    return len > 0.0f ? a / len : fallback;
  };
  v.forward = axis(-glm::vec3(m[2]), {0, 0, -1});
  v.up = axis(glm::vec3(m[1]) - glm::dot(glm::vec3(m[1]), v.forward) * v.forward, {0, 1, 0});
  v.right = glm::cross(v.forward, v.up);
  v.yfov = cam.yfov;
  v.znear = cam.znear;
  v.zfar = cam.zfar;
  return v;
}

gpu::Camera gpuCamera(const CameraView& v, float aspect) {
  float ty = std::tan(0.5f * v.yfov), tx = ty * aspect;
  return {glm::vec4(v.origin, v.znear), glm::vec4(v.right * tx, 0.0f), glm::vec4(v.up * ty, 0.0f),
          glm::vec4(v.forward, v.zfar)};
}

CameraView framingCamera(const Bounds& bounds, float aspect) {
  CameraView v;
  glm::vec3 centre = bounds.empty() ? glm::vec3(0) : 0.5f * (bounds.min + bounds.max);
  float radius = bounds.empty() ? 1.0f : std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-6f);
  float halfY = 0.5f * v.yfov, halfX = std::atan(std::tan(halfY) * aspect);
  float distance = radius / std::sin(std::min(halfX, halfY)) * 1.05f;
  v.origin = centre + glm::vec3(0.0f, 0.0f, distance);
  v.znear = std::max(distance - radius * 1.5f, distance * 1e-3f);
  v.zfar = 0.0f;
  return v;
}

}  // namespace ivgi::scene

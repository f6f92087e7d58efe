#include "engine/scene/camera.h"

#include <algorithm>
#include <cmath>

namespace ivgi::scene {

CameraView cameraView(const Scene& scene, const Pose& pose, int cameraNode) {
  const Camera& cam = scene.cameras[scene.nodes[cameraNode].camera];
  const glm::mat4& m = pose.world[cameraNode];
  CameraView v;
  v.origin = glm::vec3(m[3]);
  // The node's transform may scale the camera uniformly (its axes are normalised) but must leave it
  // a view direction and an up direction apart from it.
  const glm::vec3 back = glm::vec3(m[2]), up = glm::vec3(m[1]);
  const float backLength = glm::length(back);
  const glm::vec3 upAcross = backLength > 0.0f ? up - glm::dot(up, back) / (backLength * backLength) * back : up;
  if (!(backLength > 0.0f) || !(glm::length(upAcross) > 1e-6f * glm::length(up)) || !std::isfinite(backLength) ||
      !std::isfinite(glm::length(v.origin)))
    throw LoadError(scene.source + ": camera '" + (cam.name.empty() ? scene.nodes[cameraNode].name : cam.name) +
                    "' is degenerate: its node's transform leaves it no view or no up direction (a zero scale?)");
  v.forward = -back / backLength;
  v.up = upAcross / glm::length(upAcross);
  v.right = glm::cross(v.forward, v.up);
  v.yfov = cam.yfov;
  v.znear = cam.znear;
  v.zfar = cam.zfar;
  v.orthographic = cam.orthographic;
  v.ymag = cam.ymag;
  return v;
}

gpu::Camera gpuCamera(const CameraView& v, float aspect) {
  // Perspective: the image plane's half extents at unit distance; orthographic: the view's own.
  float ty = v.orthographic ? v.ymag : std::tan(0.5f * v.yfov), tx = ty * aspect;
  return {glm::vec4(v.origin, v.znear), glm::vec4(v.right * tx, 0.0f),
          glm::vec4(v.up * ty, v.orthographic ? gpu::kOrthographic : 0.0f), glm::vec4(v.forward, v.zfar)};
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

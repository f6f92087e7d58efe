#include "engine/scene/animation.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>

namespace ivgi::scene {

glm::quat slerp(glm::quat a, glm::quat b, float t) {
  float d = glm::dot(a, b);
  if (d < 0.0f) b = -b, d = -d;
  if (d > 0.9995f) return glm::normalize(a * (1.0f - t) + b * t);  // nearly parallel: lerp is exact enough
  float theta = std::acos(std::min(d, 1.0f));
  float s = std::sin(theta);
  return a * (std::sin((1.0f - t) * theta) / s) + b * (std::sin(t * theta) / s);
}

void sampleAt(const Sampler& sm, float t, bool isRotation, float* out) {
  const int n = sm.components;
  const size_t keys = sm.input.size();
  const bool cubic = sm.interpolation == Interpolation::CubicSpline;
  // Value (not tangent) of key k, component c.
  auto value = [&](size_t k, int c) { return sm.output[(cubic ? 3 * k + 1 : k) * n + c]; };
  auto emit = [&](auto fn) {
    for (int c = 0; c < n; ++c) out[c] = fn(c);
  };
  if (keys == 1 || t <= sm.input.front()) return emit([&](int c) { return value(0, c); });
  if (t >= sm.input.back()) return emit([&](int c) { return value(keys - 1, c); });
  size_t k = size_t(std::upper_bound(sm.input.begin(), sm.input.end(), t) - sm.input.begin()) - 1;
  float t0 = sm.input[k], t1 = sm.input[k + 1], dt = t1 - t0, u = (t - t0) / dt;
  switch (sm.interpolation) {
    case Interpolation::Step: return emit([&](int c) { return value(k, c); });
    case Interpolation::Linear:
      if (isRotation) {
        glm::quat a(value(k, 3), value(k, 0), value(k, 1), value(k, 2)),
            b(value(k + 1, 3), value(k + 1, 0), value(k + 1, 1), value(k + 1, 2));
        glm::quat q = slerp(a, b, u);
        out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
        return;
      }
      return emit([&](int c) { return value(k, c) * (1 - u) + value(k + 1, c) * u; });
    case Interpolation::CubicSpline: {
      // Hermite spline of the glTF spec: out-tangent of key k and in-tangent of key k+1, scaled by dt.
      float u2 = u * u, u3 = u2 * u;
      emit([&](int c) {
        float outTangent = sm.output[(3 * k + 2) * n + c], inTangent = sm.output[(3 * (k + 1)) * n + c];
        return (2 * u3 - 3 * u2 + 1) * value(k, c) + (u3 - 2 * u2 + u) * dt * outTangent +
               (-2 * u3 + 3 * u2) * value(k + 1, c) + (u3 - u2) * dt * inTangent;
      });
      if (isRotation) {
        glm::vec4 q(out[0], out[1], out[2], out[3]);
        float len = glm::length(q);
        if (len > 0)
          for (int c = 0; c < 4; ++c) out[c] /= len;
      }
      return;
    }
  }
}

glm::mat4 localMatrix(const Node& node, glm::vec3 t, glm::quat r, glm::vec3 s) {
  if (node.matrix) return *node.matrix;
  return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), s);
}

bool animationMovesGeometry(const Scene& scene, int animation) {
  if (animation < 0) return false;
  std::vector<char> carries(scene.nodes.size(), 0);  // node or a descendant carries geometry or a light
  for (const auto& skin : scene.skins)
    for (int j : skin.joints) carries[j] = 1;
  std::function<bool(int)> visit = [&](int n) {
    bool any = scene.nodes[n].mesh >= 0 || scene.nodes[n].light >= 0 || carries[n];
    for (int c : scene.nodes[n].children) any = visit(c) || any;
    carries[n] = any;
    return any;
  };
  for (size_t i = 0; i < scene.nodes.size(); ++i)
    if (scene.nodes[i].parent < 0) visit(int(i));
  for (const Channel& ch : scene.animations[animation].channels)
    if (ch.path == Path::Weights || carries[ch.node]) return true;
  return false;
}

bool animationMovesCameras(const Scene& scene, int animation) {
  if (animation < 0) return false;
  std::vector<char> moved(scene.nodes.size(), 0);
  for (const Channel& ch : scene.animations[animation].channels)
    if (ch.path != Path::Weights) moved[ch.node] = 1;
  for (int camera : scene.cameraNodes())
    for (int n = camera; n >= 0; n = scene.nodes[n].parent)
      if (moved[n]) return true;
  return false;
}

Pose evaluatePose(const Scene& scene, int animation, float t) {
  Pose pose;
  size_t n = scene.nodes.size();
  pose.translation.resize(n), pose.rotation.resize(n), pose.scale.resize(n), pose.weights.resize(n),
      pose.world.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Node& node = scene.nodes[i];
    pose.translation[i] = node.translation, pose.rotation[i] = node.rotation, pose.scale[i] = node.scale;
    if (node.mesh >= 0) {
      const Mesh& mesh = scene.meshes[node.mesh];
      size_t targets = 0;
      for (const auto& p : mesh.primitives) targets = std::max(targets, p.targets.size());
      auto& w = pose.weights[i];
      w.assign(targets, 0.0f);
      const auto& given = !node.weights.empty() ? node.weights : mesh.weights;
      for (size_t k = 0; k < std::min(targets, given.size()); ++k) w[k] = given[k];
    }
  }
  if (animation >= 0) {
    const Animation& a = scene.animations[animation];
    float buffer[64];
    std::vector<float> wide;
    for (const Channel& ch : a.channels) {
      const Sampler& sm = a.samplers[ch.sampler];
      float* out = sm.components <= 64 ? buffer : (wide.resize(sm.components), wide.data());
      sampleAt(sm, t, ch.path == Path::Rotation, out);
      switch (ch.path) {
        case Path::Translation: pose.translation[ch.node] = {out[0], out[1], out[2]}; break;
        case Path::Scale: pose.scale[ch.node] = {out[0], out[1], out[2]}; break;
        case Path::Rotation: pose.rotation[ch.node] = glm::normalize(glm::quat(out[3], out[0], out[1], out[2])); break;
        case Path::Weights: {
          auto& w = pose.weights[ch.node];
          for (size_t k = 0; k < std::min(w.size(), size_t(sm.components)); ++k) w[k] = out[k];
          break;
        }
      }
    }
  }
  std::function<void(int, const glm::mat4&)> visit = [&](int i, const glm::mat4& parent) {
    pose.world[i] = parent * localMatrix(scene.nodes[i], pose.translation[i], pose.rotation[i], pose.scale[i]);
    for (int c : scene.nodes[i].children) visit(c, pose.world[i]);
  };
  // Every node gets a matrix, also those outside the default scene (joints may live there).
  for (size_t i = 0; i < n; ++i)
    if (scene.nodes[i].parent < 0) visit(int(i), glm::mat4(1.0f));
  return pose;
}

}  // namespace ivgi::scene

#pragma once
// Host twins of the definitions in shaders/common.glsl that are not plain data layouts.
#include <glm/glm.hpp>

#include <bit>
#include <cstdint>

#include "engine/scene/camera.h"

namespace ivgi::gi {

constexpr uint64_t kEmptyVisibility = ~0ull;

inline uint64_t packDepthKey(float depth, uint32_t id) { return uint64_t(std::bit_cast<uint32_t>(depth)) << 32 | id; }
inline uint32_t keyId(uint64_t key) { return uint32_t(key & 0xFFFFFFFFu); }
inline float keyDepth(uint64_t key) { return std::bit_cast<float>(uint32_t(key >> 32)); }

// std430 / push-constant layout of `Camera` in common.glsl.
struct GpuCamera {
  glm::vec4 origin;   // w: znear
  glm::vec4 right;    // scaled by tan(half horizontal fov)
  glm::vec4 up;       // scaled by tan(half vertical fov)
  glm::vec4 forward;  // w: zfar (0: none)
};

inline GpuCamera gpuCamera(const scene::CameraView& v, float aspect) {
  float ty = std::tan(0.5f * v.yfov), tx = ty * aspect;
  return {glm::vec4(v.origin, v.znear), glm::vec4(v.right * tx, 0.0f), glm::vec4(v.up * ty, 0.0f), glm::vec4(v.forward, v.zfar)};
}

// Direction of the camera ray through sample position `s` of an image `size` samples large.
inline glm::vec3 cameraRay(const GpuCamera& c, glm::vec2 s, glm::uvec2 size) {
  glm::vec2 ndc(2.0f * s.x / float(size.x) - 1.0f, 1.0f - 2.0f * s.y / float(size.y));
  return glm::vec3(c.forward) + ndc.x * glm::vec3(c.right) + ndc.y * glm::vec3(c.up);
}

}  // namespace ivgi::gi

// shaders/common.glsl and its C++ twins (engine/gi/shared.h, engine/scene/texture_sampling.h) give
// the same answers on the same cases: key packing and ordering, texel addressing, camera rays.
#include <gtest/gtest.h>

#include <algorithm>
#include <span>

#include "engine/gi/shared.h"
#include "engine/scene/texture_sampling.h"
#include "engine/vk/program.h"
#include "tests/test_support.h"

namespace ivgi {
std::span<const uint32_t> testShaderCode(const std::string& name);
}

using namespace ivgi;

namespace {

struct Case {
  float value;
  uint32_t id, size, mode;
};

struct Push {
  gi::GpuCamera camera;
  glm::uvec2 size;
  uint32_t count, pad = 0;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  const float values[] = {0.0f, 1e-30f, 1e-6f, 0.25f, 0.5f, 0.999999f, 1.0f, 1.5f, 2.75f, -0.25f, -3.6f, 1e6f, 123.456f, 7.0f};
  const uint32_t modes[] = {10497u, 33071u, 33648u};
  const uint32_t sizes[] = {1u, 2u, 7u, 64u};
  uint32_t id = 0;
  for (float v : values)
    for (uint32_t m : modes)
      for (uint32_t s : sizes) out.push_back({v, id++ * 2654435761u, s, m});
  return out;
}

}  // namespace

TEST(SharedDefinitions, GlslAndCppAgree) {
  auto& ctx = test::gpu();
  auto cs = cases();
  vk::Program program(ctx, "common_cases", testShaderCode("common_cases"));
  vk::Buffer in = vk::makeBuffer(ctx, cs);
  vk::Buffer keys(ctx, cs.size() * 8, vk::Memory::Host), pairs(ctx, cs.size() * 16, vk::Memory::Host), rays(ctx, cs.size() * 16, vk::Memory::Host);
  scene::CameraView view;
  view.origin = {1, 2, 3};
  view.forward = glm::normalize(glm::vec3(0.2f, -0.1f, -1.0f));
  view.right = glm::normalize(glm::cross(view.forward, glm::vec3(0, 1, 0)));
  view.up = glm::cross(view.right, view.forward);
  view.yfov = 0.6f;
  Push push{gi::gpuCamera(view, 1.5f), {48, 32}, uint32_t(cs.size())};
  ctx.submitAndWait([&](VkCommandBuffer cmd) { program.dispatchItems(cmd, cs.size(), {&in, &keys, &pairs, &rays}, push); });
  auto gotKeys = keys.read<uint64_t>(cs.size());
  auto gotPairs = pairs.read<glm::vec4>(cs.size());
  auto gotRays = rays.read<glm::vec4>(cs.size());

  for (size_t i = 0; i < cs.size(); ++i) {
    const Case& c = cs[i];
    if (c.value >= 0.0f) {  // keys are defined for depths >= 0
      EXPECT_EQ(gotKeys[i], gi::packDepthKey(c.value, c.id)) << i;
      EXPECT_EQ(gotPairs[i].w, 1.0f) << "keyDepth/keyId round trip, case " << i;
    }
    float weight;
    glm::ivec2 pair = scene::texelPair(c.value, int(c.size), c.mode, weight);
    EXPECT_EQ(glm::ivec2(gotPairs[i]), pair) << "u " << c.value << " size " << c.size << " mode " << c.mode;
    EXPECT_NEAR(gotPairs[i].z, weight, 1e-3f) << "u " << c.value << " size " << c.size << " mode " << c.mode;
    EXPECT_GE(pair.x, 0);
    EXPECT_LT(pair.y, int(c.size));
    glm::vec3 ray = gi::cameraRay(push.camera, glm::vec2(c.value, float(c.id % 7u)) * float(push.size.x), push.size);
    EXPECT_LT(glm::length(glm::vec3(gotRays[i]) - ray), 1e-4f * std::max(1.0f, glm::length(ray))) << i;
  }
}

TEST(SharedDefinitions, KeysOrderByDepthThenId) {
  // atomicMin on the key must keep the nearest hit, ties broken by the lower id.
  std::vector<std::pair<float, uint32_t>> hits = {{2.0f, 1}, {0.5f, 9}, {0.5f, 3}, {1e-20f, 7}, {1e20f, 0}, {0.0f, 4}};
  std::vector<uint64_t> keys;
  for (auto [d, id] : hits) keys.push_back(gi::packDepthKey(d, id));
  auto sortedHits = hits;
  std::sort(sortedHits.begin(), sortedHits.end());
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(gi::keyDepth(keys[i]), sortedHits[i].first);
    EXPECT_EQ(gi::keyId(keys[i]), sortedHits[i].second);
  }
  EXPECT_LT(gi::packDepthKey(1e30f, ~0u - 1), gi::kEmptyVisibility) << "any hit beats an empty sample";
}

TEST(SharedDefinitions, TexelPairsFollowTheWrapModes) {
  float w;
  EXPECT_EQ(scene::texelPair(0.0f, 4, 10497u, w), glm::ivec2(3, 0)) << "repeat wraps left of the first texel centre";
  EXPECT_FLOAT_EQ(w, 0.5f);
  EXPECT_EQ(scene::texelPair(0.0f, 4, 33071u, w), glm::ivec2(0, 0)) << "clamp";
  EXPECT_EQ(scene::texelPair(1.25f, 4, 10497u, w), glm::ivec2(0, 1)) << "repeat: 1.25 is 0.25";
  EXPECT_FLOAT_EQ(w, 0.5f);
  EXPECT_EQ(scene::texelPair(1.25f, 4, 33648u, w), glm::ivec2(2, 3)) << "mirrored: 1.25 is 0.75";
  EXPECT_FLOAT_EQ(w, 0.5f);
}

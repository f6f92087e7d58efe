// No result depends on what the device's memory held before: every frame is the same whatever word
// fresh buffers hold (vk::Context::fillFreshMemory), so a pass that reads memory nothing wrote shows
// here at once, not once in hundreds of runs as the driver's recycled memory happens to say.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "engine/cli/commands.h"
#include "engine/gi/frame_renderer.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/builtin.h"
#include "tests/test_support.h"

namespace ivgi {
namespace {

// The radiance of the first two frames of `s`'s first animation (where it has one) by `method` at
// its defaults, as render makes its renderer, every buffer made while it runs holding `word` first.
std::vector<glm::vec4> framesOver(const scene::Scene& s, const std::string& method, uint32_t word) {
  cli::SolverOptions options;
  options.method = method;
  const scene::Geometry g = cli::renderableGeometry(s, options, {});
  options = cli::withSceneLight(options, s, g);
  const int animation = s.animations.empty() ? -1 : 0;
  const test::FreshMemoryFill fill(word);
  std::vector<glm::vec4> radiance;
  {
    gi::FrameRenderer r(test::gpu(), g, {32, 24, 1}, cli::makeSolver(options, test::gpu(), s, g, animation),
                        cli::directLightSettings(options, s, g), scene::movingInstances(s, g, animation));
    for (int frame = 0; frame < 2; ++frame) {
      const scene::Pose pose = scene::evaluatePose(s, animation, 0.25f * float(frame));
      const scene::FrameInputs inputs = g.frameInputs(s, pose);
      const scene::CameraView view =
          s.cameraNodes().empty() ? test::framing(g, inputs) : scene::cameraView(s, pose, s.cameraNodes()[0]);
      const auto frameRadiance = r.render(inputs, view, scene::worldLights(s, pose), true, frame).channels.radiance;
      radiance.insert(radiance.end(), frameRadiance.begin(), frameRadiance.end());
    }
  }
  return radiance;
}

void expectTheSameOverAnyWord(const scene::Scene& s, const std::string& method) {
  // Zero, every bit set, a NaN, and a small number (a valid index of most arrays).
  const std::vector<uint32_t> words = {0u, 0xFFFFFFFFu, 0x7FC00000u, 3u};
  const auto first = framesOver(s, method, words[0]);
  for (size_t k = 1; k < words.size(); ++k) {
    const auto other = framesOver(s, method, words[k]);
    ASSERT_EQ(other.size(), first.size());
    EXPECT_EQ(std::memcmp(other.data(), first.data(), first.size() * sizeof(glm::vec4)), 0)
        << method << ": fresh memory holding " << std::hex << words[k] << " against " << words[0];
  }
}

TEST(FreshMemory, TheAnimatedCornellBoxByIv) {
  expectTheSameOverAnyWord(scene::sceneFromModel(scenes::cornellBox({.cells = 4}), "cornell"), "iv");
}
TEST(FreshMemory, TheAnimatedCornellBoxByAr) {
  expectTheSameOverAnyWord(scene::sceneFromModel(scenes::cornellBox({.cells = 4}), "cornell"), "ar");
}
TEST(FreshMemory, TheGlossyCornellBoxByIv) {
  expectTheSameOverAnyWord(scene::sceneFromModel(scenes::cornellBox({.cells = 4, .glossy = true}), "glossy"), "iv");
}
TEST(FreshMemory, ASunOverABoxByIvAndAr) {
  const scene::Scene s = scene::sceneFromModel(test::sunOverABox(), "sun");
  expectTheSameOverAnyWord(s, "iv");
  expectTheSameOverAnyWord(s, "ar");
}

}  // namespace
}  // namespace ivgi

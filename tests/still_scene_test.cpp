// A scene whose animation moves nothing that lights it (a camera's flight through a still scene):
// after the first frame the solvers record nothing, and each frame shows the first frame's
// solution, which is bit for bit what solving it again from the start gives. A sun's cascades
// follow the camera, for the pixels alone: the surfels' light stands.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <memory>
#include <set>
#include <string>

#include "engine/gi/ar/solver.h"
#include "engine/gi/iv/solver.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/builtin.h"
#include "tests/test_support.h"

namespace ivgi {
namespace {

using MakeSolver = std::function<std::unique_ptr<gi::Solver>(const scene::Scene&, const scene::Geometry&)>;

// Renders three frames of the still `model` from a camera that moves, by a renderer told that
// nothing moved after the first frame (`kept`) and one told each frame that everything did
// (`solved`, made by `makeSolved`); each frame's images must match bit for bit, and `kept`'s later
// frames time only what depends on the view (the direct light where `cascades` follow the camera):
// the posed vertices, the surfels and the solution stand.
void stillFramesShowWhatSolvingGives(const tinygltf::Model& model, const gi::DirectLightSettings& maps,
                                     const MakeSolver& makeKept, const MakeSolver& makeSolved, bool cascades) {
  const scene::Scene s = scene::sceneFromModel(model, "test");
  const scene::Geometry g = scene::buildGeometry(s);
  const scene::Pose pose = scene::evaluatePose(s, -1, 0.0f);
  const gi::ImageSettings image{40, 30, 1};
  const auto still = scene::movingInstances(s, g, -1);
  gi::FrameRenderer kept(test::gpu(), g, image, makeKept(s, g), maps, still);
  gi::FrameRenderer solved(test::gpu(), g, image, makeSolved(s, g), maps, still);
  const std::set<std::string> viewPasses = {"direct light", "raster", "direct pixels", "reflections", "resolve"};
  scene::CameraView view = scene::cameraView(s, pose, s.cameraNodes()[0]);
  for (int frame = 0; frame < 3; ++frame) {
    const auto lights = scene::worldLights(s, pose);
    const auto a = kept.render(g.frameInputs(s, pose), view, lights, frame == 0, frame);
    const auto b = solved.render(g.frameInputs(s, pose), view, lights, true, frame);
    ASSERT_EQ(a.channels.radiance.size(), b.channels.radiance.size());
    EXPECT_EQ(std::memcmp(a.channels.radiance.data(), b.channels.radiance.data(),
                          a.channels.radiance.size() * sizeof(glm::vec4)),
              0)
        << "frame " << frame;
    bool posedOrSolved = false, mapsDrawn = false;
    for (const auto& p : a.passTimes)
      posedOrSolved = posedOrSolved || !viewPasses.count(p.pass), mapsDrawn = mapsDrawn || p.pass == "direct light";
    EXPECT_EQ(posedOrSolved, frame == 0) << "frame " << frame;
    EXPECT_EQ(mapsDrawn, frame == 0 || cascades) << "frame " << frame;
    if (frame > 0 && cascades) {
      EXPECT_EQ(kept.directLight()->surfelsLit(), 0u) << "the cascades alone were drawn";
    }
    view.origin += glm::vec3(0.05f, 0.02f, 0.0f);  // the view-dependent passes run on
  }
}

// The still Cornell box, and the sun over a box, whose cascades follow the camera.
void stillFramesShowWhatSolvingGives(const MakeSolver& kept, const MakeSolver& solved) {
  stillFramesShowWhatSolvingGives(scenes::cornellBox({.cells = 6}), {.samples = 16, .resolution = 64, .perPixel = true},
                                  kept, solved, false);
  stillFramesShowWhatSolvingGives(test::sunOverABox(), {.resolution = 64, .perPixel = true, .punctualLights = 1}, kept,
                                  solved, true);
}

TEST(StillScene, IvShowsTheFirstFramesBounces) {
  const MakeSolver iv = [](const scene::Scene& s, const scene::Geometry& g) -> std::unique_ptr<gi::Solver> {
    // A camera that moves over a still scene: the solve does not follow the view (as the commands
    // choose where a camera moves and nothing else does).
    return std::make_unique<gi::IvSolver>(test::gpu(), g,
                                          gi::makeIvSetup(s, g, gi::IvSettings{.bins = 8, .viewGuided = false}, -1));
  };
  stillFramesShowWhatSolvingGives(iv, iv);
}

TEST(StillScene, ArShowsTheFirstFramesSolution) {
  // Solved again every frame, ar's chains would go on from the frame before; a chain of one
  // frame solves each from the start, as the first frame was.
  const auto ar = [](uint32_t restartEvery) {
    return [restartEvery](const scene::Scene& s, const scene::Geometry& g) -> std::unique_ptr<gi::Solver> {
      gi::Hierarchy h = gi::restPoseHierarchy(s, g);
      std::vector<bool> moves = gi::movingRoots(h, s, g, -1);
      return std::make_unique<gi::ArSolver>(test::gpu(), g, std::move(h), gi::ArSettings{.restartEvery = restartEvery},
                                            moves);
    };
  };
  stillFramesShowWhatSolvingGives(ar(16), ar(1));
}

}  // namespace
}  // namespace ivgi

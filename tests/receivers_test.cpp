// The iv solver's receivers (docs/design.md §2.4): chosen where the lighting needs them, coarse where
// it is smooth, continuous in what they judge by; coarse meshes tessellated so that they can be
// finer than the mesh; and the temporal measure of `ivgi compare` on an animation.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/gi/frame_renderer.h"
#include "engine/gi/hierarchy.h"
#include "engine/image/metrics.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

// A 2 m grey floor of 40×40 cells at y = 0 under a small lamp 3 m up, and a black square 0.5 m up
// shading the floor's half x < 0: a shadow edge along x = 0 with a penumbra of about 6 cm, the
// other half lit evenly (the lamp is far against the floor). With `camera`, a narrow camera 1 m over
// the floor that moves in one second from over its shaded half to over its lit half.
tinygltf::Model shadowEdge(bool camera = false) {
  scenes::GltfBuilder b;
  int lamp = b.material("lamp", glm::vec3(0.0f), glm::vec3(50.0f));
  int grey = b.material("floor", glm::vec3(0.5f));
  int black = b.material("blocker", glm::vec3(0.0f));
  scenes::MeshData light, floor, blocker;
  scenes::addQuad(light, {-0.15f, 3, -0.15f}, {0.15f, 3, -0.15f}, {0.15f, 3, 0.15f}, {-0.15f, 3, 0.15f}, 1, 1,
                  {0, 0, 0});
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 40, 40, {0, 1, 0});
  scenes::addQuad(blocker, {-3, 0.5f, -3}, {0, 0.5f, -3}, {0, 0.5f, 3}, {-3, 0.5f, 3}, 6, 12, {0, 0, 0});
  b.node("lamp", b.mesh("lamp", {{light, lamp}}));
  b.node("floor", b.mesh("floor", {{floor, grey}}));
  b.node("blocker", b.mesh("blocker", {{blocker, black}}));
  if (camera) {
    const glm::quat down = glm::angleAxis(glm::radians(-90.0f), glm::vec3(1, 0, 0));
    b.animate("a", b.camera("camera", 0.6f, 0.01f, {-0.5f, 0.4f, 0}, down), "translation", {0, 1},
              {-0.5f, 0.4f, 0, 0.5f, 0.4f, 0});
  }
  return b.finish();
}

// Per surfel, the irradiance the bounces brought: its radiosity over its albedo, less the direct light
// the depth maps gave it.
std::vector<glm::vec4> bouncedLight(const gi::FrameRenderer& r, const scene::Geometry& g) {
  const auto radiosity = test::ivSolver(r).leafRadiosity();
  const auto lit = r.directLight()->surfelDirect().read<glm::vec4>(g.surfels.size());
  std::vector<glm::vec4> e(g.surfels.size());
  for (size_t i = 0; i < e.size(); ++i)
    e[i] = glm::vec4(glm::vec3(radiosity[i]) / glm::vec3(g.surfelAlbedo[i]) - glm::vec3(lit[i]), 0.0f);
  return e;
}

}  // namespace

// Receivers crowd where the shadow's edge crosses the floor and thin out where the floor is lit
// evenly: the refinement follows the lighting, not the mesh (40×40 cells everywhere). Every surface
// is judged alike, whether the 16×16 image shows it or not.
TEST(Receivers, RefineAtAShadowEdgeAndStayCoarseOnAnEvenlyLitFloor) {
  scene::Scene s = scene::sceneFromModel(shadowEdge(), "test");
  scene::Geometry g = scene::buildGeometry(s);
  gi::FrameRenderer r = test::ivRenderer(g, {16, 16, 1}, gi::makeIvSetup(s, g, {.unseenTolerance = 1.0f}));
  auto pose = scene::evaluatePose(s, -1, 0.0f);
  r.render(g.frameInputs(s, pose),
           scene::framingCamera(scene::worldBounds(scene::animateOnHost(g, g.frameInputs(s, pose))), 1.0f));
  const auto surfels = scene::surfelsOnHost(g, scene::animateOnHost(g, g.frameInputs(s, pose)));
  std::vector<char> receiver(surfels.size(), 0);
  for (uint32_t k : test::ivSolver(r).receiverSurfels()) receiver[k] = 1;
  // Floor surfels (y = 0, facing up) in a band along the edge and in one as wide on the lit side.
  size_t edge = 0, edgeReceivers = 0, lit = 0, litReceivers = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    const glm::vec4 p = surfels[i].positionArea;
    if (std::abs(p.y) > 1e-4f || surfels[i].normal.y < 0.9f || std::abs(p.z) > 0.8f) continue;
    if (std::abs(p.x) < 0.15f) ++edge, edgeReceivers += receiver[i];
    if (p.x > 0.55f && p.x < 0.85f) ++lit, litReceivers += receiver[i];
  }
  const double edgeShare = double(edgeReceivers) / double(edge), litShare = double(litReceivers) / double(lit);
  std::printf(
      "[ receivers ] %zu of %zu surfels; along the edge %.0f %% of the floor's surfels, on the evenly lit side "
      "%.0f %%\n",
      test::ivSolver(r).receiverSurfels().size(), surfels.size(), 100 * edgeShare, 100 * litShare);
  EXPECT_LE(litShare, 0.25);
  EXPECT_GE(edgeShare, 3.0 * litShare);
}

// The image shows the back wall alone (a narrow view into the Cornell box): the surfaces it does not
// show, whose light reaches it only after a bounce, are judged at --unseen-tol and keep fewer
// receivers; those it shows keep theirs, and the image hardly changes.
TEST(Receivers, SurfacesTheImageDoesNotShowAreJudgedLooser) {
  const scene::Scene s = scene::sceneFromModel(scenes::cornellBox({.cells = 12}), "test");
  const scene::Geometry g = scene::buildGeometry(s);
  const scene::Pose pose = scene::evaluatePose(s, -1, 0.0f);
  scene::CameraView view = scene::cameraView(s, pose, s.cameraNodes()[0]);
  view.yfov *= 0.3f;
  struct Solved {
    std::vector<glm::vec4> radiance;
    std::vector<uint32_t> shown;
    std::vector<char> receiver;
  };
  auto solve = [&](float unseenTolerance) {
    gi::FrameRenderer r = test::ivRenderer(g, {48, 36, 1}, gi::makeIvSetup(s, g, {.unseenTolerance = unseenTolerance}));
    Solved out;
    out.radiance = r.render(g.frameInputs(s, pose), view).channels.radiance;
    out.shown = r.shownSurfels();
    out.receiver.assign(g.surfels.size(), 0);
    for (uint32_t k : test::ivSolver(r).receiverSurfels()) out.receiver[k] = 1;
    return out;
  };
  const Solved alike = solve(1.0f), looser = solve(16.0f);
  ASSERT_EQ(looser.shown.size(), g.surfels.size());
  size_t shown = 0, shownAlike = 0, shownLooser = 0, unseenAlike = 0, unseenLooser = 0;
  for (size_t i = 0; i < g.surfels.size(); ++i) {
    const bool seen = (looser.shown[i] & gpu::kShownFit) != 0;
    shown += seen;
    (seen ? shownAlike : unseenAlike) += alike.receiver[i];
    (seen ? shownLooser : unseenLooser) += looser.receiver[i];
  }
  double change = 0;
  for (size_t i = 0; i < alike.radiance.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double a = alike.radiance[i][c], b = looser.radiance[i][c];
      change += (b - a) * (b - a) / (a * a + 0.01) / double(3 * alike.radiance.size());
    }
  std::printf(
      "[ unseen ] %zu of %zu surfels shown; receivers among them %zu at --unseen-tol 1, %zu at 16; among the rest "
      "%zu and %zu; the image's relMSE between the two %.3g\n",
      shown, g.surfels.size(), shownAlike, shownLooser, unseenAlike, unseenLooser, change);
  EXPECT_LT(shown, g.surfels.size() / 4) << "the view shows the back wall alone";
  EXPECT_LT(unseenLooser, unseenAlike * 9 / 10);  // cells no larger than 1/8 of the box bound them
  EXPECT_GE(shownLooser, shownAlike * 9 / 10);
  EXPECT_LT(change, 1e-3);
}

// A camera that moves over a still scene sees it solved once, in the first frame a run renders: the
// receivers then do not follow the view (the sidecar says so), and shards write what one run writes.
TEST(Receivers, ACameraMovingOverAStillSceneLeavesThemUnguided) {
  const fs::path dir = test::scratchDir("moving-camera");
  const fs::path file = dir / "edge.gltf";
  scenes::writeModel(shadowEdge(true), file.string());
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", file.string(), "--frames", "0-23:8", "--size",
                                     "32x24",  "--format",    "exr",      "--out",  (dir / out / "f_%04d").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::runIvgi(args);
  };
  ASSERT_EQ(render("one", {}).status, 0);
  ASSERT_EQ(render("shards", {"--shard", "1/3"}).status, 0);
  EXPECT_TRUE(test::readFile(dir / "one" / "f_0008.exr") == test::readFile(dir / "shards" / "f_0008.exr"))
      << "frame 8 differs";
  const auto sidecar = nlohmann::json::parse(std::ifstream(dir / "one" / "f.json"));
  EXPECT_EQ(sidecar["solver"]["unseenTolerance"].get<double>(), 1.0);
  EXPECT_EQ(sidecar["settings"]["unseenTolerance"].get<double>(), 16.0);
}

namespace {

fs::path render(const std::string& name, std::vector<std::string> args) {
  const fs::path dir = test::scratchDir(name);
  args.insert(args.begin(), "render");
  args.insert(args.end(), {"--format", "exr", "--out", (dir / "f_%04d").string()});
  auto r = test::runIvgi(args);
  EXPECT_EQ(r.status, 0) << r.err;
  return dir;
}

double relMse(const fs::path& test, const fs::path& reference) {
  return image::measureError(image::readLinearRgb(test.string()), image::readLinearRgb(reference.string())).relMse;
}

}  // namespace

// The Cornell box of 2 cells a side: with the direct light from iv's own bins, light leaks where
// its few, large surfels meet the blocks (Dong et al. name it as the method's limitation on coarse
// meshes). Tessellated, the surfaces are sampled finely enough for the receivers to resolve the
// contact shadows: the image comes much nearer the path tracer's. With the direct light per pixel
// (the default) the shadows no longer depend on the surfels and the coarse box comes nearer too,
// though not as near: the unshadowed light and the bounces are still as coarse as its surfels.
TEST(Receivers, ACoarseFloorDoesNotLeakUnderTheBlocks) {
  const std::vector<std::string> scene = {"cornell", "--cells", "2", "--frames", "0", "--size", "96x72"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = scene;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  const fs::path pt = render("pt", with({"--method", "pt", "--spp", "512"})) / "f_0000.exr";
  const double coarse = relMse(render("coarse", with({"--tessellate", "0", "--direct", "bins"})) / "f_0000.exr", pt);
  const double tessellated = relMse(render("tessellated", with({"--direct", "bins"})) / "f_0000.exr", pt);
  const double coarsePixels = relMse(render("coarse-pixels", with({"--tessellate", "0"})) / "f_0000.exr", pt);
  std::printf(
      "[ leak ] relMSE against pt at 2 cells, the bins' direct light: %.4f as modelled, %.4f tessellated; "
      "the pixels': %.4f as modelled\n",
      coarse, tessellated, coarsePixels);
  EXPECT_LT(tessellated, 0.5 * coarse);
  EXPECT_LT(coarsePixels, coarse);
}

// The animated Cornell box with receivers chosen each frame against the same with every surfel a
// receiver: the adaptive choices do not flicker. The temporal relMSE (`ivgi compare` on two
// sequences: the error of the frame-to-frame change) stays far below the frames' own relMSE, which
// it would approach if the receivers' errors came and went from frame to frame (the test prints
// both).
TEST(Receivers, AdaptiveChoicesDoNotFlicker) {
  const std::vector<std::string> scene = {"cornell", "--cells", "12", "--frames", "0-9", "--size", "96x72"};
  std::vector<std::string> full = scene;
  full.insert(full.end(), {"--receiver-tol", "0"});
  const fs::path adaptive = render("adaptive", scene), everySurfel = render("every", full);
  const fs::path report = test::scratchDir("report") / "r.json";
  auto r = test::runIvgi({"compare", adaptive.string(), everySurfel.string(), "--json", report.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(report);
  const nlohmann::json j = nlohmann::json::parse(in);
  double frames = 0;
  for (const auto& f : j["frames"]) frames += f["metrics"]["relMSE"].get<double>() / double(j["frames"].size());
  const double temporal = j["summary"]["temporal"]["relMSE"].get<double>();
  std::printf("[ flicker ] temporal relMSE %.3g, frames' mean relMSE %.3g\n", temporal, frames);
  EXPECT_GT(frames, 0.0) << "the two sequences differ";
  EXPECT_LT(temporal, 3e-4);
  EXPECT_LT(temporal, 0.2 * frames);
}

// Without --receiver-tol the receivers are chosen on a CPU device (lavapipe), where fewer receivers
// save work, and every surfel is one on a GPU; the sidecar says "auto" and the value solved with.
TEST(Receivers, TheDefaultToleranceFollowsTheDevice) {
  EXPECT_EQ(gi::receiverToleranceOn({}, true), gi::kCpuReceiverTolerance);
  EXPECT_EQ(gi::receiverToleranceOn({}, false), 0.0f);
  EXPECT_EQ(gi::receiverToleranceOn({.receiverTolerance = 0.2f}, false), 0.2f);
  EXPECT_EQ(gi::receiverToleranceOn({.receiverTolerance = 0.0f}, true), 0.0f);

  auto dir = test::scratchDir("receiver-tol");
  for (const std::string given : {"", "0.2"}) {
    std::vector<std::string> args = {"render",   "cornell",
                                     "--cells",  "2",
                                     "--size",   "32x24",
                                     "--frames", "0",
                                     "--format", "exr",
                                     "--out",    (dir / "f").string(),
                                     "--json",   (dir / "s.json").string()};
    if (!given.empty()) args.insert(args.end(), {"--receiver-tol", given});
    auto r = test::runIvgi(args);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto sidecar = nlohmann::json::parse(std::ifstream(dir / "s.json"));
    const bool cpu = sidecar["device"]["type"] == "cpu";
    const float solved = given.empty() ? (cpu ? gi::kCpuReceiverTolerance : 0.0f) : std::stof(given);
    if (given.empty())
      EXPECT_EQ(sidecar["settings"]["receiverTolerance"], "auto");
    else
      EXPECT_FLOAT_EQ(sidecar["settings"]["receiverTolerance"].get<float>(), solved);
    EXPECT_FLOAT_EQ(sidecar["solver"]["receiverTolerance"].get<float>(), solved) << sidecar["solver"].dump();
  }
}

// The empty Cornell room's direct light (no bounce) at every surfel, interpolated from the receivers
// chosen at the default tolerance, against the lamp's exact integral: the walls' light, brightest
// between the floor and the ceiling and falling toward the corners, is curved where the receivers are
// sparse, and a linear fit through them flattens it (2.6 % dark in all); the quadratic fit follows it.
TEST(Receivers, TheInterpolationFollowsCurvedLight) {
  auto model = scenes::cornellBox({.cells = 16, .animated = false, .blocks = false});
  scene::Scene s = scene::sceneFromModel(model, "cornell");
  scene::Geometry g = scene::buildGeometry(s);
  gi::FrameRenderer r = test::ivRenderer(
      g, {16, 16, 1}, gi::makeIvSetup(s, g, {.bounces = 0, .receiverTolerance = gi::kCpuReceiverTolerance}));
  auto pose = scene::evaluatePose(s, -1, 0.0f);
  r.render(g.frameInputs(s, pose), scene::cameraView(s, pose, s.cameraNodes()[0]));
  const auto surfels = scene::surfelsOnHost(g, scene::animateOnHost(g, g.frameInputs(s, pose)));
  const std::vector<glm::vec4> radiosity = test::ivSolver(r).leafRadiosity();
  const test::DirectLightErrors e = test::emptyRoomDirectLight(
      surfels, g.surfelEmission, [&](size_t i) { return radiosity[i].x / g.surfelAlbedo[i].x; });
  std::printf(
      "[ interpolation ] empty room, %zu receivers of %zu surfels: in all %.2f %% of the exact; mean error %.2f %%, "
      "worst %.2f %%\n",
      test::ivSolver(r).receiverSurfels().size(), surfels.size(), 100 * e.total, 100 * e.mean, 100 * e.worst);
  EXPECT_GT(e.counted, 500);
  EXPECT_NEAR(e.total, 1.0, 0.01);
}

// A white ball over a floor red on one half and green on the other, under a point lamp whose light
// the depth maps give: the ball's bounced light comes from below and changes with the normal, red
// on one side, green on the other, none on top. Interpolated from the receivers at the default
// tolerance, each surfel takes its receivers' light turned to its own normal (their rotation
// gradients). Against every surfel a receiver, on the ball's sides (normals within 30° of level,
// where the floor's light comes in sideways) it is off by 5.1 % on average (9.7 % without the
// turn), and over the whole ball by 13.3 % (17.9 %).
TEST(Receivers, ABallTakesTheBouncedLightItsNormalsFace) {
  scenes::GltfBuilder b;
  const int white = b.material("white", glm::vec3(0.8f)), red = b.material("red", glm::vec3(0.8f, 0.1f, 0.1f)),
            green = b.material("green", glm::vec3(0.1f, 0.8f, 0.1f));
  scenes::MeshData left, right, ball = test::ball(24, 0.25f, {0.0f, 0.4f, 0.0f});
  scenes::addQuad(left, {-1, 0, -1}, {0, 0, -1}, {0, 0, 1}, {-1, 0, 1}, 16, 32, {0, 1, 0});
  scenes::addQuad(right, {0, 0, -1}, {1, 0, -1}, {1, 0, 1}, {0, 0, 1}, 16, 32, {0, 1, 0});
  b.node("floor", b.mesh("floor", {{left, red}, {right, green}}));
  b.node("ball", b.mesh("ball", {{ball, white}}));
  b.light("lamp", "point", 20.0f, {0, 2, 0});
  const auto [s, g, pose, inputs] = test::atRest(b.finish(), "ball");
  const auto view = test::framing(g, inputs);
  const gi::DirectLightSettings direct{.samples = 1, .punctualLights = 1};
  std::vector<std::vector<glm::vec4>> bounced;  // at the default tolerance, then with every surfel a receiver
  for (float tolerance : {gi::kCpuReceiverTolerance, 0.0f}) {
    gi::FrameRenderer r(
        test::gpu(), g, {16, 16, 1},
        std::make_unique<gi::IvSolver>(test::gpu(), g, gi::makeIvSetup(s, g, {.receiverTolerance = tolerance})),
        direct);
    r.render(inputs, view, scene::worldLights(s, pose));
    bounced.push_back(bouncedLight(r, g));
    if (tolerance > 0.0f)
      std::printf("[ receivers ] %zu of %zu surfels\n", test::ivSolver(r).receiverSurfels().size(), g.surfels.size());
  }
  const std::vector<scene::Surfel> surfels = scene::surfelsOnHost(g, scene::animateOnHost(g, inputs));
  double error[2] = {0.0, 0.0}, total[2] = {0.0, 0.0}, redSide = 0.0, greenSide = 0.0;  // the ball; its sides
  for (size_t i = 0; i < surfels.size(); ++i) {
    if (surfels[i].positionArea.y < 1e-3f) continue;  // the floor
    for (int part = 0; part < (std::abs(surfels[i].normal.y) < 0.5f ? 2 : 1); ++part)
      for (int c = 0; c < 3; ++c)
        error[part] += std::abs(bounced[0][i][c] - bounced[1][i][c]), total[part] += bounced[1][i][c];
    (surfels[i].positionArea.x < 0.0f ? redSide : greenSide) += bounced[1][i].x - bounced[1][i].y;
  }
  std::printf("[ receivers ] the ball's bounced light off by %.1f %% on average, on its sides by %.1f %%\n",
              100.0 * error[0] / total[0], 100.0 * error[1] / total[1]);
  EXPECT_GT(redSide, 0.0);  // the scene is what it says: red below on the left, green on the right
  EXPECT_LT(greenSide, 0.0);
  EXPECT_LT(error[1] / total[1], 0.07);
}

// The refinement's first candidates are the trees' roots and nothing else, however little room the
// roots take (a scene of one to three objects: their list is padded to the least buffer): a solver
// whose fresh memory held an inner node's index in every word gives the receivers and the image of
// one whose fresh memory held a root's (which the first round lists anyway).
TEST(Receivers, TheFirstRoundRefinesTheRootsAlone) {
  scene::Scene s = scene::sceneFromModel(shadowEdge(), "test");  // three objects
  scene::Geometry g = scene::buildGeometry(s);
  const auto pose = scene::evaluatePose(s, -1, 0.0f);
  const scene::CameraView view = test::framing(g, g.frameInputs(s, pose));
  const gi::Hierarchy h = gi::restPoseHierarchy(s, g);
  ASSERT_GE(h.levels(), 3u);
  const uint32_t inner = h.levelStart[h.levels() - 2];  // above leaves: refined only where the light asks
  ASSERT_EQ(std::find(h.roots.begin(), h.roots.end(), inner), h.roots.end());
  const auto solveOver = [&](uint32_t word) {
    gi::FrameRenderer r = [&] {
      const test::FreshMemoryFill fill(word);
      return test::ivRenderer(g, {16, 16, 1}, gi::makeIvSetup(s, g, {}));
    }();
    const auto frame = r.render(g.frameInputs(s, pose), view);
    return std::make_pair(test::ivSolver(r).receiverSurfels(), frame.channels.radiance);
  };
  const auto overRoot = solveOver(h.roots[0]), overInner = solveOver(inner);
  EXPECT_EQ(overInner.first, overRoot.first) << "receivers";
  EXPECT_EQ(std::memcmp(overInner.second.data(), overRoot.second.data(), overRoot.second.size() * sizeof(glm::vec4)),
            0);
}

// A bumpy ball under a lamp: where a sampled node's receiver does not reach all of its surfels (its
// normal turned past the kernel's, or its place off the receiver's plane), those surfels take a
// receiver made for them, a fill. A fill stands at the coarsest node between such a surfel and that
// sampled ancestor whose support holds it, so that the surfels it holds share it: fewer fills than
// surfels taking them, each within the kernel's angle of them, and their bounced light near what
// every surfel a receiver gives them.
TEST(Receivers, SurfelsNoSupportHoldsShareTheirFills) {
  scenes::MeshData ball = test::uvSphere(48, true);
  for (glm::vec3& p : ball.positions) p = 0.1f * p + glm::vec3(0.0f, 0.4f, 0.0f);
  const auto [s, g, pose, inputs] =
      test::atRest(test::ballOnFloor(ball, glm::vec3(0.8f), 32, 20.0f, {0.5f, 2, 0.3f}), "ball");
  const auto view = test::framing(g, inputs);
  std::vector<std::vector<glm::vec4>> bounced;  // at the default tolerance, then with every surfel a receiver
  std::vector<std::vector<gi::IvSolver::Tap>> taps;
  std::vector<uint32_t> receivers, fills;
  for (float tolerance : {gi::kCpuReceiverTolerance, 0.0f}) {
    gi::FrameRenderer r(
        test::gpu(), g, {16, 16, 1},
        std::make_unique<gi::IvSolver>(test::gpu(), g, gi::makeIvSetup(s, g, {.receiverTolerance = tolerance})),
        gi::DirectLightSettings{.samples = 1, .punctualLights = 1});
    r.render(inputs, view, scene::worldLights(s, pose));
    bounced.push_back(bouncedLight(r, g));
    if (tolerance > 0.0f) {
      taps = test::ivSolver(r).interpolationTaps();
      receivers = test::ivSolver(r).receiverSurfels();
      fills = test::ivSolver(r).fillSurfels();
    }
  }
  const std::vector<scene::Surfel> surfels = scene::surfelsOnHost(g, scene::animateOnHost(g, inputs));
  size_t served = 0;
  double error[2] = {0.0, 0.0}, total[2] = {0.0, 0.0};  // the ball's surfels taking a fill; interpolated
  for (size_t i = 0; i < taps.size(); ++i) {
    if (surfels[i].positionArea.y < 1e-3f || std::binary_search(receivers.begin(), receivers.end(), uint32_t(i)))
      continue;  // the floor, or a receiver itself
    const bool fill = taps[i].size() == 1 && std::binary_search(fills.begin(), fills.end(), taps[i][0].receiver);
    if (fill) {
      ++served;
      EXPECT_EQ(taps[i][0].coefficient, 1.0f);
      EXPECT_GT(glm::dot(surfels[i].normal, surfels[taps[i][0].receiver].normal), gpu::kReceiverNormalCos);
    }
    for (int c = 0; c < 3; ++c)
      error[fill ? 0 : 1] += std::abs(bounced[0][i][c] - bounced[1][i][c]), total[fill ? 0 : 1] += bounced[1][i][c];
  }
  std::printf(
      "[ receivers ] %zu fills for %zu surfels no support holds; against every surfel a receiver, their bounced "
      "light off by %.1f %%, the interpolated surfels' by %.1f %%\n",
      fills.size(), served, 100.0 * error[0] / total[0], 100.0 * error[1] / total[1]);
  ASSERT_GT(served, 0u);  // some surfels take a fill that is not their own
  EXPECT_LT(fills.size(), served);
  EXPECT_LT(error[0] / total[0], error[1] / total[1]);
}

// The still box at --cells 26, and the same turned 30° about (1, 1, 1), camera and all: pt's image
// does not change, and iv's must not change with where the world's axes fall. The receivers' largest
// cell is a share of the scene's extent, which must be the same however the scene turns (the
// diagonal of its bounds along the world's axes would grow by up to √3).
TEST(Receivers, TheSameSceneTurnedGetsTheSameReceivers) {
  const tinygltf::Model box = scenes::cornellBox({.cells = 26, .animated = false});
  const tinygltf::Model askew = test::turned(box, 30.0f, {1, 1, 1});
  const auto extent = [](const tinygltf::Model& model) {
    const scene::Scene s = scene::sceneFromModel(model, "test");
    return gi::restPoseHierarchy(s, scene::buildGeometry(s)).size;
  };
  EXPECT_NEAR(extent(askew) / extent(box), 1.0, 1e-4);
  const auto render = [](const std::string& name, const tinygltf::Model& model) {
    const fs::path exr = test::renderModelExr(name, model, {"--supersample", "2", "--size", "160x120"});
    const auto sidecar = nlohmann::json::parse(std::ifstream(exr.parent_path() / "f.json"));
    return std::pair{exr, sidecar["solver"]["receivers"].get<double>()};
  };
  const auto [straight, straightReceivers] = render("straight", box);
  const auto [turnedImage, turnedReceivers] = render("turned", askew);
  const auto error =
      image::measureError(image::readLinearRgb(turnedImage.string()), image::readLinearRgb(straight.string()));
  std::printf(
      "[ receivers ] the box turned 30°: %.0f receivers against %.0f, relMSE %.6f, FLIP %.4f against unturned\n",
      turnedReceivers, straightReceivers, error.relMse, error.flip);
  EXPECT_GT(turnedReceivers, 0.85 * straightReceivers);
  EXPECT_LT(error.relMse, 0.00011);
}

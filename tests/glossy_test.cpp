// Glossy surfaces in iv and ar: the direct light's highlights per pixel (direct_pixels evaluates
// each light's reflection through the material's lobe), against the path tracer, and the extremes
// of the factors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/gi/ar/solver.h"
#include "engine/gi/iv/solver.h"
#include "engine/image/metrics.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf.h"
#include "engine/scene/lights.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

// A floor (4 m square; by default metal of roughness 0.25) under a point light 1 m above its
// centre, seen from 2 m away at 26.6° down, so that the light's highlight lies in the middle of
// the image.
fs::path metalFloorUnderALamp(float metallic = 1.0f, float roughness = 0.25f, const std::string& name = "metal-floor") {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}, 8, 8, {0, 1, 0});
  b.node("floor",
         b.mesh("floor", {{floor, b.glossyMaterial("metal", glm::vec3(0.9f, 0.7f, 0.5f), metallic, roughness)}}));
  b.light("lamp", "point", 4.0f, {0, 1, 0});
  b.camera("camera", 0.9f, 0.01f, {0, 1, 2}, glm::angleAxis(-std::atan(0.5f), glm::vec3(1, 0, 0)));
  const fs::path file = test::scratchDir(name) / (name + ".gltf");
  scenes::writeModel(b.finish(), file.string());
  return file;
}

using MakeSolver = std::function<std::unique_ptr<gi::Solver>(const scene::Scene&, const scene::Geometry&)>;

// The reflections are computed only at the surfels the image reads (mark_shown, mark_fit, iv's
// mark_taps). A narrow view into the still glossy box, moving from frame to frame, must show bit for
// bit what reflecting at every surfel shows, while most surfels go unmarked: a surfel left out that
// the image reads would show a fresh renderer's empty buffer or a frame before's reflection.
void reflectionsOnlyWhereShown(const MakeSolver& make, bool receivers) {
  const scene::Scene s =
      scene::sceneFromModel(scenes::cornellBox({.cells = 6, .animated = false, .glossy = true}), "test");
  const scene::Geometry g = scene::buildGeometry(s);
  const scene::Pose pose = scene::evaluatePose(s, -1, 0.0f);
  const gi::ImageSettings image{40, 30, 2};
  const gi::DirectLightSettings maps{.samples = 16, .resolution = 64, .perPixel = true};
  const auto still = scene::movingInstances(s, g, -1);
  gi::FrameRenderer marked(test::gpu(), g, image, make(s, g), maps, still);
  gi::FrameRenderer every(test::gpu(), g, image, make(s, g), maps, still);
  every.reflectEverySurfel();
  scene::CameraView view = scene::cameraView(s, pose, s.cameraNodes()[0]);
  view.yfov *= 0.4f;  // the blocks and the floor before them
  for (int frame = 0; frame < 3; ++frame) {
    const auto lights = scene::worldLights(s, pose);
    const auto a = marked.render(g.frameInputs(s, pose), view, lights, frame == 0, frame);
    const auto b = every.render(g.frameInputs(s, pose), view, lights, frame == 0, frame);
    ASSERT_EQ(a.channels.radiance.size(), b.channels.radiance.size());
    EXPECT_EQ(std::memcmp(a.channels.radiance.data(), b.channels.radiance.data(),
                          a.channels.radiance.size() * sizeof(glm::vec4)),
              0)
        << "frame " << frame;
    const std::vector<uint32_t> shown = marked.shownSurfels();
    const auto marks = [&](uint32_t bit) {
      return std::count_if(shown.begin(), shown.end(), [&](uint32_t m) { return (m & bit) != 0; });
    };
    EXPECT_GT(marks(gpu::kShownVertex), 0) << "frame " << frame;
    EXPECT_GE(marks(gpu::kShownFit), marks(gpu::kShownVertex)) << "frame " << frame;
    EXPECT_LT(2 * marks(gpu::kShownFit), long(shown.size())) << "frame " << frame << ": most of the box is out of view";
    EXPECT_EQ(marks(gpu::kShownTap) > 0, receivers) << "frame " << frame;
    view.origin += glm::vec3(0.04f, 0.02f, 0.0f);
    view.forward = glm::normalize(view.forward + glm::vec3(-0.05f, 0.0f, 0.0f));
    view.right = glm::normalize(glm::cross(view.forward, view.up));
    view.up = glm::cross(view.right, view.forward);
  }
}

}  // namespace

// The passes that weigh only some links' lobes (lobe_excess, reflect_receivers) gather those links
// in batches (receiver_links.glsl's walkLinksInBatches): by a subgroup ballot where the device's
// subgroup holds the workgroup, else behind barriers. The second way, forced on a device that has
// the first, must give the same image (the batches fill in lane order either way; within 1e-5
// where a device's ballot orders its lanes otherwise) and no validation error.
TEST(Glossy, IvBatchesLinksAlikeWhereWorkgroupsSpanSubgroups) {
  const scene::Scene s = scene::sceneFromModel(scenes::cornellBox({.cells = 8, .glossy = true}), "test");
  const scene::Geometry g = scene::buildGeometry(s);
  const scene::Pose pose = scene::evaluatePose(s, 0, 0.25f);
  const scene::CameraView view = scene::cameraView(s, pose, s.cameraNodes()[0]);
  const gi::DirectLightSettings maps{.samples = 16, .resolution = 64, .perPixel = true};
  const auto renderOn = [&](const vk::Context& ctx) {
    gi::FrameRenderer r(ctx, g, gi::ImageSettings{48, 36, 1},
                        std::make_unique<gi::IvSolver>(ctx, g, gi::makeIvSetup(s, g, gi::IvSettings{.bins = 8}, 0)),
                        maps);
    return r.render(g.frameInputs(s, pose), view, scene::worldLights(s, pose)).channels.radiance;
  };
  if (!test::gpu().subgroupHolds(gpu::kReceiverGroup)) GTEST_SKIP() << "the device takes the barriers' way itself";
  vk::Context spanning(vk::ContextOptions{.validation = true, .spanSubgroups = true});
  ASSERT_FALSE(spanning.subgroupHolds(gpu::kReceiverGroup));
  const std::vector<glm::vec4> ballot = renderOn(test::gpu()), barriers = renderOn(spanning);
  ASSERT_EQ(ballot.size(), barriers.size());
  double largest = 0.0, worst = 0.0;
  for (size_t i = 0; i < ballot.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      largest = std::max(largest, double(ballot[i][c]));
      worst = std::max(worst, std::abs(double(ballot[i][c]) - double(barriers[i][c])));
    }
  EXPECT_GT(largest, 0.0);
  EXPECT_LE(worst, 1e-5 * largest);
  EXPECT_EQ(spanning.validationErrors(), 0u);
}

TEST(Glossy, IvReflectsOnlyWhatTheImageShows) {
  reflectionsOnlyWhereShown(
      [](const scene::Scene& s, const scene::Geometry& g) -> std::unique_ptr<gi::Solver> {
        return std::make_unique<gi::IvSolver>(test::gpu(), g, gi::makeIvSetup(s, g, gi::IvSettings{.bins = 8}, -1));
      },
      true);
}

TEST(Glossy, ArReflectsOnlyWhatTheImageShows) {
  reflectionsOnlyWhereShown(
      [](const scene::Scene& s, const scene::Geometry& g) -> std::unique_ptr<gi::Solver> {
        gi::Hierarchy h = gi::restPoseHierarchy(s, g);
        std::vector<bool> moves = gi::movingRoots(h, s, g, -1);
        return std::make_unique<gi::ArSolver>(test::gpu(), g, std::move(h), gi::ArSettings{}, moves);
      },
      false);
}

// The highlight of a point light on a rough metal: iv and ar reflect it per pixel as the path
// tracer does (nothing else lights the floor, so only the pixels' sampling differs); the diffuse
// surface they drew before spread it over the floor (relMSE 7.8, FLIP 0.67 against pt here).
TEST(Glossy, APointLightsHighlightIsWherePtPutsIt) {
  const fs::path scene = metalFloorUnderALamp();
  const auto pt = image::readLinearRgb(
      test::renderExr("pt", {scene.string(), "--method", "pt", "--spp", "1", "--size", "96x72"}).string());
  size_t brightest = 0;
  for (size_t i = 0; i < pt.pixels.size(); ++i)
    if (pt.pixels[i].g > pt.pixels[brightest].g) brightest = i;
  const int bx = int(brightest % pt.width), by = int(brightest / pt.width);
  // The lamp's mirror image in the floor, (0, -1, 0), is seen through the floor at (0, 0, 1): on the
  // middle column, 18.4° below the view's axis (the row at 36 + 36 · tan 18.4° / tan 25.8°).
  EXPECT_NEAR(bx, 48, 8) << "the highlight lies on the image's middle column";
  EXPECT_NEAR(by, 61, 8) << "the highlight lies where the lamp's mirror image is seen";
  for (const char* method : {"iv", "ar"}) {
    const auto image =
        image::readLinearRgb(test::renderExr(method, {scene.string(), "--method", method, "--size", "96x72"}).string());
    const auto error = image::measureError(image, pt);
    std::printf("[ glossy ] %s against pt: relMSE %.5f, FLIP %.4f; highlight %.4f against %.4f\n", method, error.relMse,
                error.flip, image.pixels[brightest].g, pt.pixels[brightest].g);
    EXPECT_LT(error.relMse, 0.01) << method;
    EXPECT_NEAR(image.pixels[brightest].g, pt.pixels[brightest].g, 0.05 * pt.pixels[brightest].g) << method;
  }
}

// A white wall beside a metal floor (roughness 0.25) that mirrors a point light onto it. The light
// the floor throws up grows toward the wall's foot, nearer the lamp's mirror image: the glossy
// leaves send what their lobes reflect of the direct light along the lobe
// (shaders/common/sender_lobes.glsl). Sent evenly over the floor's hemisphere, as a diffuse floor
// sends it, the wall's foot came out 4 % (iv) and 6 % (ar) brighter than its upper part, against
// pt's 25 %.
// iv sends a glossy leaf's light along its lobe (lobe_excess.comp), and reflects the other surfaces'
// light toward the eye through the lobe (reflect_receivers.comp), only where some material's lobe
// is far from even (Geometry::directionalLobes): a floor of roughness 1 runs neither pass, one of
// roughness 0.5 both. The lamp's highlight is drawn per pixel either way.
TEST(Glossy, IvSendsOnlyDirectionalLobesByDirection) {
  for (const float roughness : {1.0f, 0.5f}) {
    const std::string name = roughness < 1.0f ? "satin-floor" : "rough-floor";
    const fs::path scene = metalFloorUnderALamp(0.0f, roughness, name),
                   json = test::scratchDir(name + "-bench") / "bench.json";
    const auto r = test::runIvgi({"bench", scene.string(), "--size", "32x24", "--frames", "1", "--warmup", "0",
                                  "--per-program", "--json", json.string()});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(json);
    const auto programs = nlohmann::json::parse(in)["programs"];
    EXPECT_EQ(programs.contains("lobe_excess"), roughness < 1.0f) << "roughness " << roughness;
    EXPECT_EQ(programs.contains("reflect_receivers"), roughness < 1.0f) << "roughness " << roughness;
    EXPECT_TRUE(programs.contains("direct_pixels")) << "roughness " << roughness;
  }
}

TEST(Glossy, AMetalFloorThrowsTheLampsLightUpTheWall) {
  scenes::GltfBuilder b;
  scenes::MeshData floor, wall;
  scenes::addQuad(floor, {-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}, 16, 16, {0, 1, 0});
  scenes::addQuad(wall, {1.5f, 0, 2}, {1.5f, 0, -2}, {1.5f, 2, -2}, {1.5f, 2, 2}, 16, 8, {-1, 0, 0});
  b.node("floor", b.mesh("floor", {{floor, b.glossyMaterial("metal", glm::vec3(0.9f), 1.0f, 0.25f)}}));
  b.node("wall", b.mesh("wall", {{wall, b.material("white", glm::vec3(0.8f))}}));
  b.light("lamp", "point", 4.0f, {-1, 1, 0});
  b.camera("camera", 0.6f, 0.01f, {-1.8f, 1.2f, 0}, glm::angleAxis(-0.5f * gpu::kPi, glm::vec3(0, 1, 0)));
  const fs::path scene = test::scratchDir("lobe-wall") / "lobe-wall.gltf";
  scenes::writeModel(b.finish(), scene.string());
  // Rows 8 to 47 of the 48 see the wall alone (the sky above it).
  const auto rowsMean = [](const image::RgbImage& im, uint32_t first, uint32_t end) {
    double sum = 0.0;
    for (uint32_t y = first; y < end; ++y)
      for (uint32_t x = 0; x < im.width; ++x) sum += im.pixels[size_t(y) * im.width + x].g;
    return sum / (im.width * (end - first));
  };
  const auto pt = image::readLinearRgb(
      test::renderExr("pt", {scene.string(), "--method", "pt", "--spp", "64", "--size", "64x48"}).string());
  const double ptRise = rowsMean(pt, 36, 48) / rowsMean(pt, 8, 20), ptMean = rowsMean(pt, 8, 48);
  for (const char* method : {"iv", "ar"}) {
    const auto image =
        image::readLinearRgb(test::renderExr(method, {scene.string(), "--method", method, "--size", "64x48"}).string());
    const double rise = rowsMean(image, 36, 48) / rowsMean(image, 8, 20), mean = rowsMean(image, 8, 48);
    std::printf("[ glossy ] the wall, %s: foot over upper part %.3f, pt %.3f; mean %.4f, pt %.4f\n", method, rise,
                ptRise, mean, ptMean);
    EXPECT_NEAR(rise, ptRise, 0.05 * ptRise) << method;
    EXPECT_NEAR(mean, ptMean, 0.1 * ptMean) << method;
  }
}

// A metal plane (base 0.9, roughness 0.35) under an even white sky, seen 42° to 66° from its normal:
// what its lobe reflects is its directional albedo. ar reflects the light its bins hold through the
// lobe weighed at their centres; a lobe about a bin wide then falls between or onto them, and the
// plane came out 27 % dark at --dirs 2, 19 % at 4 and 7 % at 8, where its weights now sum to the
// lobe's albedo. iv reflects the sky as even light: exact by construction.
TEST(Glossy, AnEvenSkyReflectsAsTheLobesAlbedo) {
  scenes::GltfBuilder b;
  scenes::MeshData plane;
  scenes::addQuad(plane, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, 8, 8, {0, 1, 0});
  b.node("plane", b.mesh("plane", {{plane, b.glossyMaterial("metal", glm::vec3(0.9f), 1.0f, 0.35f)}}));
  b.camera("camera", 0.4f, 0.01f, {0, 1, 0}, glm::angleAxis(-gpu::kPi / 5.0f, glm::vec3(1, 0, 0)));
  const fs::path scene = test::scratchDir("even-sky") / "even-sky.gltf";
  scenes::writeModel(b.finish(), scene.string());
  const auto mean = [](const fs::path& exr) { return test::meanOf(image::readLinearRgb(exr.string()), 1); };
  const std::vector<std::string> common = {scene.string(), "--env", "1,1,1", "--size", "32x24"};
  auto args = [&](std::vector<std::string> more) {
    more.insert(more.begin(), common.begin(), common.end());
    return more;
  };
  const double pt = mean(test::renderExr("even-sky-pt", args({"--method", "pt", "--spp", "256"})));
  for (const char* dirs : {"2", "4", "8"}) {
    const double ar =
        mean(test::renderExr(std::string("even-sky-ar") + dirs, args({"--method", "ar", "--dirs", dirs})));
    std::printf("[ glossy ] the plane under an even sky: ar --dirs %s %.4f, pt %.4f\n", dirs, ar, pt);
    EXPECT_NEAR(ar, pt, 0.01 * pt) << "--dirs " << dirs;
  }
  const double iv = mean(test::renderExr("even-sky-iv", args({"--method", "iv"})));
  EXPECT_NEAR(iv, pt, 0.01 * pt);
}

// The furnace's walls a rough metal (base 0.9, roughness 0.35), every wall emitting 1, seen from
// the centre: a reflectance near 0.87 multiplies any loss a bounce makes about sevenfold. iv's
// reflections toward the eye read the bounces' last radiosity without the tail of the bounces not
// run, which the irradiance takes (bounce_tail.comp): 4.64 where pt gives 7.61. Now iv 7.26, ar 7.08.
TEST(Glossy, AMetalFurnaceKeepsItsLight) {
  tinygltf::Model m = scenes::furnace({.cells = 8});
  m.materials[0].pbrMetallicRoughness.baseColorFactor = {0.9, 0.9, 0.9, 1.0};
  m.materials[0].pbrMetallicRoughness.metallicFactor = 1.0;
  m.materials[0].pbrMetallicRoughness.roughnessFactor = 0.35;
  m.materials[0].extensions.clear();
  const fs::path scene = test::scratchDir("metal-furnace") / "metal-furnace.gltf";
  scenes::writeModel(m, scene.string());
  const auto mean = [](const fs::path& exr) { return test::meanOf(image::readLinearRgb(exr.string())); };
  const double pt =
      mean(test::renderExr("metal-furnace-pt", {scene.string(), "--method", "pt", "--spp", "64", "--size", "32x32"}));
  for (const char* method : {"iv", "ar"}) {
    const double got = mean(test::renderExr(std::string("metal-furnace-") + method,
                                            {scene.string(), "--method", method, "--size", "32x32"}));
    std::printf("[ glossy ] the metal furnace, %s: %.3f, pt %.3f\n", method, got, pt);
    EXPECT_NEAR(got, pt, 0.08 * pt) << method;
  }
}

// The extremes of the factors: a mirror (roughness 0, drawn at the clamp's 0.032), the roughest
// metal and a smooth dielectric give finite images in every method, no value replaced; iv and ar
// say once that they reflect the smooth ones' surroundings blurred.
TEST(Glossy, AMirrorAndTheRoughestSurfacesRenderFinitely) {
  struct Case {
    float metallic, roughness;
  };
  for (const Case c : {Case{1.0f, 0.0f}, Case{1.0f, 1.0f}, Case{0.0f, 0.0f}}) {
    const std::string name = "floor-" + std::to_string(int(c.metallic)) + "-" + std::to_string(int(c.roughness));
    const fs::path scene = metalFloorUnderALamp(c.metallic, c.roughness, name);
    for (const char* method : {"pt", "iv", "ar"}) {
      const fs::path out = test::scratchDir(name + method);
      std::vector<std::string> args = {"render",   scene.string(), "--method", method,
                                       "--size",   "48x36",        "--frames", "0",
                                       "--format", "exr",          "--out",    (out / "f").string()};
      if (std::string(method) == "pt") args.insert(args.end(), {"--spp", "4"});
      const test::Run r = test::runIvgi(args);
      EXPECT_EQ(r.status, 0) << name << " " << method << ": " << r.err;
      EXPECT_EQ(r.err.find("non-finite"), std::string::npos) << name << " " << method << ": " << r.err;
      // Smoother than their directions resolve, iv and ar say so, once.
      const bool unresolved = c.roughness == 0.0f && std::string(method) != "pt";
      const size_t note = r.err.find("are smoother than the");
      EXPECT_EQ(note != std::string::npos, unresolved) << name << " " << method << ": " << r.err;
      if (unresolved) {
        EXPECT_EQ(r.err.find("are smoother than the", note + 1), std::string::npos) << r.err;
      }
      const std::vector<float> red = test::channelOf(out / "f_0000.exr", "R");
      ASSERT_FALSE(red.empty()) << name << " " << method;
      for (float v : red) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << name << " " << method;
      EXPECT_GT(*std::max_element(red.begin(), red.end()), 0.0f) << name << " " << method << ": a lit floor";
    }
  }
}

// A metal ball (roughness 0.4) over a floor red on one half and green on the other, under a lamp.
// Toward its silhouette a surfel faces the eye at grazing, while the receivers it interpolates from
// face it more squarely (their views mirror toward the lit floor) or face away. Taking what those
// found for the surfel's own view made the rim (normals 70° to 90° from the view) 63 % brighter
// than pt; the receivers whose views mirror alike stand for it, else the rest of the indirect light
// is reflected as if even: 22 % brighter, where the receivers are coarse (1.6 % with every surfel a
// receiver). iv at 4×4 samples a pixel.
TEST(Glossy, IvReflectsTowardTheSilhouetteWhatLikeViewsFound) {
  scenes::GltfBuilder b;
  scenes::MeshData left, right, ball = test::ball(24, 0.3f, {0.0f, 0.35f, 0.0f});
  scenes::addQuad(left, {-1.5f, 0, -1.5f}, {0, 0, -1.5f}, {0, 0, 1.5f}, {-1.5f, 0, 1.5f}, 12, 24, {0, 1, 0});
  scenes::addQuad(right, {0, 0, -1.5f}, {1.5f, 0, -1.5f}, {1.5f, 0, 1.5f}, {0, 0, 1.5f}, 12, 24, {0, 1, 0});
  b.node("floor", b.mesh("floor", {{left, b.material("red", glm::vec3(0.8f, 0.1f, 0.1f))},
                                   {right, b.material("green", glm::vec3(0.1f, 0.8f, 0.1f))}}));
  b.node("ball", b.mesh("ball", {{ball, b.glossyMaterial("metal", glm::vec3(0.9f), 1.0f, 0.4f)}}));
  b.light("lamp", "point", 6.0f, {0.3f, 1.5f, 0.4f});
  b.camera("camera", 0.5f, 0.01f, {0, 0.5f, 1.6f}, glm::angleAxis(-0.1f, glm::vec3(1, 0, 0)));
  const fs::path scene = test::scratchDir("silhouette") / "silhouette.gltf";
  scenes::writeModel(b.finish(), scene.string());
  constexpr uint32_t kWidth = 160, kHeight = 120;
  const std::string size = std::to_string(kWidth) + "x" + std::to_string(kHeight);
  const fs::path ptFile =
      test::renderExr("silhouette-pt", {scene.string(), "--method", "pt", "--spp", "256", "--size", size});
  const fs::path ivFile = test::renderExr("silhouette-iv", {scene.string(), "--supersample", "4", "--size", size});
  const std::vector<float> metallic = test::channelOf(ptFile, "metallic"), pt = test::channelOf(ptFile, "G"),
                           iv = test::channelOf(ivFile, "G");
  std::vector<float> normal[3] = {test::channelOf(ptFile, "N.X"), test::channelOf(ptFile, "N.Y"),
                                  test::channelOf(ptFile, "N.Z")};
  ASSERT_FALSE(metallic.empty() || pt.empty() || iv.empty() || normal[0].empty());
  // Each pixel's view ray, from the camera's field of view and its tilt of 0.1 rad about x.
  const float t = std::tan(0.25f), aspect = float(kWidth) / float(kHeight);
  double ptRim = 0.0, ivRim = 0.0, ptBall = 0.0, ivBall = 0.0;
  size_t rim = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (metallic[i] < 0.99f) continue;  // wholly the ball
      ptBall += pt[i], ivBall += iv[i];
      const glm::vec3 ray = glm::angleAxis(-0.1f, glm::vec3(1, 0, 0)) *
                            glm::normalize(glm::vec3((2.0f * (x + 0.5f) / kWidth - 1.0f) * t * aspect,
                                                     (1.0f - 2.0f * (y + 0.5f) / kHeight) * t, -1.0f));
      const glm::vec3 n(normal[0][i], normal[1][i], normal[2][i]);
      if (std::abs(glm::dot(glm::normalize(n), ray)) < 0.35f) ptRim += pt[i], ivRim += iv[i], ++rim;
    }
  std::printf("[ glossy ] the ball's rim (%zu pixels), iv over pt %.3f; the whole ball %.3f\n", rim, ivRim / ptRim,
              ivBall / ptBall);
  EXPECT_GT(rim, 300u);
  EXPECT_NEAR(ivBall / ptBall, 1.0, 0.05);
  EXPECT_NEAR(ivRim / ptRim, 1.0, 0.25) << "the receivers' spacing at the silhouette";
}

// The still glossy box at --cells 26, and the same turned 2° about x, camera and all: pt's image
// does not change, and iv's reflection of the metal block must not change with where the turn puts
// its receivers. A receiver's reflection through the metal's narrow lobe is taken from few links:
// where a few receivers' supports span the block, each decides a patch of it, and the patches follow
// where the receivers fall. The receivers of a surface whose lobe holds most of what the eye sees
// lie nearer by the lobe's width (seen_nodes), so that each surfel takes its reflection from several.
TEST(Glossy, IvMetalReflectionHoldsUnderARigidTurn) {
  const auto render = [](const std::string& name, float degrees) {
    const tinygltf::Model box = scenes::cornellBox({.cells = 26, .animated = false, .glossy = true});
    return test::renderModelExr(name, test::turned(box, degrees, {1, 0, 0}),
                                {"--supersample", "2", "--size", "160x120"});
  };
  const fs::path before = render("metal-turn-0", 0.0f), after = render("metal-turn-2", 2.0f);
  const std::vector<float> metallic = test::channelOf(before, "metallic"),
                           turnedMetallic = test::channelOf(after, "metallic");
  ASSERT_EQ(metallic.size(), turnedMetallic.size());
  double sumBefore = 0.0, sumAfter = 0.0, relMse = 0.0;
  size_t pixels = 0;
  for (const char* channel : {"R", "G", "B"}) {
    const std::vector<float> a = test::channelOf(before, channel), b = test::channelOf(after, channel);
    ASSERT_EQ(a.size(), metallic.size());
    for (size_t i = 0; i < a.size(); ++i) {
      if (metallic[i] < 0.99f || turnedMetallic[i] < 0.99f) continue;  // wholly the metal block in both
      sumBefore += a[i], sumAfter += b[i], ++pixels;
      relMse += double(b[i] - a[i]) * (b[i] - a[i]) / (double(a[i]) * a[i] + 0.01);
    }
  }
  relMse /= double(std::max<size_t>(pixels, 1));
  std::printf("[ glossy ] the metal block (%zu pixel channels) turned 2°: its light %.3f of before, relMSE %.5f\n",
              pixels, sumAfter / sumBefore, relMse);
  EXPECT_GT(pixels, 3000u);
  EXPECT_NEAR(sumAfter / sumBefore, 1.0, 0.05);
  EXPECT_LT(relMse, 0.006);
}

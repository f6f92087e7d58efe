// glTF's orthographic cameras: parallel rays from a plane, its half height ymag (the half width from
// the image's aspect, as a perspective camera's from yfov), read by every method and the path tracer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/image/metrics.h"
#include "engine/scene/gltf.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

// The still Cornell box, its camera made orthographic (looking in from the same place) where
// `orthographic`: a view 0.4 m high, within the box's walls.
fs::path cornellView(bool orthographic) {
  tinygltf::Model m = scenes::cornellBox({.cells = 8, .animated = false});
  if (orthographic) {
    tinygltf::Camera& c = m.cameras[0];
    c.type = "orthographic";
    c.orthographic.xmag = 0.2 * 4.0 / 3.0, c.orthographic.ymag = 0.2;
    c.orthographic.znear = 0.01, c.orthographic.zfar = 100.0;
  }
  const std::string name = orthographic ? "orthographic" : "perspective";
  const fs::path file = test::scratchDir("camera-" + name) / (name + ".gltf");
  scenes::writeModel(m, file.string());
  return file;
}

// The pixels whose albedo is the red wall's.
size_t redWallPixels(const fs::path& exr) {
  const auto r = test::channelOf(exr, "albedo.R"), g = test::channelOf(exr, "albedo.G");
  size_t red = 0;
  for (size_t i = 0; i < r.size(); ++i) red += r[i] > 0.4f && g[i] < 0.2f;
  return red;
}

}  // namespace

TEST(OrthographicCamera, IsReadWithItsExtentAndClipRange) {
  const scene::Scene s = scene::loadGltf(cornellView(true).string());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_TRUE(s.cameras[0].orthographic);
  EXPECT_FLOAT_EQ(s.cameras[0].ymag, 0.2f);
  EXPECT_FLOAT_EQ(s.cameras[0].zfar, 100.0f);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
}

// Its rays run parallel to the view: the box's side walls, parallel to it, vanish edge-on where the
// perspective camera sees the red one over a tenth of the image. The path tracer, iv and ar render
// the same view: each solver's error against the path tracer (256 samples a pixel) is below its
// error in perspective, where the walls' edges alias (there 0.0068, orthographic 0.0021).
TEST(OrthographicCamera, SideWallsVanishEdgeOnInEveryMethod) {
  double perspectiveError[2] = {};
  for (const bool orthographic : {false, true}) {
    const fs::path scene = cornellView(orthographic);
    const std::string name = orthographic ? "ortho" : "persp";
    const fs::path pt =
        test::renderExr(name + "-pt", {scene.string(), "--method", "pt", "--spp", "256", "--size", "64x48"});
    const size_t red = redWallPixels(pt);
    if (orthographic)
      EXPECT_EQ(red, 0u) << "the red wall seen edge-on";
    else
      EXPECT_GT(red, 64u * 48u / 10u) << "the red wall seen in perspective";
    const image::RgbImage reference = image::readLinearRgb(pt.string());
    int k = 0;
    for (const char* method : {"iv", "ar"}) {
      const fs::path exr =
          test::renderExr(name + "-" + method, {scene.string(), "--method", method, "--size", "64x48"});
      // The same pixels as the path tracer's, but for the wall's edges, which its jittered samples
      // share with the next surface where one sample a pixel takes either.
      EXPECT_NEAR(double(redWallPixels(exr)), double(red), 48.0) << method;
      const double error = image::measureError(image::readLinearRgb(exr.string()), reference).relMse;
      std::printf("[ camera ] %s, %s against pt: relMSE %.5f\n", name.c_str(), method, error);
      if (!orthographic)
        perspectiveError[k] = error;
      else
        EXPECT_LT(error, perspectiveError[k]) << method;
      ++k;
    }
  }
}

// A glossy surface reflects toward an orthographic camera along the view's axis, not toward a
// point. A rough metal floor under a point lamp at (0, 1, 0), seen from (0, 1, 2) looking 26.6°
// down: the lamp's highlight lies where its mirror direction is the view's, at z = 2 (for an eye
// at the camera's origin it would lie at z = 1). iv and ar put it where the path tracer does, as
// bright.
TEST(OrthographicCamera, AHighlightLiesWhereTheViewsAxisMirrorsTheLamp) {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {-2, 0, -2}, {2, 0, -2}, {2, 0, 3}, {-2, 0, 3}, 8, 10, {0, 1, 0});
  b.node("floor", b.mesh("floor", {{floor, b.glossyMaterial("metal", glm::vec3(0.9f, 0.7f, 0.5f), 1.0f, 0.25f)}}));
  b.light("lamp", "point", 4.0f, {0, 1, 0});
  b.camera("camera", 0.9f, 0.01f, {0, 1, 2}, glm::angleAxis(-std::atan(0.5f), glm::vec3(1, 0, 0)));
  tinygltf::Model m = b.finish();
  tinygltf::Camera& c = m.cameras[0];
  c.type = "orthographic";
  c.orthographic.xmag = 1.6, c.orthographic.ymag = 1.2, c.orthographic.znear = 0.01, c.orthographic.zfar = 10.0;
  const fs::path scene = test::scratchDir("ortho-highlight") / "ortho-highlight.gltf";
  scenes::writeModel(m, scene.string());

  auto brightest = [](const image::RgbImage& im) {
    size_t at = 0;
    for (size_t i = 0; i < im.pixels.size(); ++i)
      if (im.pixels[i].g > im.pixels[at].g) at = i;
    return at;
  };
  const image::RgbImage pt = image::readLinearRgb(
      test::renderExr("highlight-pt", {scene.string(), "--method", "pt", "--spp", "16", "--size", "96x72"}).string());
  const size_t peak = brightest(pt);
  // (0, 0, 2) lies 0.894 m below the view's centre along its up axis: ndc −0.745, row 62.8 of 72.
  EXPECT_NEAR(double(peak % 96), 47.5, 3.0) << "on the middle column";
  EXPECT_NEAR(double(peak / 96), 62.8, 3.0) << "where the view's axis mirrors the lamp";
  for (const char* method : {"iv", "ar"}) {
    const image::RgbImage im = image::readLinearRgb(
        test::renderExr(std::string("highlight-") + method, {scene.string(), "--method", method, "--size", "96x72"})
            .string());
    const size_t at = brightest(im);
    std::printf("[ camera ] orthographic highlight, %s: pixel (%zu, %zu), %.4f; pt (%zu, %zu), %.4f\n", method, at % 96,
                at / 96, im.pixels[at].g, peak % 96, peak / 96, pt.pixels[peak].g);
    EXPECT_NEAR(double(at % 96), double(peak % 96), 2.0) << method;
    EXPECT_NEAR(double(at / 96), double(peak / 96), 2.0) << method;
    EXPECT_NEAR(im.pixels[peak].g, pt.pixels[peak].g, 0.05 * pt.pixels[peak].g) << method;
  }
}

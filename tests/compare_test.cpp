// `ivgi compare` as a CI gate: exit 0 when every limit holds for every frame, 1 when a limit fails
// (one line naming it) or a frame is missing, 2 when the comparison cannot be made; sequences paired
// by name or number; one JSON report with images of the failing frames only.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "engine/image/frame_image.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

// A frame with every layer ivgi writes: a smooth gradient of radiance `scale` times its base.
image::FrameChannels frame(uint32_t width, uint32_t height, float scale) {
  image::FrameChannels f;
  f.width = width, f.height = height;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const float u = (x + 0.5f) / float(width), v = (y + 0.5f) / float(height);
      f.radiance.emplace_back(scale * glm::vec3(0.2f + u, 0.3f + v, 0.5f), 1.0f);
      f.albedo.emplace_back(0.5f, 0.4f, 0.3f, 1.0f);
      f.normalDepth.emplace_back(0.0f, 1.0f, 0.0f, 2.0f + u);
      f.emission.emplace_back(0.0f);
    }
  return f;
}

// Frames 0..count-1 of a sequence, each `scale` times the base (`dimmed`: that frame 5 % darker).
fs::path sequence(const std::string& name, int count, int dimmed = -1, uint32_t width = 24) {
  const fs::path dir = test::scratchDir(name);
  for (int i = 0; i < count; ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "f_%04d.exr", i);
    image::writeExr((dir / file).string(), frame(width, 16, i == dimmed ? 0.95f : 1.0f));
  }
  return dir;
}

struct Compared {
  test::Run run;
  nlohmann::json report;
  fs::path reportPath;
};

Compared compare(const fs::path& test, const fs::path& reference, std::vector<std::string> limits) {
  const fs::path report = test::scratchDir("report") / "report.json";
  limits.insert(limits.begin(), {"compare", test.string(), reference.string(), "--json", report.string()});
  Compared c{test::runIvgi(limits), nullptr, report};
  if (fs::exists(report)) c.report = nlohmann::json::parse(std::ifstream(report));
  return c;
}

}  // namespace

TEST(CompareGate, ADimmerImageFailsNamingTheLimit) {
  const fs::path ref = sequence("ref", 1), dim = sequence("dim", 1, 0);
  const fs::path a = ref / "f_0000.exr", b = dim / "f_0000.exr";
  EXPECT_EQ(compare(a, a, {"--max-relmse", "0", "--max-flip", "0", "--max-pixel-error", "0"}).run.status, 0);
  for (const std::vector<std::string>& limit : {std::vector<std::string>{"--max-relmse", "1e-4"},
                                                {"--max-flip", "0.001"},
                                                {"--max-pixel-error", "0.01"},
                                                {"--pixel-tol", "0.02", "--max-failing", "1%"}}) {
    Compared c = compare(b, a, limit);
    EXPECT_EQ(c.run.status, 1) << limit[0] << "\n" << c.run.out << c.run.err;
    const std::string named = limit[0] == "--pixel-tol" ? "--max-failing" : limit[0];
    EXPECT_NE(c.run.out.find("FAIL "), std::string::npos) << c.run.out;
    EXPECT_NE(c.run.out.find(named), std::string::npos) << "the failing limit is named: " << c.run.out;
    EXPECT_NE(c.run.out.find("(by "), std::string::npos) << "and by how much: " << c.run.out;
    EXPECT_EQ(c.report["status"], 1);
    EXPECT_EQ(c.report["frames"][0]["status"], "fail");
  }
  // 5 % darker passes a tolerance above it.
  EXPECT_EQ(compare(b, a, {"--pixel-tol", "0.06", "--max-failing", "0"}).run.status, 0);
}

TEST(CompareGate, AMatchingSequencePassesAndADimmedFrameIsNamed) {
  const fs::path ref = sequence("ref", 4), same = sequence("same", 4), dim = sequence("dim", 4, 2);
  Compared pass = compare(same, ref, {"--golden", "--max-relmse", "1e-6"});
  EXPECT_EQ(pass.run.status, 0) << pass.run.out << pass.run.err;
  EXPECT_NE(pass.run.out.find("4 frames: 4 pass, 0 fail, 0 missing"), std::string::npos) << pass.run.out;
  EXPECT_EQ(pass.report["frames"].size(), 4u);
  EXPECT_FALSE(fs::exists(pass.reportPath.parent_path() / "report-heatmaps")) << "no images for passing frames";

  Compared fail = compare(dim, ref, {"--golden"});
  EXPECT_EQ(fail.run.status, 1);
  EXPECT_NE(fail.run.out.find("f_0002.exr: FAIL RGB: "), std::string::npos) << fail.run.out;
  EXPECT_EQ(std::count(fail.run.out.begin(), fail.run.out.end(), '\n'), 3)
      << "one line a failing frame, one summary, one of the temporal measure";
  EXPECT_NE(fail.run.out.find("temporal: relMSE of the frame-to-frame change"), std::string::npos) << fail.run.out;
  const auto& frames = fail.report["frames"];
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(frames[i]["status"], i == 2 ? "fail" : "pass") << i;
    EXPECT_EQ(frames[i].contains("heatmap"), i == 2) << "a heatmap for the failing frame only";
  }
  EXPECT_TRUE(fs::exists(frames[2]["heatmap"].get<std::string>()));
  EXPECT_TRUE(fs::exists(frames[2]["ratio"].get<std::string>()));
}

TEST(CompareGate, AMissingFrameFailsOnEitherSide) {
  const fs::path ref = sequence("ref", 3), test = sequence("test", 3);
  fs::remove(test / "f_0001.exr");
  Compared c = compare(test, ref, {"--golden"});
  EXPECT_EQ(c.run.status, 1);
  EXPECT_NE(c.run.out.find("f_0001.exr: FAIL missing from " + test.string()), std::string::npos) << c.run.out;
  fs::copy_file(ref / "f_0002.exr", test / "f_0007.exr");
  fs::copy_file(ref / "f_0000.exr", test / "f_0001.exr");
  c = compare(test, ref, {});
  EXPECT_EQ(c.run.status, 1) << "no limits, but a frame the reference lacks";
  EXPECT_NE(c.run.out.find("f_0007.exr: FAIL missing from " + ref.string()), std::string::npos) << c.run.out;
  // Patterns pair by frame number whatever the names around it.
  const fs::path renamed = test::scratchDir("renamed");
  for (int i = 0; i < 3; ++i)
    fs::copy_file(ref / ("f_000" + std::to_string(i) + ".exr"), renamed / ("shot." + std::to_string(i) + ".exr"));
  c = compare(renamed / "shot.%d.exr", ref / "f_%04d.exr", {"--golden"});
  EXPECT_EQ(c.run.status, 0) << c.run.out << c.run.err;
  EXPECT_EQ(c.report["frames"][2]["name"], "frame 2");
}

TEST(CompareGate, AComparisonThatCannotBeMadeIsStatusTwo) {
  const fs::path ref = sequence("ref", 1), wide = sequence("wide", 1, -1, 32);
  Compared size = compare(wide / "f_0000.exr", ref / "f_0000.exr", {"--golden"});
  EXPECT_EQ(size.run.status, 2);
  ASSERT_EQ(size.run.errLines().size(), 1u) << size.run.err;
  EXPECT_NE(size.run.err.find("32x16"), std::string::npos) << size.run.err;

  // A NaN in the test image.
  const fs::path nan = test::scratchDir("nan") / "f_0000.exr";
  {
    OIIO_NAMESPACE::ImageBuf buf((ref / "f_0000.exr").string());
    ASSERT_TRUE(buf.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT));
    buf.setpixel(3, 4, std::vector<float>(buf.spec().nchannels, std::numeric_limits<float>::quiet_NaN()).data());
    ASSERT_TRUE(buf.write(nan.string()));
  }
  Compared c = compare(nan, ref / "f_0000.exr", {"--max-relmse", "1"});
  EXPECT_EQ(c.run.status, 2);
  EXPECT_NE(c.run.err.find("NaN"), std::string::npos) << c.run.err;
  EXPECT_FALSE(fs::exists(c.reportPath)) << "no report of a comparison that was not made";

  // A missing file, a file against a folder, an option that cannot be read: 2 as well.
  EXPECT_EQ(compare(ref / "nope.exr", ref / "f_0000.exr", {}).run.status, 2);
  EXPECT_EQ(compare(ref / "f_0000.exr", ref, {}).run.status, 2);
  EXPECT_EQ(compare(ref, ref, {"--max-failing", "abc"}).run.status, 2);
  EXPECT_EQ(compare(ref, ref, {"--layers", "depth"}).run.status, 2);
}

// Golden images on lavapipe: every channel of the built-in Cornell box at two frames and of
// animated assets, against references in tests/golden/, through `ivgi compare --golden`, the gate
// users get. To regenerate them after an intended change:
//   IVGI_UPDATE_GOLDEN=1 build/tests/ivgi_tests --gtest_filter='Golden.*'
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

fs::path goldenDir() { return fs::path(IVGI_SOURCE_DIR) / "tests" / "golden"; }

// Renders with `args` to one EXR and returns its path.
fs::path render(const std::string& name, std::vector<std::string> args) {
  auto dir = test::scratchDir(name);
  args.insert(args.begin(), "render");
  args.insert(args.end(),
              {"--format", "exr", "--out", (dir / name).string() + ".exr", "--json", (dir / "sidecar.json").string()});
  auto r = test::runIvgi(args);
  EXPECT_EQ(r.status, 0) << r.err;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".exr") return entry.path();
  ADD_FAILURE() << "no EXR written for " << name;
  return {};
}

// `ivgi compare TEST REF ARGS…` and its JSON report.
std::pair<test::Run, nlohmann::json> compare(const fs::path& test, const fs::path& reference,
                                             std::vector<std::string> args) {
  const fs::path report = test::scratchDir("compare") / "report.json";
  args.insert(args.begin(), {"compare", test.string(), reference.string(), "--json", report.string()});
  test::Run r = test::runIvgi(args);
  nlohmann::json j;
  if (fs::exists(report)) j = nlohmann::json::parse(std::ifstream(report));
  return {r, j};
}

void expectMatchesGolden(const std::string& name, const std::vector<std::string>& args) {
  fs::path result = render(name, args);
  fs::path golden = goldenDir() / (name + ".exr");
  if (const char* update = std::getenv("IVGI_UPDATE_GOLDEN"); update && std::string(update) == "1") {
    fs::copy_file(result, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "updated " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; see the header of tests/golden_test.cpp";
  auto [r, report] = compare(result, golden, {"--golden"});
  EXPECT_EQ(r.status, 0) << name << ":\n" << r.out << r.err;
}

// The foundation's channels: emission-only radiance (--method none) and the geometry layers.
const std::vector<std::string> kCornell = {"cornell", "--cells", "8", "--size", "160x120", "--method", "none"};

}  // namespace

TEST(Golden, CornellBoxFrame0) {
  auto args = kCornell;
  args.insert(args.end(), {"--frames", "0"});
  expectMatchesGolden("cornell_f0000", args);
}

TEST(Golden, CornellBoxFrame24) {
  auto args = kCornell;
  args.insert(args.end(), {"--frames", "24", "--supersample", "2"});
  expectMatchesGolden("cornell_f0024_ss2", args);
}

TEST(Golden, AnimatedMorphCube) {
  auto path = test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  expectMatchesGolden("morphcube_f0030", {path.string(), "--frames", "30", "--size", "128x96", "--method", "none"});
}

TEST(Golden, TexturedSkinnedFox) {
  auto dir = test::sharedGltfDir();
  if (!dir) GTEST_SKIP() << "../shared/data/gltf is not present";
  expectMatchesGolden("fox_run_f0010", {(*dir / "Fox.gltf").string(), "--animation", "Run", "--frames", "10", "--size",
                                        "160x120", "--method", "none"});
}

// The iv solver's images: the Cornell box (area light, interreflection), its glossy variant, and the
// morph cube lit by a constant environment.
TEST(Golden, IvCornellBox) {
  expectMatchesGolden("iv_cornell_f0012",
                      {"cornell", "--cells", "6", "--bins", "8", "--size", "128x96", "--frames", "12"});
}

// The glossy box, animated: the metal block and the polished floor reflect the direct light per
// pixel and the indirect light through iv's links.
TEST(Golden, IvGlossyCornellBox) {
  expectMatchesGolden("iv_glossy_cornell_f0012",
                      {"cornell", "--glossy", "--cells", "6", "--bins", "8", "--size", "128x96", "--frames", "12"});
}

TEST(Golden, IvMorphCubeUnderEnvironment) {
  auto path = test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  expectMatchesGolden("iv_morphcube_env_f0030",
                      {path.string(), "--frames", "30", "--size", "96x72", "--bins", "8", "--env", "0.8,0.9,1.0"});
}

// The comparison itself must reject a visibly different image: the moving block at another frame,
// and a 5 % change of one layer.
TEST(Golden, VisiblyDifferentImagesFail) {
  auto args = kCornell;
  args.insert(args.end(), {"--frames", "12"});
  fs::path moved = render("moved", args);
  fs::path golden = goldenDir() / "cornell_f0000.exr";
  ASSERT_TRUE(fs::exists(golden));
  EXPECT_EQ(compare(moved, golden, {"--golden"}).first.status, 1) << "frame 12 passed as frame 0";

  auto same = kCornell;
  same.insert(same.end(), {"--frames", "0"});
  fs::path f0 = render("f0", same);
  const std::vector<std::string> albedoRule = {"--layers", "albedo", "--pixel-tol", "0.02", "--max-failing", "0.2%"};
  EXPECT_EQ(compare(f0, golden, albedoRule).first.status, 0);
  // The same image with albedo brightened by 5 %: must fail.
  fs::path brighter = f0.parent_path() / "brighter.exr";
  {
    OIIO_NAMESPACE::ImageBuf buf(f0.string());
    ASSERT_TRUE(buf.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT));
    std::vector<int> albedo;
    for (const char* name : {"albedo.R", "albedo.G", "albedo.B"}) albedo.push_back(buf.spec().channelindex(name));
    for (OIIO_NAMESPACE::ImageBuf::Iterator<float> it(buf); !it.done(); ++it)
      for (int c : albedo) it[c] = it[c] * 1.05f;
    ASSERT_TRUE(buf.write(brighter.string()));
  }
  auto [r, report] = compare(brighter, golden, albedoRule);
  EXPECT_EQ(r.status, 1) << "a 5 % brighter albedo passed";
  EXPECT_NE(r.out.find("FAIL albedo: "), std::string::npos) << r.out;
}

// The radiance is held to each pixel's own value: the indirect light of the iv Cornell box dimmed by
// 5 % must fail although it is a few thousandths of the light's radiance.
TEST(Golden, DimmerIndirectLightFails) {
  fs::path golden = goldenDir() / "iv_cornell_f0012.exr";
  ASSERT_TRUE(fs::exists(golden));
  fs::path dimmer = test::scratchDir("dimmer") / "dimmer.exr";
  {
    OIIO_NAMESPACE::ImageBuf buf(golden.string());
    ASSERT_TRUE(buf.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT));
    int emission = buf.spec().channelindex("emission.R");
    for (OIIO_NAMESPACE::ImageBuf::Iterator<float> it(buf); !it.done(); ++it)
      if (it[emission] == 0.0f)
        for (int c = 0; c < 3; ++c) it[c] = it[c] * 0.95f;
    ASSERT_TRUE(buf.write(dimmer.string()));
  }
  EXPECT_EQ(compare(golden, golden, {"--golden"}).first.status, 0);
  auto [r, report] = compare(dimmer, golden, {"--golden"});
  EXPECT_EQ(r.status, 1) << "5 % less indirect light passed";
  const auto& rgb = report["frames"][0]["layers"][0];
  EXPECT_EQ(rgb["layer"], "RGB");
  EXPECT_GT(rgb["failingPercent"].get<double>(), 50.0);
}

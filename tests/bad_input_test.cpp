// Bad input through the ivgi binary: one clear line naming the file and the problem, a non-zero
// exit, and nothing written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <tuple>

#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

void expectOneLineError(const test::Run& r, const std::vector<std::string>& mentions) {
  EXPECT_NE(r.status, 0);
  auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("ivgi: error: ", 0), 0u) << lines[0];
  for (const auto& m : mentions)
    EXPECT_NE(lines[0].find(m), std::string::npos) << "'" << m << "' missing from: " << lines[0];
}

size_t filesIn(const fs::path& dir) {
  if (!fs::exists(dir)) return 0;
  return size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// Renders `scene` into a fresh folder; expects the error and that nothing was written there.
void expectRenderRefused(const std::string& scene, const std::vector<std::string>& extra,
                         const std::vector<std::string>& mentions) {
  auto out = test::scratchDir("out");
  std::vector<std::string> args = {"render", scene, "--out", (out / "f_%04d").string()};
  if (std::find(extra.begin(), extra.end(), "--size") == extra.end()) args.insert(args.end(), {"--size", "16x16"});
  args.insert(args.end(), extra.begin(), extra.end());
  expectOneLineError(test::runIvgi(args), mentions);
  EXPECT_EQ(filesIn(out), 0u) << "nothing may be written";
}

std::string writeModel(tinygltf::Model model, const std::string& name) {
  auto path = test::scratchDir("model") / name;
  scenes::writeModel(model, path.string());
  return path.string();
}

tinygltf::Model triangleModel(glm::vec3 corner = glm::vec3(0, 1, 0)) {
  scenes::MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, corner};
  m.indices = {0, 1, 2};
  scenes::GltfBuilder b;
  b.node("triangle", b.mesh("triangle", {{m, b.material("grey", glm::vec3(0.5f))}}));
  return b.finish();
}

}  // namespace

TEST(BadInput, MissingFile) {
  expectRenderRefused("/nonexistent/scene.gltf", {}, {"/nonexistent/scene.gltf", "no such file"});
}

// Found while writing the options fuzzer: `compare /dev/zero /dev/zero` read forever. A device or a pipe has
// no end to read to: compare, --env and a glTF path refuse it in one line.
TEST(BadInput, ADeviceFileIsRefusedNotReadForever) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  expectOneLineError(test::runIvgi({"compare", "/dev/zero", "/dev/zero"}), {"/dev/zero", "not a regular file"});
  expectRenderRefused("cornell", {"--env", "/dev/zero"}, {"/dev/zero"});
  expectRenderRefused("/dev/zero", {}, {"/dev/zero", "not a regular file"});
}

TEST(BadInput, NotAGltfFile) {
  auto path = test::scratchDir("in") / "notes.gltf";
  std::ofstream(path) << "these are not the droids you are looking for\n";
  expectRenderRefused(path.string(), {}, {path.string(), "invalid glTF"});
  const auto empty = test::scratchDir("in") / "empty.gltf";
  std::ofstream{empty};
  expectRenderRefused(empty.string(), {}, {empty.string(), "invalid glTF: the file is empty"});
}

TEST(BadInput, CorruptedEmbeddedBuffer) {
  // A broken base64 data URI: the message names the file and stays one short line.
  tinygltf::Model m = scenes::cornellBox({.cells = 2});
  std::string path = writeModel(m, "cornell.gltf");
  std::string text;
  {
    std::ifstream in(path);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  size_t at = text.find("base64,");
  ASSERT_NE(at, std::string::npos);
  text.replace(at + 100, 3, "!!!");
  std::ofstream(path) << text;
  auto r = test::runIvgi({"info", path});
  expectOneLineError(r, {path, "invalid glTF"});
  EXPECT_LT(r.err.size(), 400u) << r.err;
}

// A Draco-compressed mesh's accessors have no buffer view of their own, which tinygltf refuses
// before ivgi sees the model: the message names the extension, not tinygltf's complaint.
TEST(BadInput, DracoCompressedMeshNamesItsExtension) {
  tinygltf::Model m = triangleModel();
  m.accessors[m.meshes[0].primitives[0].indices].bufferView = -1;
  m.extensionsUsed.push_back("KHR_draco_mesh_compression");
  m.extensionsRequired.push_back("KHR_draco_mesh_compression");
  std::string path = writeModel(m, "draco.gltf");
  expectRenderRefused(path, {}, {path, "requires the unsupported extension KHR_draco_mesh_compression"});
}

TEST(BadInput, TruncatedGlb) {
  std::string path = writeModel(scenes::cornellBox({.cells = 2}), "cornell.glb");
  fs::resize_file(path, fs::file_size(path) / 2);
  expectRenderRefused(path, {}, {path, "invalid .glb"});
}

TEST(BadInput, AccessorOutOfRange) {
  tinygltf::Model m = triangleModel();
  m.accessors[m.meshes[0].primitives[0].attributes["POSITION"]].count = 1000;
  std::string path = writeModel(m, "accessor.gltf");
  expectRenderRefused(path, {}, {path, "POSITION", "past the end of buffer view"});
}

// A count far past the data (a few bytes declaring terabytes, or a count whose product with the
// stride wraps around) is refused by the check of the buffer view, before anything is sized by it
// (sized first, 10^12 positions asked for 12 TB and ended in std::bad_alloc).
TEST(BadInput, AccessorCountFarPastItsDataIsRefusedBeforeAnythingIsSized) {
  for (size_t count : {size_t(1000000000000ull), size_t(1) << 62}) {
    tinygltf::Model m = triangleModel();
    m.accessors[m.meshes[0].primitives[0].attributes["POSITION"]].count = count;
    std::string path = writeModel(m, "huge.gltf");
    auto r = test::runIvgi({"info", path});
    expectOneLineError(r, {path, "POSITION", "past the end of buffer view"});
  }
}

// A buffer declaring 4 GiB over a 48-byte file (docs/notes/extremes.md): refused by its size against
// the file's, before anything is allocated for it.
TEST(BadInput, ABufferDeclaringFourGibibytesOverASmallFileIsRefused) {
  const fs::path dir = test::scratchDir("huge_buffer");
  std::ofstream(dir / "small.bin", std::ios::binary) << std::string(48, '\0');
  const std::string path = (dir / "huge.gltf").string();
  std::ofstream(path) << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [0, 0, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": "small.bin", "byteLength": 4294967296}]})";
  expectOneLineError(test::runIvgi({"info", path}), {path, "4294967296"});
  expectRenderRefused(path, {}, {path, "4294967296"});
}

// A PNG and a JPEG whose headers declare 100,000² and 60,000² pixels (a few dozen bytes each):
// refused by their headers, before their pixels are allocated (stb_image had answered "Unknown image
// format" to the PNG).
TEST(BadInput, AnImageDeclaringMorePixelsThanTheLimitIsRefusedBeforeItIsDecoded) {
  const fs::path dir = test::scratchDir("huge_image");
  using test::bigEndian;
  // The PNG's chunks carry no valid CRCs: nothing reads past the header.
  const std::string png = "\x89PNG\r\n\x1a\n" + bigEndian(13, 4) + "IHDR" + bigEndian(100000, 4) +
                          bigEndian(100000, 4) + std::string("\x08\x02\x00\x00\x00", 5) + bigEndian(0, 4);
  // The JPEG: start of image, an APP0 segment to skip, a baseline start of frame (height, width).
  const std::string jpeg = std::string("\xFF\xD8\xFF\xE0", 4) + bigEndian(6, 2) + "JFIF" + std::string("\xFF\xC0", 2) +
                           bigEndian(17, 2) + std::string("\x08", 1) + bigEndian(60000, 2) + bigEndian(60000, 2) +
                           std::string("\x03", 1);
  for (const auto& [file, bytes, size] :
       {std::tuple{"huge.png", png, "100000x100000"}, std::tuple{"huge.jpg", jpeg, "60000x60000"}}) {
    std::ofstream(dir / file, std::ios::binary) << bytes;
    tinygltf::Model m = triangleModel();
    tinygltf::Image image;
    image.uri = file;
    m.images.push_back(image);
    tinygltf::Texture texture;
    texture.source = 0;
    m.textures.push_back(texture);
    m.materials[0].pbrMetallicRoughness.baseColorTexture.index = 0;
    const std::string path = (dir / (std::string(file) + ".gltf")).string();
    scenes::writeModel(m, path);
    expectOneLineError(test::runIvgi({"info", path}), {path, "image 0", size, "--max-texels"});
  }
}

// Found by the glTF fuzzer (build-fuzz/crash-bd5f06da…): an image in a buffer view that reaches
// past its buffer. tinygltf hands the image decoder the view's bytes without checking them against
// the buffer, and stb_image read past its end (a heap overflow under AddressSanitizer).
TEST(BadInput, AnImagesBufferViewPastItsBufferIsRefusedBeforeItIsDecoded) {
  tinygltf::Model m = triangleModel();
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = 0;
  view.byteLength = m.buffers[0].data.size() + 4096;
  m.bufferViews.push_back(view);
  tinygltf::Image image;
  image.bufferView = int(m.bufferViews.size()) - 1;
  image.mimeType = "image/png";
  m.images.push_back(image);
  tinygltf::Texture texture;
  texture.source = 0;
  m.textures.push_back(texture);
  m.materials[0].pbrMetallicRoughness.baseColorTexture.index = 0;
  const std::string path = writeModel(m, "image-view.gltf");
  expectOneLineError(test::runIvgi({"info", path}),
                     {path, "image 0's buffer view", "reaches past the end of buffer 0"});
}

TEST(BadInput, BufferViewOutOfRange) {
  tinygltf::Model m = triangleModel();
  auto& view = m.bufferViews[m.accessors[m.meshes[0].primitives[0].attributes["POSITION"]].bufferView];
  view.byteOffset = m.buffers[0].data.size() - 4;
  std::string path = writeModel(m, "view.gltf");
  auto r = test::runIvgi({"info", path});
  expectOneLineError(r, {path});
  EXPECT_NE(r.err.find("buffer"), std::string::npos);
}

TEST(BadInput, IndexOutOfRange) {
  tinygltf::Model m = triangleModel();
  uint32_t* idx = reinterpret_cast<uint32_t*>(
      m.buffers[0].data.data() + m.bufferViews[m.accessors[m.meshes[0].primitives[0].indices].bufferView].byteOffset);
  idx[2] = 77;
  std::string path = writeModel(m, "index.gltf");
  expectRenderRefused(path, {}, {path, "index 77 out of range"});
}

TEST(BadInput, NanAndInfInVertexAttributes) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::string path = writeModel(triangleModel(glm::vec3(0, bad, 0)), "nan.gltf");
    expectRenderRefused(path, {}, {path, "POSITION", "NaN or infinite"});
  }
}

TEST(BadInput, NoTrianglesAtAll) {
  tinygltf::Model m = triangleModel();
  m.meshes[0].primitives[0].mode = TINYGLTF_MODE_POINTS;
  std::string path = writeModel(m, "points.gltf");
  auto out = test::scratchDir("out");
  auto r = test::runIvgi({"render", path, "--out", (out / "f").string()});
  EXPECT_NE(r.status, 0);
  // The error is the last line; it names the problem and what the loader skipped that was why.
  auto lines = r.errLines();
  ASSERT_FALSE(lines.empty());
  using testing::HasSubstr;
  EXPECT_THAT(lines.back(),
              testing::AllOf(HasSubstr(path), HasSubstr("no triangles"), HasSubstr("draws points or lines")));
  EXPECT_EQ(filesIn(out), 0u);
}

TEST(BadInput, ImageSizeZeroOrAboveTheDeviceLimits) {
  expectRenderRefused("cornell", {"--size", "0x240"}, {"--size", "at least 1"});
  expectRenderRefused("cornell", {"--size", "100000x100000"}, {"--size", "exceeds the device limit"});
  expectRenderRefused("cornell", {"--size", "8000x8000", "--supersample", "4"}, {"maxStorageBufferRange"});
  expectRenderRefused("cornell", {"--size", "big"}, {"--size", "WIDTHxHEIGHT"});
}

TEST(BadInput, FrameRangeOutsideTheAnimation) {
  expectRenderRefused("cornell", {"--frames", "40-60"}, {"built-in cornell", "frames 40-60", "outside", "frames 0-48"});
  expectRenderRefused("cornell", {"--frames", "9-3"}, {"--frames", "before the first"});
  std::string still = writeModel(triangleModel(), "still.gltf");
  expectRenderRefused(still, {"--frames", "0-1"}, {still, "without animation"});
}

TEST(BadInput, AbsurdOptions) {
  expectRenderRefused("cornell", {"--fps", "0"}, {"--fps"});
  expectRenderRefused("cornell", {"--fps", "nan"}, {"--fps"});
  expectRenderRefused("cornell", {"--supersample", "100"}, {"--supersample"});
  expectRenderRefused("cornell", {"--cells", "0"}, {"--cells"});
  expectRenderRefused("cornell", {"--format", "jpg"}, {"--format"});
  expectRenderRefused("cornell", {"--device", "no such gpu"}, {"no Vulkan device matches 'no such gpu'"});
  expectRenderRefused("cornell", {"--camera", "nope"},
                      {"no camera named or numbered 'nope' (1 camera, numbered 0 to 0"});
  expectRenderRefused("cornell", {"--camera", "5"}, {"no camera named or numbered '5'"});
  expectRenderRefused("cornell", {"--animation", "nope"},
                      {"no animation named or numbered 'nope' (1 animation, numbered 0 to 0"});
  expectRenderRefused("cornell", {"--direct", "rays"}, {"--direct rays"});
  expectRenderRefused("cornell", {"--direct", "maps", "--method", "pt"}, {"--direct maps", "only iv and ar"});
  expectRenderRefused("cornell", {"--direct", "maps", "--light-samples", "0"}, {"--light-samples 0"});
  expectRenderRefused("cornell", {"--direct", "maps", "--shadow-map", "1"}, {"--shadow-map 1"});
  expectRenderRefused("cornell", {"--direct", "maps", "--light-samples", "4096", "--shadow-map", "4096"},
                      {"--light-samples 4096 with --shadow-map 4096", "maxStorageBufferRange"});
  expectRenderRefused("cornell", {"--env", "1,1,1", "--env-directions", "5000"}, {"--env-directions 5000"});
  expectRenderRefused("cornell", {"--env", "-1,0,0"}, {"--env '-1,0,0'", "at least 0"});
  expectRenderRefused("cornell", {"--env", "3e38,0,0"}, {"--env '3e38,0,0'", "below 1e30"});
  expectRenderRefused(
      "cornell", {"--env", "1,1,1", "--env-directions", "4096", "--shadow-map", "4096"},
      {"--light-samples 128 and --env-directions 4096 with --shadow-map 4096", "maxStorageBufferRange"});
}

TEST(BadInput, EarlierFramesSurviveAFailedRun) {
  auto out = test::scratchDir("out");
  std::string pattern = (out / "f_%04d").string();
  auto ok = test::runIvgi({"render", "--size", "32x24", "--frames", "0-1", "--out", pattern});
  ASSERT_EQ(ok.status, 0) << ok.err;
  auto before = fs::file_size(out / "f_0000.exr");
  auto failed = test::runIvgi({"render", "--size", "0x24", "--frames", "0-1", "--out", pattern});
  EXPECT_NE(failed.status, 0);
  EXPECT_EQ(fs::file_size(out / "f_0000.exr"), before);
  EXPECT_TRUE(fs::exists(out / "f_0001.png"));
}

// What a run writes at its end (render's sidecar, bench's and compare's --json, the sweep's
// tables) was first tried once every frame had rendered: a --json naming a folder failed the run
// at its end. Each is now checked before the first frame; a missing folder is made, as the
// frames' own is.
TEST(BadInput, WhatARunWritesAtItsEndIsCheckedBeforeItsFirstFrame) {
  const fs::path dir = test::scratchDir("ends");
  const fs::path out = dir / "out", file = dir / "a_file";
  std::ofstream(file) << "not a folder";
  const std::string pattern = (out / "f_%04d").string();
  auto render = [&](const std::string& json) {
    return test::runIvgi({"render", "--size", "16x12", "--frames", "0", "--out", pattern, "--json", json});
  };
  expectOneLineError(render(dir.string()), {dir.string(), "is a directory"});
  const std::string inFile = (file / "x.json").string();
  expectOneLineError(render(inFile), {inFile, "cannot make its folder"});
  EXPECT_EQ(filesIn(out), 0u) << "no frame rendered";
  expectOneLineError(test::runIvgi({"render", "--size", "16x12", "--frames", "0", "--out", (file / "f_%04d").string()}),
                     {"cannot make its folder", file.string()});
  expectOneLineError(test::runIvgi({"bench", "--size", "16x12", "--frames", "1", "--warmup", "0", "--json", inFile}),
                     {inFile, "cannot make its folder"});

  const fs::path made = dir / "made" / "x.json";
  const test::Run ok = render(made.string());
  ASSERT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(made)) << "the sidecar's folder is made";
  ASSERT_TRUE(fs::exists(out / "f_0000.exr"));
  expectOneLineError(test::runIvgi({"sweep", "cornell", "--bins", "4", "--reference", (out / "f_0000.exr").string(),
                                    "--out", (file / "sweep").string()}),
                     {"sweep.csv", "cannot make its folder"});
  const std::string frame = (out / "f_0000.exr").string();
  expectOneLineError(test::runIvgi({"compare", frame, frame, "--json", dir.string()}),
                     {dir.string(), "is a directory"});
}

// A camera whose transform collapses its view (scaled to zero, or turned so that it looks along no
// direction) cannot frame an image: one line names the file, the camera and the problem.
TEST(BadInput, DegenerateCamera) {
  for (const auto& scale : {std::vector<double>{0, 0, 0}, std::vector<double>{1, 1, 0}}) {
    tinygltf::Model m = triangleModel();
    scenes::GltfBuilder b;
    b.model() = m;
    int cam = b.camera("flat", 0.8f, 0.01f, {0.3f, 0.3f, 2.0f}, glm::quat(1, 0, 0, 0));
    b.model().nodes[cam].scale = scale;
    std::string path = writeModel(b.finish(), "flat-camera.gltf");
    expectRenderRefused(path, {"--env", "none"}, {path, "camera 'flat'", "degenerate"});
  }
}

// An orthographic camera that spans nothing (ymag 0) or whose far plane is not beyond its near one
// (the spec requires zfar > znear ≥ 0): one line names the file, the camera and the problem.
TEST(BadInput, OrthographicCameraOfNoExtent) {
  for (const auto& [ymag, znear, zfar] : {std::tuple{0.0, 0.01, 10.0}, std::tuple{1.0, 0.5, 0.5}}) {
    scenes::GltfBuilder b;
    b.model() = triangleModel();
    b.camera("plan", 0.8f, 0.01f, {0.3f, 0.3f, 2.0f}, glm::quat(1, 0, 0, 0));
    tinygltf::Camera& c = b.model().cameras.back();
    c.type = "orthographic";
    c.orthographic.xmag = 1.0, c.orthographic.ymag = ymag, c.orthographic.znear = znear, c.orthographic.zfar = zfar;
    const std::string path = writeModel(b.finish(), "flat-orthographic.gltf");
    expectRenderRefused(path, {"--env", "none"}, {path, "camera 'plan'", "orthographic extent or clip range"});
  }
}

// Triangles of zero area only: nothing to render, said as such.
TEST(BadInput, ZeroAreaTrianglesOnly) {
  std::string path = writeModel(triangleModel(glm::vec3(2, 0, 0)), "flat-triangle.gltf");
  expectRenderRefused(path, {}, {path, "no triangles"});
}

// Files nobody here wrote: Debian's assimp-testmodels glTF 2.0 set, many of them broken on purpose
// (indices and buffers out of range, infinities, cycles, wrong types, missing buffers, no scene,
// points and lines only, Draco). Each renders a frame whose every value is finite, or is refused
// with one line naming it and leaves nothing behind; none crashes or trips the validation layers.
// The 85k-vertex engine is left to the performance tables.
TEST(RealFiles, EveryAssimpGltfRendersOrIsRefusedInOneLine) {
  const fs::path dir = test::assimpGltfDir();
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " is not installed";
  int rendered = 0, refused = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const fs::path file = entry.path();
    if ((file.extension() != ".gltf" && file.extension() != ".glb") || file.filename() == "2CylinderEngine.glb")
      continue;
    const fs::path out = test::scratchDir("assimp");
    const test::Run r = test::runIvgi({"render", file.string(), "--frames", "0", "--size", "24x18", "--format", "exr",
                                       "--out", (out / "f_%04d").string()});
    if (r.status != 0) {
      ++refused;
      expectOneLineError(r, {file.string()});
      EXPECT_EQ(filesIn(out), 0u) << file;
      continue;
    }
    ++rendered;
    OIIO_NAMESPACE::ImageBuf image((out / "f_0000.exr").string());
    ASSERT_TRUE(image.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT)) << file;
    const float* v = static_cast<const float*>(image.localpixels());
    const size_t values = size_t(image.spec().image_pixels()) * size_t(image.spec().nchannels);
    EXPECT_EQ(std::count_if(v, v + values, [](float x) { return !std::isfinite(x); }), 0) << file;
  }
  EXPECT_GE(rendered, 20);
  EXPECT_GE(refused, 15);
}

namespace {

// A floor of 8×8 cells (128 triangles) drawn by `instances` nodes a millimetre apart.
tinygltf::Model instancedFloor(int instances) {
  scenes::MeshData floor;
  const int cells = 8;
  for (int z = 0; z <= cells; ++z)
    for (int x = 0; x <= cells; ++x) floor.positions.push_back(glm::vec3(x, 0, z) / float(cells));
  for (uint32_t z = 0; z < uint32_t(cells); ++z)
    for (uint32_t x = 0; x < uint32_t(cells); ++x) {
      const uint32_t v = z * (cells + 1) + x;
      floor.indices.insert(floor.indices.end(), {v, v + cells + 1, v + 1, v + 1, v + cells + 1, v + cells + 2});
    }
  scenes::GltfBuilder b;
  const int mesh = b.mesh("floor", {{floor, b.material("grey", glm::vec3(0.5f))}});
  for (int i = 0; i < instances; ++i) b.node("floor " + std::to_string(i), mesh, glm::vec3(0, 0.001f * float(i), 0));
  return b.finish();
}

}  // namespace

// The issue's file: the floor instanced by 100,000 nodes a millimetre apart (12.8 M triangles drawn)
// kept `info` and `render` busy for minutes, tessellating. It is refused by what it draws, counted
// before anything is built; a lower limit refuses what the tessellation would reach.
TEST(BadInput, TheFloorInstancedAHundredThousandTimesIsRefusedByItsTriangles) {
  const std::string path = writeModel(instancedFloor(100000), "floors.gltf");
  const std::string drawn = std::to_string(uint64_t(100000) * 128);
  expectOneLineError(test::runIvgi({"info", path}), {path, drawn + " triangles", "--max-triangles"});
  expectRenderRefused(path, {}, {path, drawn + " triangles", "--max-triangles"});

  // The Cornell box at 2 cells draws 70 triangles and tessellates (iv) into 3,616.
  expectOneLineError(test::runIvgi({"info", "cornell", "--cells", "2", "--max-triangles", "1000"}),
                     {"tessellate", "--max-triangles"});
  const test::Run allowed = test::runIvgi({"info", "cornell", "--cells", "2", "--max-triangles", "3616"});
  EXPECT_EQ(allowed.status, 0) << allowed.err;
}

// Morph targets that share one accessor declare targets × vertices at no cost in the file: 2,000
// targets of a 20,301-vertex grid (40.6 M deltas, a gigabyte and more as read) and a floor of 81
// vertices with 20,000 targets drawn by 30 nodes (48.6 M as drawn) are refused before either is
// read or sized.
TEST(BadInput, MorphTargetsPastTheLimitAreRefusedBeforeTheyAreRead) {
  auto withTargets = [](tinygltf::Model m, int targets) {
    tinygltf::Primitive& p = m.meshes[0].primitives[0];
    p.targets.assign(size_t(targets), {{"POSITION", p.attributes.at("POSITION")}});
    m.meshes[0].weights.assign(size_t(targets), 0.0);
    return m;
  };
  scenes::MeshData grid;
  for (int z = 0; z <= 100; ++z)
    for (int x = 0; x <= 200; ++x) grid.positions.push_back(glm::vec3(x, 0, z) * 0.01f);
  grid.indices = {0, 201, 1};
  scenes::GltfBuilder b;
  b.node("grid", b.mesh("grid", {{grid, b.material("grey", glm::vec3(0.5f))}}));
  const std::string read = writeModel(withTargets(b.finish(), 2000), "read.gltf");
  expectOneLineError(test::runIvgi({"info", read}), {read, "40602000 deltas", "--max-morph-deltas"});

  tinygltf::Model drawn = withTargets(instancedFloor(30), 20000);
  const std::string drawnPath = writeModel(drawn, "drawn.gltf");
  expectOneLineError(test::runIvgi({"info", drawnPath}), {drawnPath, "48600000 morph deltas", "--max-morph-deltas"});

  // A small file passes at the default and is refused under a limit below what it draws.
  const std::string small = writeModel(withTargets(instancedFloor(2), 100), "small.gltf");
  const test::Run passes = test::runIvgi({"info", small});
  EXPECT_EQ(passes.status, 0) << passes.err;
  expectOneLineError(test::runIvgi({"info", small, "--max-morph-deltas", "10000"}), {"16200 morph deltas"});
}

// What a surface's albedo is made of besides the base colour factor: vertex colours (COLOR_0) and
// textures read through KHR_texture_transform. Each reaches every place the albedo is used: the
// surfels' albedo the solvers reflect with, the resolve's per-pixel albedo and the path tracer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "engine/image/compare.h"
#include "engine/image/metrics.h"
#include "engine/scene/geometry.h"
#include "engine/scene/gltf.h"
#include "engine/scene/texture_sampling.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

std::string writeScene(const tinygltf::Model& model, const std::string& name) {
  const fs::path path = test::scratchDir("scene-" + name) / (name + ".gltf");
  scenes::writeModel(model, path.string());
  return path.string();
}

// The model with every material's base colour moved into its primitives' COLOR_0 (as normalized
// unsigned bytes, one of the spec's forms, which holds a colour of whole 255ths exactly), the
// materials left white.
tinygltf::Model colorsInVertices(tinygltf::Model m) {
  std::vector<std::vector<double>> bases;
  for (auto& material : m.materials) {
    bases.push_back(material.pbrMetallicRoughness.baseColorFactor);
    material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  }
  scenes::GltfBuilder b;
  b.model() = std::move(m);
  for (size_t k = 0; k < b.model().meshes.size(); ++k)
    for (auto& p : b.model().meshes[k].primitives) {
      const auto& base = bases[size_t(p.material)];
      const size_t n = size_t(b.model().accessors[size_t(p.attributes.at("POSITION"))].count);
      std::vector<uint8_t> rgba;
      for (size_t v = 0; v < n; ++v)
        for (int c = 0; c < 4; ++c) rgba.push_back(uint8_t(std::lround(base[size_t(c)] * 255.0)));
      const int a = b.accessor(rgba.data(), n, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 4);
      b.model().accessors[size_t(a)].normalized = true;
      p.attributes["COLOR_0"] = a;  // accessor() grows the accessors and views, not the meshes
    }
  return b.finish();
}

// The Cornell box with its base colours rounded to 255ths, so that both forms hold the same values.
tinygltf::Model cornellIn255ths() {
  tinygltf::Model m = scenes::cornellBox({.cells = 4, .animated = false});
  for (auto& material : m.materials)
    for (double& c : material.pbrMetallicRoughness.baseColorFactor) c = std::lround(c * 255.0) / 255.0;
  return m;
}

}  // namespace

// The Cornell box coloured by its vertices renders as the box coloured by its materials: iv, ar and
// the path tracer, every layer, per pixel within 10⁻⁴ of the pixel's value (what is left is the
// interpolation's rounding of a colour equal at three vertices).
TEST(VertexColors, ColourTheBoxAsItsMaterialsDo) {
  const std::string byMaterial = writeScene(cornellIn255ths(), "by-material");
  const std::string byVertex = writeScene(colorsInVertices(cornellIn255ths()), "by-vertex");
  const std::vector<std::vector<std::string>> methods = {
      {"--method", "iv"}, {"--method", "ar"}, {"--method", "pt", "--spp", "16"}};
  for (const auto& method : methods) {
    std::vector<std::string> args = {"--size", "48x36"};
    args.insert(args.end(), method.begin(), method.end());
    std::vector<std::string> material = args, vertex = args;
    material.insert(material.begin(), byMaterial);
    vertex.insert(vertex.begin(), byVertex);
    const fs::path a = test::renderExr("material-" + method[1], material),
                   b = test::renderExr("vertex-" + method[1], vertex);
    for (const auto& d : image::compareLayers(b.string(), a.string(), image::pixelRule(image::layerNames(), 1e-4f, 0)))
      EXPECT_TRUE(d.passed) << method[1] << ", layer '" << d.layer << "': " << 100 * d.failingFraction
                            << " % of pixels beyond " << d.threshold << ", max error " << d.maxError;
  }
}

// A white floor whose colour runs from red at x = −1 to green at x = 1: the albedo layer follows the
// colour across each triangle (the camera looks straight down, so a pixel's column is its x), and the
// solver's light follows the albedo (under a white sky, red light only where the floor is red).
TEST(VertexColors, InterpolateAcrossTheSurface) {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 4, 4, {0, 1, 0});
  for (const glm::vec3& p : floor.positions) {
    const float t = 0.5f * (p.x + 1.0f);
    floor.colors.push_back({1.0f - t, t, 0.0f, 1.0f});
  }
  b.node("floor", b.mesh("floor", {{floor, b.material("white", glm::vec3(1.0f))}}));
  b.camera("down", 0.5f, 0.1f, {0, 3, 0}, glm::quatLookAtRH(glm::vec3(0, -1, 0), glm::vec3(0, 0, -1)));
  const std::string file = writeScene(b.finish(), "gradient");
  const fs::path exr = test::renderExr("gradient", {file, "--size", "64x64", "--env", "1,1,1"});
  const std::vector<float> red = test::channelOf(exr, "albedo.R"), green = test::channelOf(exr, "albedo.G"),
                           lit = test::channelOf(exr, "R"), litGreen = test::channelOf(exr, "G");
  ASSERT_EQ(red.size(), 64u * 64u);
  ASSERT_EQ(lit.size(), 64u * 64u);
  // The camera sees x within ±0.77 m at the floor (yfov 0.5 at 3 m); pixel column i at x(i).
  const float halfWidth = 3.0f * std::tan(0.25f);
  size_t checked = 0;
  for (int row : {8, 32, 56})
    for (int column = 0; column < 64; ++column) {
      const size_t i = size_t(row) * 64 + size_t(column);
      const float x = halfWidth * ((float(column) + 0.5f) / 32.0f - 1.0f), t = 0.5f * (x + 1.0f);
      EXPECT_NEAR(red[i], 1.0f - t, 2e-3f) << "row " << row << ", column " << column;
      EXPECT_NEAR(green[i], t, 2e-3f) << "row " << row << ", column " << column;
      ++checked;
    }
  EXPECT_EQ(checked, 3u * 64u);
  // Reflected light follows the albedo: red on the left edge, green on the right, each about twice
  // the other colour's a quarter of the way in.
  const size_t left = 32 * 64 + 2, right = 32 * 64 + 61;
  EXPECT_GT(lit[left], 5.0f * litGreen[left]);
  EXPECT_GT(litGreen[right], 5.0f * lit[right]);
}

// The extension's own example: offset (0, 1), rotation π/2, scale ½ reads "only the lower left
// quadrant of the source image, rotated clockwise 90°": the unit square's corners land on the
// quadrant's, the source's top-left corner at the top-right.
TEST(TextureTransform, TheSpecificationsExample) {
  const scene::TextureTransform t{{0.0f, 1.0f}, 1.57079632679f, {0.5f, 0.5f}};
  gpu::Texture record{};
  record.uvRowU = glm::vec4(t.rowU(), 0.0f), record.uvRowV = glm::vec4(t.rowV(), 0.0f);
  const std::vector<std::pair<glm::vec2, glm::vec2>> corners = {
      {{0, 0}, {0, 1}}, {{1, 0}, {0, 0.5f}}, {{0, 1}, {0.5f, 1}}, {{1, 1}, {0.5f, 0.5f}}};
  for (const auto& [uv, expected] : corners) {
    const glm::vec2 got = gpu::transformedUv(record, glm::vec4(uv, uv));
    EXPECT_NEAR(got.x, expected.x, 1e-6f) << uv.x << ", " << uv.y;
    EXPECT_NEAR(got.y, expected.y, 1e-6f) << uv.x << ", " << uv.y;
  }
}

namespace {

// A 1 m floor seen from straight above, its base colour a 2×2 texture of four colours (texture 0,
// material 0). With `secondSet`, a TEXCOORD_1 as well, of each vertex's TEXCOORD_0 through it.
tinygltf::Model fourColourFloor(const std::function<glm::vec2(glm::vec2)>& secondSet = {}) {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 1, 1, {0, 1, 0});
  if (secondSet)
    for (glm::vec2 uv : floor.uvs) floor.uvs1.push_back(secondSet(uv));
  const int material = b.material("texture", glm::vec3(1.0f));
  b.node("floor", b.mesh("floor", {{floor, material}}));
  b.camera("down", 0.5f, 0.1f, {0, 3, 0}, glm::quatLookAtRH(glm::vec3(0, -1, 0), glm::vec3(0, 0, -1)));
  tinygltf::Model m = b.finish();
  m.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture.index =
      test::addTexture(m, 2, 2, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
  return m;
}

// The floor of fourColourFloor() as `file` renders it at 64×64: its albedo at a grid of pixels is
// what the host's lookup of `texture` gives at the pixel's texture coordinates (the solvers' albedo
// is the host's), its two sets `sets(TEXCOORD_0)`. Each lookup is passed to `also`.
void expectAlbedoAsTheHostReads(
    const std::string& name, const std::string& file, const scene::Geometry& g, int texture,
    const std::function<void(glm::vec2 uv, glm::vec4 host)>& also,
    const std::function<glm::vec4(glm::vec2)>& sets = [](glm::vec2 uv) { return glm::vec4(uv, uv); }) {
  const fs::path exr = test::renderExr(name, {file, "--size", "64x64", "--env", "1,1,1", "--tessellate", "0"});
  std::vector<std::vector<float>> albedo;
  for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) albedo.push_back(test::channelOf(exr, c));
  ASSERT_EQ(albedo[0].size(), 64u * 64u);
  // The floor's UVs run with x and z (addQuad: u along p0 → p1, v along p0 → p3); the camera sees
  // x and z within ±0.77 m, x to the right and z downwards.
  const float halfWidth = 3.0f * std::tan(0.25f);
  for (int row = 4; row < 64; row += 8)
    for (int column = 4; column < 64; column += 8) {
      const float x = halfWidth * ((float(column) + 0.5f) / 32.0f - 1.0f),
                  z = halfWidth * ((float(row) + 0.5f) / 32.0f - 1.0f);
      const glm::vec2 uv(0.5f * (x + 1.0f), 0.5f * (z + 1.0f));
      const glm::vec4 host = scene::sampleTexture(g, texture, sets(uv));
      const size_t i = size_t(row) * 64 + size_t(column);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(albedo[size_t(c)][i], host[c], 0.02f)
            << "row " << row << ", column " << column << ", channel " << c;
      also(uv, host);
    }
}

}  // namespace

// The four colours read through a transform (offset, rotation and scale at once): the resolve reads
// as the host does, and the transform changed what is read.
TEST(TextureTransform, TheResolveReadsAsTheHostDoes) {
  tinygltf::Model m = fourColourFloor();
  auto& info = m.materials[0].pbrMetallicRoughness.baseColorTexture;
  const tinygltf::Value::Array offset{tinygltf::Value(0.3), tinygltf::Value(-0.2)},
      scale{tinygltf::Value(1.5), tinygltf::Value(0.7)};
  info.extensions["KHR_texture_transform"] = tinygltf::Value(tinygltf::Value::Object{
      {"offset", tinygltf::Value(offset)}, {"rotation", tinygltf::Value(0.6)}, {"scale", tinygltf::Value(scale)}});
  m.extensionsUsed.push_back("KHR_texture_transform");
  const std::string file = writeScene(m, "transformed");

  const scene::Scene loaded = scene::loadGltf(file);
  ASSERT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  const scene::Geometry g = scene::buildGeometry(loaded, 0);
  const int transformed = g.materials[0].baseColorTexture;
  ASSERT_EQ(transformed, 1) << "a record of its own";
  size_t differ = 0, checked = 0;
  expectAlbedoAsTheHostReads("transformed", file, g, transformed, [&](glm::vec2 uv, glm::vec4 host) {
    differ += glm::length(glm::vec3(host) - glm::vec3(scene::sampleTexture(g, 0, uv))) > 0.1f;
    ++checked;
  });
  EXPECT_GT(differ, checked / 2) << "the transform changes most lookups";
}

// A base colour read on TEXCOORD_1, which runs across the floor a quarter turn from TEXCOORD_0: the
// resolve reads the texture on that set as the host does, and what it reads there differs from
// what TEXCOORD_0 would give.
TEST(TextureCoordinates, TheSecondSetIsRead) {
  const auto turned = [](glm::vec2 uv) { return glm::vec2(1.0f - uv.y, uv.x); };
  tinygltf::Model m = fourColourFloor(turned);
  m.materials[0].pbrMetallicRoughness.baseColorTexture.texCoord = 1;
  const std::string file = writeScene(m, "second_set");

  const scene::Scene loaded = scene::loadGltf(file);
  ASSERT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  ASSERT_EQ(loaded.meshes[0].primitives[0].uvs1.size(), loaded.meshes[0].primitives[0].uvs.size());
  const scene::Geometry g = scene::buildGeometry(loaded, 0);
  const int record = g.materials[0].baseColorTexture;
  ASSERT_EQ(record, 1) << "a record of its own";
  EXPECT_EQ(g.textures[size_t(record)].uvRowV.w, 1.0f);
  size_t differ = 0, checked = 0;
  expectAlbedoAsTheHostReads(
      "second_set", file, g, record,
      [&](glm::vec2 uv, glm::vec4 host) {
        differ += glm::length(glm::vec3(host) - glm::vec3(scene::sampleTexture(g, 0, uv))) > 0.1f;
        ++checked;
      },
      [&](glm::vec2 uv) { return glm::vec4(uv, turned(uv)); });
  EXPECT_GT(differ, checked / 2) << "the second set changes most lookups";

  // Tessellated, the new vertices carry both sets: the turn is affine, so each keeps it.
  const scene::Geometry fine = scene::buildGeometry(loaded, 16);
  ASSERT_GT(fine.uvs.size(), 4u * g.uvs.size());
  for (const glm::vec4& uv : fine.uvs) {
    const glm::vec2 expected = turned(glm::vec2(uv));
    ASSERT_NEAR(uv.z, expected.x, 1e-5f) << uv.x << ", " << uv.y;
    ASSERT_NEAR(uv.w, expected.y, 1e-5f) << uv.x << ", " << uv.y;
  }
}

// A sampler whose magFilter is NEAREST reads the nearest texel, as glTF viewers and Blender's
// importer ("Closest") show it: every lookup, the resolve's and the host's alike, is one of the four
// colours, where the bilinear default blends them between the texels' centres.
TEST(TexturedAlbedo, NearestFilterReadsWholeTexels) {
  for (const bool nearest : {false, true}) {
    tinygltf::Model m = fourColourFloor();
    tinygltf::Sampler sampler;
    sampler.magFilter = nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR;
    m.samplers.push_back(sampler);
    m.textures[0].sampler = 0;
    const std::string name = nearest ? "nearest" : "linear", file = writeScene(m, name);
    const scene::Geometry g = scene::buildGeometry(scene::loadGltf(file), 0);
    const std::vector<glm::vec3> colours = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    size_t whole = 0, checked = 0;
    expectAlbedoAsTheHostReads(name, file, g, 0, [&](glm::vec2, glm::vec4 host) {
      whole += std::any_of(colours.begin(), colours.end(),
                           [&](glm::vec3 c) { return glm::length(glm::vec3(host) - c) < 1e-3f; });
      ++checked;
    });
    if (nearest)
      EXPECT_EQ(whole, checked) << "every lookup one texel's colour";
    else
      EXPECT_LT(whole, checked / 4) << "bilinear lookups blend";
  }
}

// Khronos' test model for the extension (in Debian's assimp-testmodels): its three offset squares
// show a tick on green, blue and cyan where the offset is applied, and a yellow "not supported"
// sign where it is not.
TEST(TextureTransform, KhronosTestModelShowsItsTicks) {
  const fs::path file = test::assimpGltfDir() / "textureTransform" / "TextureTransformTest.gltf";
  if (!fs::exists(file)) GTEST_SKIP() << file << " not installed";
  const fs::path exr = test::renderExr("khronos", {file.string(), "--size", "320x240", "--env", "1,1,1"});
  std::vector<std::vector<float>> albedo;
  for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) albedo.push_back(test::channelOf(exr, c));
  ASSERT_EQ(albedo[0].size(), 320u * 240u);
  // The squares' centres at 320×240, read off the rendered image, and the channels that must lead.
  const std::vector<std::pair<glm::ivec2, glm::bvec3>> squares = {
      {{100, 70}, {false, true, false}}, {{160, 70}, {false, false, true}}, {{220, 70}, {false, true, true}}};
  for (const auto& [at, lit] : squares) {
    const size_t i = size_t(at.y) * 320 + size_t(at.x);
    const glm::vec3 a(albedo[0][i], albedo[1][i], albedo[2][i]);
    for (int c = 0; c < 3; ++c)
      if (lit[c])
        EXPECT_GT(a[c], 0.4f) << "square at " << at.x << ": " << a.r << " " << a.g << " " << a.b;
      else
        EXPECT_LT(a[c], 0.2f) << "square at " << at.x << ": " << a.r << " " << a.g << " " << a.b;
  }
}

namespace {

// A floor of two triangles (1 m square) under an 8×8 texture framed in white with a black inside,
// clamped at its edges: each vertex reads white, the texture's mean is darker than half.
tinygltf::Model framedFloor() {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, 1, 1, {0, 1, 0});
  const int material = b.material("framed", glm::vec3(1.0f));
  b.node("floor", b.mesh("floor", {{floor, material}}));
  tinygltf::Model m = b.finish();
  tinygltf::Sampler clamp;
  clamp.wrapS = clamp.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  m.samplers.push_back(clamp);
  m.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture.index = test::addGreyTexture(
      m, 8, [](int x, int y) { return x == 0 || y == 0 || x == 7 || y == 7 ? 255 : 0; }, 0);
  return m;
}

}  // namespace

// Each surfel reflects the hat-weighted mean of its triangles' texture, so that the surfels
// together reflect what the surface does: Σ (area/3 of its triangles) × albedo over the surfels is
// the texture's integral over the floor, within the sampling's error. Reading the texture at the
// vertices gave every surfel the frame's white. Also through a transform that repeats the
// texture 4 × 4 times over the floor: the samples follow the texels the transform puts there.
TEST(TexturedAlbedo, SurfelsTogetherReflectTheTexturesMean) {
  for (const bool repeated : {false, true}) {
    tinygltf::Model m = framedFloor();
    if (repeated) {
      m.samplers[0].wrapS = m.samplers[0].wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
      const tinygltf::Value::Array four{tinygltf::Value(4.0), tinygltf::Value(4.0)};
      m.materials[0].pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
          tinygltf::Value(tinygltf::Value::Object{{"scale", tinygltf::Value(four)}});
      m.extensionsUsed.push_back("KHR_texture_transform");
    }
    const scene::Scene s = scene::sceneFromModel(m, "framed.gltf");
    const scene::Geometry g = scene::buildGeometry(s, 0);
    ASSERT_EQ(g.surfels.size(), 4u);
    const int texture = g.materials[0].baseColorTexture;
    double mean = 0.0;  // of the texture over the floor, on a fine grid
    const int fine = 1024;
    for (int j = 0; j < fine; ++j)
      for (int i = 0; i < fine; ++i)
        mean += scene::sampleTexture(g, texture, {(float(i) + 0.5f) / fine, (float(j) + 0.5f) / fine}).r /
                double(fine * fine);
    ASSERT_LT(mean, 0.5) << "the frame is the lesser part";
    std::vector<double> third(g.surfels.size(), 0.0);  // a third of each surfel's triangles' area
    for (size_t k = 0; k < g.surfels.size(); ++k)
      for (uint32_t t = 0; t < g.surfels[k].triangleCount; ++t) {
        const auto& tri = g.triangles[g.surfelTriangles[g.surfels[k].firstTriangle + t]];
        const glm::vec3 a = g.vertices[tri.v0].position, b = g.vertices[tri.v1].position,
                        c = g.vertices[tri.v2].position;
        third[k] += glm::length(glm::cross(b - a, c - a)) / 6.0;
      }
    double reflected = 0.0;
    for (size_t k = 0; k < g.surfels.size(); ++k) {
      reflected += third[k] * g.surfelAlbedo[k].r;
      EXPECT_LT(g.surfelAlbedo[k].r, 0.9f) << "surfel " << k << " took the white its vertex reads";
    }
    EXPECT_NEAR(reflected, mean, 0.01 * mean) << (repeated ? "repeated 4 × 4 times" : "once") << " over 1 m²";
  }
}

namespace {

// The Cornell box (8 cells, static) with its white room tiled: one tile a cell, each an 8×8 texture
// of a dark tile (0.2) inside a line of light grout (0.9), so that every vertex lies on grout while
// most of the surface is tile, as in a floor modelled a quad a tile.
tinygltf::Model tiledCornellBox() {
  tinygltf::Model m = scenes::cornellBox({.cells = 8, .animated = false});
  tinygltf::Material tiles = m.materials[0];
  tiles.name = "tiles";
  tiles.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  tiles.pbrMetallicRoughness.baseColorTexture.index = test::addGreyTexture(m, 8, [](int x, int y) {
    return x == 0 || y == 0 || x == 7 || y == 7 ? 243 : 124;  // sRGB for 0.9 and 0.2
  });
  m.materials.push_back(tiles);
  tinygltf::Primitive& room = m.meshes[0].primitives[0];  // the white walls, floor and ceiling
  room.material = int(m.materials.size() - 1);
  // addQuad's coordinates run from 0 to 1 over a face's 8 cells: 8 times them puts a tile in a cell.
  const tinygltf::Accessor& a = m.accessors[size_t(room.attributes.at("TEXCOORD_0"))];
  const tinygltf::BufferView& view = m.bufferViews[size_t(a.bufferView)];
  float* uv = reinterpret_cast<float*>(m.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset);
  for (size_t i = 0; i < 2 * a.count; ++i) uv[i] *= 8.0f;
  return m;
}

double meanOver(const image::RgbImage& im, glm::ivec2 from, glm::ivec2 to) {
  double sum = 0.0;
  for (int y = from.y; y < to.y; ++y)
    for (int x = from.x; x < to.x; ++x) {
      const glm::vec3 p = im.pixels[size_t(y) * im.width + size_t(x)];
      sum += p.r + p.g + p.b;
    }
  return sum / double((to.x - from.x) * (to.y - from.y));
}

}  // namespace

// The tiled box against the path tracer: the ceiling, lit only by light reflected from the tiled
// floor and walls, within 5 % of pt (1.34 times pt's with each surfel reading its vertex's grout, at
// 320×240 and 1,024 samples a pixel), with the surfaces as modelled and as tessellated.
TEST(TexturedAlbedo, ATiledRoomReflectsItsTilesNotItsGrout) {
  const std::string file = writeScene(tiledCornellBox(), "tiled");
  const image::RgbImage pt =
      image::readLinearRgb(test::renderExr("pt", {file, "--size", "96x72", "--method", "pt", "--spp", "256"}).string());
  const glm::ivec2 from(30, 2), to(66, 7);  // the ceiling around the lamp, below the image's top edge
  for (const char* tessellate : {"0", "16"}) {
    const image::RgbImage iv =
        image::readLinearRgb(test::renderExr(std::string("iv-") + tessellate, {file, "--size", "96x72", "--supersample",
                                                                               "4", "--tessellate", tessellate})
                                 .string());
    EXPECT_NEAR(meanOver(iv, from, to) / meanOver(pt, from, to), 1.0, 0.05) << "--tessellate " << tessellate;
  }
}

// Found by tests/fuzz/gltf_scene_fuzzer (UBSan: NaN converted to int in texelPair): texture
// coordinates beyond float's range, here by a KHR_texture_transform that scales and offsets them
// past it, made the sampler's texel index NaN cast to int, and so an index out of the texture on the
// host and on the GPU. Such a coordinate reads as 0: every surfel's albedo is a texel's, in [0, 1].
TEST(TexturedAlbedo, CoordinatesBeyondFloatsRangeReadAsZero) {
  tinygltf::Model m = framedFloor();
  const tinygltf::Value::Array huge{tinygltf::Value(3e38), tinygltf::Value(3e38)};
  m.materials[0].pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
      tinygltf::Value(tinygltf::Value::Object{{"scale", tinygltf::Value(huge)}, {"offset", tinygltf::Value(huge)}});
  m.extensionsUsed.push_back("KHR_texture_transform");
  const scene::Geometry g = scene::buildGeometry(scene::sceneFromModel(m, "huge-uv.gltf"), 0);
  ASSERT_FALSE(g.surfelAlbedo.empty());
  for (const glm::vec4& albedo : g.surfelAlbedo)
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(albedo[c]));
      EXPECT_GE(albedo[c], 0.0f);
      EXPECT_LE(albedo[c], 1.0f);
    }
  const glm::vec4 atZero = scene::sampleTexture(g, g.materials[0].baseColorTexture, {0.0f, 0.0f});
  EXPECT_EQ(scene::sampleTexture(g, g.materials[0].baseColorTexture, {1.0f, 1.0f}), atZero);
}

// The roughness and metallic layers are the file's factors times its metallic-roughness texture
// (G, B, read linearly, through its KHR_texture_transform), the same from the rasteriser's resolve
// (iv, ar) as from the path tracer: the glossy Cornell box, and a floor whose texture runs in
// stripes of roughness and metal under a transform.
TEST(MaterialLayers, EveryMethodWritesTheSameRoughnessAndMetallic) {
  tinygltf::Model striped = framedFloor();
  tinygltf::Material& m = striped.materials[0];
  m.pbrMetallicRoughness.baseColorTexture.index = -1;
  m.pbrMetallicRoughness.metallicFactor = 0.8;
  m.pbrMetallicRoughness.roughnessFactor = 0.9;
  auto& texels = striped.images[0].image;
  for (size_t p = 0; p < texels.size() / 4; ++p)
    texels[4 * p + 1] = uint8_t(32 * (p % 8)), texels[4 * p + 2] = uint8_t(255 - 32 * (p / 8));
  m.pbrMetallicRoughness.metallicRoughnessTexture.index = 0;
  const tinygltf::Value::Array scale{tinygltf::Value(2.0), tinygltf::Value(1.0)};
  m.pbrMetallicRoughness.metallicRoughnessTexture.extensions["KHR_texture_transform"] =
      tinygltf::Value(tinygltf::Value::Object{{"scale", tinygltf::Value(scale)}});
  striped.extensionsUsed.push_back("KHR_texture_transform");
  striped.cameras.push_back({});
  striped.cameras.back().type = "perspective";
  striped.cameras.back().perspective.yfov = 0.9;
  striped.cameras.back().perspective.znear = 0.01;
  tinygltf::Node eye;
  eye.camera = 0;
  eye.translation = {0.5, 1.0, 0.5};
  eye.rotation = {-0.7071068, 0.0, 0.0, 0.7071068};  // looking down
  striped.nodes.push_back(eye);
  striped.scenes[0].nodes.push_back(int(striped.nodes.size() - 1));

  const std::string floor = writeScene(striped, "striped");
  for (const std::vector<std::string>& scene : {std::vector<std::string>{"cornell", "--glossy"}, {floor}}) {
    fs::path pt;
    for (const char* method : {"pt", "iv", "ar"}) {
      std::vector<std::string> args = scene;
      args.insert(args.end(), {"--size", "64x48", "--method", method, "--spp", "1"});
      if (std::string(method) != "pt") args.resize(args.size() - 2);
      const fs::path exr = test::renderExr(std::string("layers-") + method, args);
      if (pt.empty()) {
        pt = exr;
        continue;
      }
      // The resolve averages a pixel's samples' factors where pt takes its centre's: a silhouette
      // pixel may differ, no more than one in a hundred.
      for (const auto& d :
           image::compareLayers(exr.string(), pt.string(), image::pixelRule({"roughness", "metallic"}, 0.01f, 0.01f)))
        EXPECT_TRUE(d.passed) << scene[0] << ", " << method << ", layer '" << d.layer
                              << "': " << 100 * d.failingFraction << " % of pixels beyond " << d.threshold;
    }
  }
}

// glTF loading: the real assets with figures read off their files, and constructed models for every
// accessor form the spec allows (component types, normalisation, interleaving, sparse, strips).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <tuple>

#include "engine/scene/geometry.h"
#include "engine/scene/gltf.h"
#include "engine/scene/texture_sampling.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
using namespace ivgi::scene;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::ThrowsMessage;

namespace {

size_t triangleCount(const Scene& s) {
  size_t n = 0;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) n += p.indices.size() / 3;
  return n;
}

// A model with one triangle primitive whose attributes the test then rewires.
struct TriangleModel {
  scenes::GltfBuilder b;
  int node;
  TriangleModel() {
    scenes::MeshData m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.indices = {0, 1, 2};
    node = b.node("triangle", b.mesh("triangle", {{m, b.material("grey", glm::vec3(0.5f))}}));
  }
  tinygltf::Primitive& primitive() { return b.model().meshes[0].primitives[0]; }
  // A 1×1 texture of one RGBA texel, as texture 0.
  void addTexel(std::vector<unsigned char> rgba) { test::addTexture(b.model(), 1, 1, std::move(rgba)); }
  Scene load() { return sceneFromModel(b.finish(), "constructed.gltf"); }
};

}  // namespace

TEST(Loader, AnimatedMorphCube) {
  Scene s =
      loadGltf((test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf").string());
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
  EXPECT_EQ(s.meshes[0].primitives[0].targets.size(), 2u);
  EXPECT_EQ(s.meshes[0].primitives[0].positions.size(), 24u);
  EXPECT_EQ(triangleCount(s), 12u);
  ASSERT_EQ(s.animations.size(), 1u);
  EXPECT_EQ(s.animations[0].channels[0].path, Path::Weights);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(Loader, SimpleSkin) {
  Scene s = loadGltf((test::assimpGltfDir() / "simple_skin/simple_skin.gltf").string());
  ASSERT_EQ(s.skins.size(), 1u);
  EXPECT_EQ(s.skins[0].joints.size(), 2u);
  EXPECT_EQ(s.meshes[0].primitives[0].positions.size(), 10u);
  EXPECT_EQ(triangleCount(s), 8u);
  EXPECT_EQ(s.animations.size(), 1u);
}

TEST(Loader, EverySharedAsset) {
  auto dir = test::sharedGltfDir();
  if (!dir) GTEST_SKIP() << "../shared/data/gltf is not present";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(*dir)) {
    auto ext = entry.path().extension();
    if (ext != ".gltf" && ext != ".glb") continue;
    ++files;
    Scene s = loadGltf(entry.path().string());
    Geometry g = buildGeometry(s);
    EXPECT_GT(g.triangles.size(), 0u) << entry.path();
    EXPECT_GT(g.surfels.size(), 0u) << entry.path();
    EXPECT_FALSE(s.animations.empty()) << entry.path();
  }
  EXPECT_GE(files, 6);
  // Figures of the Khronos Fox: 1,728 vertices, 576 triangles, 24 joints, three animations.
  Scene fox = loadGltf((*dir / "Fox.gltf").string());
  Geometry g = buildGeometry(fox);
  EXPECT_EQ(g.vertices.size(), 1728u);
  EXPECT_EQ(g.triangles.size(), 576u);
  ASSERT_EQ(fox.skins.size(), 1u);
  EXPECT_EQ(fox.skins[0].joints.size(), 24u);
  ASSERT_EQ(fox.animations.size(), 3u);
  EXPECT_EQ(fox.animations[0].name, "Survey");
  EXPECT_EQ(fox.animations[1].name, "Walk");
  EXPECT_EQ(fox.animations[2].name, "Run");
  EXPECT_EQ(fox.textures.size(), 1u);
  EXPECT_GT(fox.textures[0].width, 0);
}

TEST(Loader, NormalizedAndQuantizedComponentTypes) {
  TriangleModel t;
  // UVs as normalized unsigned bytes and unsigned shorts; positions as plain shorts (KHR_mesh_quantization).
  const uint8_t uv8[] = {0, 255, 255, 0, 51, 102};
  int a = t.b.accessor(uv8, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC2, 2);
  t.b.model().accessors[a].normalized = true;
  t.primitive().attributes["TEXCOORD_0"] = a;
  const int16_t pos16[] = {0, 0, 0, 2, 0, 0, 0, 3, 0, 0};  // 3 × VEC3 + padding
  t.primitive().attributes["POSITION"] = t.b.accessor(pos16, 3, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3, 6);
  const int8_t n8[] = {0, 0, 127, 0, /**/ 0, 0, 127, 0, /**/ 0, 0, -128, 0};
  int n = t.b.accessor(n8, 3, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC3, 4);
  t.b.model().bufferViews.back().byteStride = 4;  // vec3 of bytes padded to 4 bytes, as the spec aligns them
  t.b.model().accessors[n].normalized = true;
  t.primitive().attributes["NORMAL"] = n;
  t.b.model().extensionsUsed.push_back("KHR_mesh_quantization");
  Scene s = t.load();
  const Primitive& p = s.meshes[0].primitives[0];
  EXPECT_EQ(p.uvs[0], glm::vec2(0.0f, 1.0f));
  EXPECT_FLOAT_EQ(p.uvs[2].x, 0.2f);
  EXPECT_FLOAT_EQ(p.uvs[2].y, 0.4f);
  EXPECT_EQ(p.positions[1], glm::vec3(2, 0, 0));
  EXPECT_EQ(p.positions[2], glm::vec3(0, 3, 0));
  EXPECT_FLOAT_EQ(p.normals[0].z, 1.0f);
  EXPECT_FLOAT_EQ(p.normals[2].z, -1.0f) << "-128 clamps to -1";
  EXPECT_TRUE(s.warnings.empty());
}

TEST(Loader, VertexColorsInEveryFormTheSpecAllows) {
  // RGBA as normalized unsigned bytes, RGB as normalized unsigned shorts, RGBA as floats.
  TriangleModel bytes;
  const uint8_t rgba8[] = {255, 0, 0, 255, /**/ 0, 51, 0, 128, /**/ 0, 0, 255, 0};
  int a = bytes.b.accessor(rgba8, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 4);
  bytes.b.model().accessors[a].normalized = true;
  bytes.primitive().attributes["COLOR_0"] = a;
  Scene s = bytes.load();
  const auto& c8 = s.meshes[0].primitives[0].colors;
  ASSERT_EQ(c8.size(), 3u);
  EXPECT_EQ(c8[0], glm::vec4(1, 0, 0, 1));
  EXPECT_FLOAT_EQ(c8[1].g, 0.2f);
  EXPECT_FLOAT_EQ(c8[1].a, 128.0f / 255.0f);
  EXPECT_TRUE(s.warnings.empty());

  TriangleModel shorts;
  const uint16_t rgb16[] = {65535, 0, 0, 0, /**/ 0, 65535, 0, 0, /**/ 0, 0, 13107, 0};  // VEC3 padded to 8 bytes
  a = shorts.b.accessor(rgb16, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC3, 8);
  shorts.b.model().bufferViews.back().byteStride = 8;
  shorts.b.model().accessors[a].normalized = true;
  shorts.primitive().attributes["COLOR_0"] = a;
  const auto c16 = shorts.load().meshes[0].primitives[0].colors;
  EXPECT_EQ(c16[1], glm::vec4(0, 1, 0, 1)) << "RGB: alpha 1";
  EXPECT_FLOAT_EQ(c16[2].b, 0.2f);

  TriangleModel floats;
  const float rgbaF[] = {0.5f, 0.25f, 1.5f, 1, /**/ 0, 0, 0, 1, /**/ -0.1f, 1, 1, 1};
  floats.primitive().attributes["COLOR_0"] =
      floats.b.accessor(rgbaF, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 16);
  s = floats.load();
  const auto& cf = s.meshes[0].primitives[0].colors;
  EXPECT_EQ(cf[0], glm::vec4(0.5f, 0.25f, 1.0f, 1.0f)) << "clamped into [0, 1]";
  EXPECT_EQ(cf[2].r, 0.0f);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("COLOR_0"), std::string::npos);

  // Integers that are not normalized, or of a wrong count, are refused with the file's name.
  TriangleModel plain;
  a = plain.b.accessor(rgba8, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 4);
  plain.primitive().attributes["COLOR_0"] = a;
  EXPECT_THAT([&] { plain.load(); },
              ThrowsMessage<LoadError>(AllOf(HasSubstr("constructed.gltf"), HasSubstr("COLOR_0"))))
      << "COLOR_0 of plain unsigned bytes";
  TriangleModel scalar;
  scalar.primitive().attributes["COLOR_0"] =
      scalar.b.accessor(rgbaF, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 4);
  EXPECT_THROW(scalar.load(), LoadError);
}

// KHR_texture_transform on a texture reference: offset, rotation and scale read, the extension's
// texCoord overriding the reference's (a set past TEXCOORD_1, or one the mesh lacks, is warned of), and values that
// are not numbers refused with the file's name.
TEST(Loader, TextureTransformsAreRead) {
  auto withTransform = [](tinygltf::Value::Object transform) {
    TriangleModel t;
    t.addTexel({255, 255, 255, 255});
    auto& info = t.b.model().materials[0].pbrMetallicRoughness.baseColorTexture;
    info.index = 0;
    info.extensions["KHR_texture_transform"] = tinygltf::Value(std::move(transform));
    t.b.model().extensionsUsed.push_back("KHR_texture_transform");
    return t.load();
  };
  const tinygltf::Value::Array offset{tinygltf::Value(0.25), tinygltf::Value(-1.0)},
      scale{tinygltf::Value(2.0), tinygltf::Value(0.5)};
  Scene s = withTransform(
      {{"offset", tinygltf::Value(offset)}, {"rotation", tinygltf::Value(0.5)}, {"scale", tinygltf::Value(scale)}});
  const TextureTransform& t = s.materials[0].baseColorTransform;
  EXPECT_EQ(t.offset, glm::vec2(0.25f, -1.0f));
  EXPECT_FLOAT_EQ(t.rotation, 0.5f);
  EXPECT_EQ(t.scale, glm::vec2(2.0f, 0.5f));
  EXPECT_EQ(s.materials[0].baseColorTexture, 0);
  EXPECT_TRUE(s.warnings.empty()) << "the extension is read, not ignored";

  s = withTransform({{"texCoord", tinygltf::Value(1)}});
  EXPECT_EQ(s.materials[0].baseColorTransform.texCoord, 1) << "the extension's set in place of the reference's";
  ASSERT_EQ(s.warnings.size(), 1u) << "the triangle has no TEXCOORD_1";
  EXPECT_NE(s.warnings[0].find("no TEXCOORD_1"), std::string::npos) << s.warnings[0];
  s = withTransform({{"texCoord", tinygltf::Value(2)}});
  EXPECT_EQ(s.materials[0].baseColorTransform.texCoord, 0) << "a third set is not read";
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("TEXCOORD_2"), std::string::npos) << s.warnings[0];

  EXPECT_THAT(
      [&] {
        withTransform({{"scale", tinygltf::Value(2.0)}});
      },
      ThrowsMessage<LoadError>(AllOf(HasSubstr("constructed.gltf"), HasSubstr("scale"))))
      << "a scale that is not a pair";
}

TEST(Loader, IndexComponentTypes) {
  for (int type : {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}) {
    TriangleModel t;
    uint32_t idx32[] = {2, 1, 0};
    uint16_t idx16[] = {2, 1, 0};
    uint8_t idx8[] = {2, 1, 0};
    const void* data = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT     ? (const void*)idx32
                       : type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? (const void*)idx16
                                                                        : idx8;
    size_t bytes = tinygltf::GetComponentSizeInBytes(type);
    t.primitive().indices = t.b.accessor(data, 3, type, TINYGLTF_TYPE_SCALAR, bytes);
    Scene s = t.load();
    EXPECT_EQ(s.meshes[0].primitives[0].indices, (std::vector<uint32_t>{2, 1, 0})) << type;
  }
}

TEST(Loader, InterleavedViews) {
  TriangleModel t;
  struct V {
    float p[3], n[3];
  } verts[3] = {{{0, 0, 0}, {0, 0, 1}}, {{4, 0, 0}, {0, 0, 1}}, {{0, 5, 0}, {0, 1, 0}}};
  int pos = t.b.accessor(verts, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, sizeof(V));
  auto& model = t.b.model();
  model.bufferViews.back().byteStride = sizeof(V);
  tinygltf::Accessor nrm = model.accessors[pos];
  nrm.byteOffset = 12;
  model.accessors.push_back(nrm);
  t.primitive().attributes["POSITION"] = pos;
  t.primitive().attributes["NORMAL"] = int(model.accessors.size() - 1);
  Scene s = t.load();
  const Primitive& p = s.meshes[0].primitives[0];
  EXPECT_EQ(p.positions[1], glm::vec3(4, 0, 0));
  EXPECT_EQ(p.positions[2], glm::vec3(0, 5, 0));
  EXPECT_EQ(p.normals[2], glm::vec3(0, 1, 0));
}

TEST(Loader, SparseAccessors) {
  TriangleModel t;
  auto& model = t.b.model();
  // Replace vertex 1 of the positions by (7, 0, 0) through a sparse substitution.
  int pos = t.primitive().attributes["POSITION"];
  uint16_t which[] = {1};
  float value[] = {7, 0, 0};
  int idx = t.b.accessor(which, 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, 2);
  int val = t.b.accessor(value, 1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 12);
  auto& a = model.accessors[pos];
  a.sparse.isSparse = true;
  a.sparse.count = 1;
  a.sparse.indices.bufferView = model.accessors[idx].bufferView;
  a.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  a.sparse.values.bufferView = model.accessors[val].bufferView;
  a.sparse.indices.byteOffset = a.sparse.values.byteOffset = 0;  // tinygltf leaves them uninitialised
  // A morph target given only as sparse values over zeros (no buffer view).
  tinygltf::Accessor delta = a;
  delta.bufferView = -1;
  delta.byteOffset = 0;
  model.accessors.push_back(delta);
  t.primitive().targets.push_back({{"POSITION", int(model.accessors.size() - 1)}});
  Scene s = t.load();
  const Primitive& p = s.meshes[0].primitives[0];
  EXPECT_EQ(p.positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(p.positions[1], glm::vec3(7, 0, 0));
  ASSERT_EQ(p.targets.size(), 1u);
  EXPECT_EQ(p.targets[0].positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(p.targets[0].positions[1], glm::vec3(7, 0, 0));
}

TEST(Loader, StripsFansAndNonIndexed) {
  TriangleModel strip;
  uint32_t four[] = {0, 1, 2, 0};
  strip.primitive().indices = strip.b.accessor(four, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 4);
  strip.primitive().mode = TINYGLTF_MODE_TRIANGLE_STRIP;
  EXPECT_EQ(strip.load().meshes[0].primitives[0].indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}))
      << "odd strip triangles flip";
  TriangleModel fan;
  fan.primitive().indices = fan.b.accessor(four, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 4);
  fan.primitive().mode = TINYGLTF_MODE_TRIANGLE_FAN;
  EXPECT_EQ(fan.load().meshes[0].primitives[0].indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 0}));
  TriangleModel plain;
  plain.primitive().indices = -1;
  EXPECT_EQ(plain.load().meshes[0].primitives[0].indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(Loader, HarmlessUnsupportedContentIsSkippedWithAWarning) {
  TriangleModel t;
  tinygltf::Primitive lines = t.primitive();
  lines.mode = TINYGLTF_MODE_LINE;
  t.b.model().meshes[0].primitives.push_back(lines);
  t.b.model().extensionsUsed.push_back("EXT_made_up");
  Scene s = t.load();
  EXPECT_EQ(s.meshes[0].primitives.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("EXT_made_up"), std::string::npos);
  EXPECT_NE(s.warnings[1].find("lines"), std::string::npos);
}

// Eight influences a vertex (JOINTS_1/WEIGHTS_1, as exporters write for dense rigs): the four
// heaviest are kept, in weight order, renormalised, with a warning naming the primitive; four
// influences alone are kept as the file gives them, normalised.
TEST(Loader, EightJointInfluencesKeepTheFourHeaviest) {
  TriangleModel t;
  const uint16_t joints0[12] = {0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3}, joints1[12] = {4, 5, 6, 7, 4, 5, 6, 7, 4, 5, 6, 7};
  // Vertex 0's heaviest four lie across both sets; vertex 1's in the first; vertex 2's set 1 is empty.
  const float weights0[12] = {0.1f, 0.3f, 0.02f, 0.08f, 0.4f, 0.2f, 0.1f, 0.1f, 0.5f, 0.25f, 0.15f, 0.1f};
  const float weights1[12] = {0.25f, 0.05f, 0.15f, 0.05f, 0.1f, 0.05f, 0.05f, 0.0f, 0, 0, 0, 0};
  auto& attributes = t.primitive().attributes;
  attributes["JOINTS_0"] = t.b.accessor(joints0, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, 8);
  attributes["WEIGHTS_0"] = t.b.accessor(weights0, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 16);
  attributes["JOINTS_1"] = t.b.accessor(joints1, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, 8);
  attributes["WEIGHTS_1"] = t.b.accessor(weights1, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 16);
  const Scene s = t.load();
  const Primitive& p = s.meshes[0].primitives[0];
  ASSERT_EQ(p.joints.size(), 3u);
  EXPECT_EQ(p.joints[0], glm::uvec4(1, 4, 6, 0));  // 0.3, 0.25, 0.15 and 0.1; 0.08 and less left out
  EXPECT_NEAR(p.weights[0].x, 0.3f / 0.8f, 1e-6f);
  EXPECT_NEAR(p.weights[0].w, 0.1f / 0.8f, 1e-6f);
  EXPECT_EQ(p.joints[1], glm::uvec4(0, 1, 2, 3));  // 0.4, 0.2, 0.1, 0.1: ties keep the earlier influence
  EXPECT_NEAR(p.weights[1].x + p.weights[1].y + p.weights[1].z + p.weights[1].w, 1.0f, 1e-6f);
  EXPECT_EQ(p.joints[2], glm::uvec4(0, 1, 2, 3));
  EXPECT_NEAR(p.weights[2].x, 0.5f, 1e-6f);
  // (The triangle's node has no skin, which a warning of its own says.)
  auto influenceWarnings = [](const Scene& scene) {
    return std::count_if(scene.warnings.begin(), scene.warnings.end(),
                         [](const std::string& w) { return w.find("four heaviest") != std::string::npos; });
  };
  EXPECT_EQ(influenceWarnings(s), 1);

  TriangleModel four;
  four.primitive().attributes["JOINTS_0"] =
      four.b.accessor(joints0, 3, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, 8);
  four.primitive().attributes["WEIGHTS_0"] =
      four.b.accessor(weights0, 3, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 16);
  const Scene f = four.load();
  EXPECT_EQ(influenceWarnings(f), 0);
  EXPECT_EQ(f.meshes[0].primitives[0].joints[0], glm::uvec4(0, 1, 2, 3));
  EXPECT_NEAR(f.meshes[0].primitives[0].weights[0].y, 0.3f / 0.5f, 1e-6f);
}

TEST(Loader, RequiredUnknownExtensionIsAnError) {
  TriangleModel t;
  t.b.model().extensionsRequired.push_back("EXT_made_up");
  t.b.model().extensionsUsed.push_back("EXT_made_up");
  EXPECT_THROW(t.load(), LoadError);
}

TEST(Loader, MaterialsLightsAndCameras) {
  Scene s = sceneFromModel(scenes::cornellBox({.cells = 1}), "cornell");
  ASSERT_EQ(s.materials.size(), 4u);
  const Material& light = s.materials[3];
  EXPECT_NEAR(light.emissiveStrength * light.emissive.r, 17.0f, 1e-5f);
  EXPECT_NEAR(light.emissiveStrength * light.emissive.g, 12.0f, 1e-5f);
  EXPECT_NEAR(light.emissiveStrength * light.emissive.b, 4.0f, 1e-5f);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_NEAR(s.cameras[0].yfov * 180.0f / 3.14159265f, 39.31f, 0.01f);

  TriangleModel t;
  tinygltf::Light point;
  point.type = "point";
  point.color = {1, 0.5, 0.25};
  point.intensity = 40;
  t.b.model().lights.push_back(point);
  t.b.model().nodes[t.node].extensions["KHR_lights_punctual"] =
      tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(0)}});
  t.b.model().extensionsUsed.push_back("KHR_lights_punctual");
  Scene lit = t.load();
  ASSERT_EQ(lit.lights.size(), 1u);
  EXPECT_EQ(lit.lights[0].type, Light::Type::Point);
  EXPECT_FLOAT_EQ(lit.lights[0].intensity, 40.0f);
  EXPECT_EQ(lit.nodes[t.node].light, 0);
}

// glTF's metallic-roughness factors, KHR_materials_specular and KHR_materials_ior: the dielectric's
// reflectance min(((ior − 1)/(ior + 1))² × colour, 1) × factor at normal incidence, the factor at
// grazing; a factor outside [0, 1] clamped with a warning; an index below 1 refused.
TEST(Loader, MetallicRoughnessAndTheSpecularLayerAreRead) {
  auto material = [](double metallic, double roughness, tinygltf::Value::Object specular, double ior) {
    TriangleModel t;
    tinygltf::Material& m = t.b.model().materials[0];
    m.pbrMetallicRoughness.metallicFactor = metallic;
    m.pbrMetallicRoughness.roughnessFactor = roughness;
    m.extensions.clear();
    m.extensions["KHR_materials_specular"] = tinygltf::Value(std::move(specular));
    m.extensions["KHR_materials_ior"] = tinygltf::Value(tinygltf::Value::Object{{"ior", tinygltf::Value(ior)}});
    t.b.model().extensionsUsed.push_back("KHR_materials_ior");
    return t.load();
  };
  const tinygltf::Value::Array colour{tinygltf::Value(1.0), tinygltf::Value(0.5), tinygltf::Value(0.25)};
  Scene s = material(0.3, 0.6,
                     {{"specularFactor", tinygltf::Value(0.5)}, {"specularColorFactor", tinygltf::Value(colour)}}, 2.0);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
  const Material& m = s.materials[0];
  EXPECT_FLOAT_EQ(m.metallic, 0.3f);
  EXPECT_FLOAT_EQ(m.roughness, 0.6f);
  const glm::vec4 reflectance = m.dielectricReflectance();
  EXPECT_FLOAT_EQ(reflectance.r, 0.5f / 9.0f);
  EXPECT_FLOAT_EQ(reflectance.g, 0.25f / 9.0f);
  EXPECT_FLOAT_EQ(reflectance.b, 0.125f / 9.0f);
  EXPECT_FLOAT_EQ(reflectance.a, 0.5f);
  // The core specification's dielectric: 0.04 at normal incidence, 1 at grazing.
  EXPECT_NEAR(Material{}.dielectricReflectance().g, 0.04f, 1e-7f);
  EXPECT_EQ(Material{}.dielectricReflectance().a, 1.0f);

  s = material(1.5, -0.5, {}, 1.5);
  EXPECT_EQ(s.materials[0].metallic, 1.0f);
  EXPECT_EQ(s.materials[0].roughness, 0.0f);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("metallicFactor"), std::string::npos) << s.warnings[0];

  for (double ior : {0.5, std::nan("")})
    EXPECT_THAT([&] { material(0.0, 1.0, {}, ior); }, ThrowsMessage<LoadError>(HasSubstr("ior"))) << "ior " << ior;
}

// A metallic-roughness texture holds data, not colour: its texels reach the passes as stored (128
// of 255 is 0.502, not the sRGB curve's 0.216), through its own KHR_texture_transform, while the
// same image read as a base colour goes through the curve.
TEST(Loader, MetallicRoughnessTexturesAreLinear) {
  TriangleModel t;
  t.addTexel({0, 128, 255, 255});
  auto& pbr = t.b.model().materials[0].pbrMetallicRoughness;
  pbr.baseColorTexture.index = 0;
  pbr.metallicRoughnessTexture.index = 0;
  const tinygltf::Value::Array offset{tinygltf::Value(0.5), tinygltf::Value(0.25)};
  pbr.metallicRoughnessTexture.extensions["KHR_texture_transform"] =
      tinygltf::Value(tinygltf::Value::Object{{"offset", tinygltf::Value(offset)}});
  t.b.model().extensionsUsed.push_back("KHR_texture_transform");
  const Scene s = t.load();
  EXPECT_EQ(s.materials[0].metallicRoughnessTransform.offset, glm::vec2(0.5f, 0.25f));
  const Geometry g = buildGeometry(s);
  const gpu::Material& m = g.materials[0];
  ASSERT_GE(m.metallicRoughnessTexture, 0);
  EXPECT_NE(m.metallicRoughnessTexture, m.baseColorTexture);
  EXPECT_EQ(g.textures[size_t(m.metallicRoughnessTexture)].uvRowU.z, 0.5f);
  EXPECT_NEAR(sampleTexture(g, m.metallicRoughnessTexture, glm::vec2(0.3f)).g, 128.0f / 255.0f, 1e-3f);
  EXPECT_NEAR(sampleTexture(g, m.metallicRoughnessTexture, glm::vec2(0.3f)).b, 1.0f, 1e-3f);
  EXPECT_NEAR(sampleTexture(g, m.baseColorTexture, glm::vec2(0.3f)).g, 0.2158f, 1e-3f);
}

// Whether the solvers send a material's lobe by direction (Geometry::directionalLobes) or evenly,
// as its base's: a rough dielectric's lobe (the glTF default's F0 0.04 at roughness 1) reflects a
// few per cent of the light over a wide lobe and goes evenly, as a Lambertian surface's does; a
// satin's, a rough metal's and any lobe under a metallic-roughness texture (which may hold a
// mirror's roughness) go by direction. The reflections toward the eye stay with every glossy one.
TEST(Loader, OnlyLobesFarFromEvenAreSentByDirection) {
  const auto classify = [](float metallic, float roughness, bool textured) {
    TriangleModel t;
    tinygltf::Material& m = t.b.model().materials[0];
    m.extensions.clear();  // the core specification's specular layer
    m.pbrMetallicRoughness.metallicFactor = metallic;
    m.pbrMetallicRoughness.roughnessFactor = roughness;
    if (textured) {
      t.addTexel({0, 255, 0, 255});
      m.pbrMetallicRoughness.metallicRoughnessTexture.index = 0;
    }
    const Geometry g = buildGeometry(t.load());
    EXPECT_TRUE(g.glossyMaterials);
    return g.directionalLobes;
  };
  EXPECT_FALSE(classify(0.0f, 1.0f, false)) << "a rough dielectric";
  EXPECT_TRUE(classify(0.0f, 0.5f, false)) << "a satin dielectric";
  EXPECT_TRUE(classify(1.0f, 1.0f, false)) << "a rough metal";
  EXPECT_TRUE(classify(0.0f, 1.0f, true)) << "a rough dielectric under a metallic-roughness texture";
  TriangleModel lambertian;
  const Geometry g = buildGeometry(lambertian.load());
  EXPECT_FALSE(g.glossyMaterials || g.directionalLobes);
}

namespace {

// One triangle in a .gltf beside its .bin, or a .glb holding both, with a textured material whose
// properties the test then sets to types the schema does not allow.
struct TriangleFile {
  std::filesystem::path dir = test::scratchDir("wrong_types");
  std::string bin = [] {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    return std::string(reinterpret_cast<const char*>(positions), sizeof positions);
  }();
  nlohmann::json doc = nlohmann::json::parse(R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "name": "triangle", "translation": [0, 0, 0]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"uri": "triangle.bin", "byteLength": 36}]})");
  uint32_t glbVersion = 2;  // the .glb header's

  Scene loadText() const {
    std::ofstream(dir / "triangle.bin", std::ios::binary) << bin;
    std::ofstream(dir / "triangle.gltf") << doc.dump();
    return loadGltf((dir / "triangle.gltf").string());
  }
  Scene loadBinary() const {
    nlohmann::json inside = doc;
    inside["buffers"][0].erase("uri");
    std::string text = inside.dump();
    text.resize((text.size() + 3) / 4 * 4, ' ');
    auto word = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const uint32_t total = uint32_t(12 + 8 + text.size() + 8 + bin.size());
    std::ofstream(dir / "triangle.glb", std::ios::binary)
        << "glTF" << word(glbVersion) << word(total) << word(uint32_t(text.size())) << "JSON" << text
        << word(uint32_t(bin.size())) << "BIN" << '\0' << bin;
    return loadGltf((dir / "triangle.glb").string());
  }
};

}  // namespace

// tinygltf reads a property of the wrong type as absent: a material's pbrMetallicRoughness given as
// an array rendered the glTF defaults (a white metal), a texture index of -1 no texture. Such a file
// is refused, naming the property; a name of the wrong type changes nothing drawn and still loads.
TEST(Loader, PropertiesOfAWrongTypeAreRefusedNamingThem) {
  {
    TriangleFile t;
    EXPECT_EQ(t.loadText().materials.at(0).metallic, 0.0f) << "the file as the schema allows loads";
    EXPECT_EQ(t.loadBinary().materials.at(0).metallic, 0.0f);
    t.doc["nodes"][0]["name"] = 42;
    EXPECT_NO_THROW(t.loadText()) << "a name changes nothing drawn";
  }
  const std::vector<std::tuple<const char*, nlohmann::json, std::string>> wrong = {
      {"/meshes/0/primitives", nlohmann::json::object(), "meshes[0].primitives is an object, not an array"},
      {"/meshes/0/primitives", nlohmann::json::array(), "meshes[0].primitives is empty"},
      {"/materials/0/pbrMetallicRoughness", {"not an object"}, "materials[0].pbrMetallicRoughness is an array"},
      {"/materials/0/pbrMetallicRoughness/metallicFactor", "0", "metallicFactor is a string, not a number"},
      {"/nodes/0/scale", "large", "nodes[0].scale is not an array of 3 numbers"},
      {"/materials/0/emissiveTexture", {{"index", -1}}, "materials[0].emissiveTexture.index is -1, not an index"},
      {"/materials/0/emissiveTexture",
       {{"index", 0}, {"extensions", {{"KHR_texture_transform", "turned"}}}},
       "emissiveTexture.extensions.KHR_texture_transform is a string, not an object"},
      {"/materials/0/doubleSided", 1, "materials[0].doubleSided is a number, not a boolean"},
      {"/nodes/0/translation", {1, 2}, "nodes[0].translation is not an array of 3 numbers"},
      {"/nodes/0/children", {0.5}, "nodes[0].children[0] is 0.5, not an index"},
      {"/meshes/0/primitives/0/mode", 9, "meshes[0].primitives[0].mode is 9, not a primitive mode"},
      {"/accessors/0/byteOffset", "12", "accessors[0].byteOffset is \"12\", not an index"},
      {"/accessors/0/bufferView", -1, "accessors[0].bufferView is -1, not an index"},
      {"/accessors/0/normalized", 1, "accessors[0].normalized is a number, not a boolean"},
      {"/bufferViews/0/byteStride", "12", "bufferViews[0].byteStride is \"12\", not an index"},
      {"/samplers", {{{"wrapS", 12345}}}, "samplers[0].wrapS is 12345, not one of 33071, 33648, 10497"}};
  for (const auto& [pointer, value, expected] : wrong)
    for (bool binary : {false, true}) {
      TriangleFile t;
      t.doc[nlohmann::json::json_pointer(pointer)] = value;
      EXPECT_THAT([&] { binary ? t.loadBinary() : t.loadText(); },
                  ThrowsMessage<LoadError>(AllOf(HasSubstr(binary ? "triangle.glb" : "triangle.gltf"),
                                                 HasSubstr(expected), Not(HasSubstr("\n")))))
          << pointer << " = " << value.dump();
    }
}

// Values the schema's types allow but its rules do not: a light of another type was read as a point
// light, one of negative intensity sent negative light, a spot's inner cone wider than its outer
// one; a rotation of no length was read as none, and one far from unit length sheared its node.
TEST(Loader, ALightOfNoKnownTypeAndARotationOfNoLengthAreRefused) {
  auto refused = [](const TriangleFile& t, const std::string& expected) {
    EXPECT_THAT([&] { t.loadText(); },
                ThrowsMessage<LoadError>(AllOf(HasSubstr("triangle.gltf"), HasSubstr(expected))));
  };
  TriangleFile light;
  light.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  light.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 5}}};
  light.doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  light.doc["scenes"][0]["nodes"].push_back(1);
  EXPECT_EQ(light.loadText().lights.size(), 1u);
  light.doc["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "laser";
  refused(light, "lights[0].type is \"laser\", not one of \"directional\", \"point\", \"spot\"");
  light.doc["extensions"]["KHR_lights_punctual"]["lights"][0] = {{"type", "point"}, {"intensity", -5}};
  refused(light, "lights[0].intensity is -5, not a number of at least 0");
  light.doc["extensions"]["KHR_lights_punctual"]["lights"][0] = {
      {"type", "spot"}, {"spot", {{"innerConeAngle", 1.0}, {"outerConeAngle", 0.5}}}};
  refused(light, "light 0: its cone's angles");

  TriangleFile turned;
  turned.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
  refused(turned, "node 'triangle': rotation of length 0");
  turned.doc["nodes"][0]["rotation"] = {0, 0, 0, 2};
  const Scene s = turned.loadText();
  EXPECT_FLOAT_EQ(s.nodes[0].rotation.w, 1.0f) << "taken at unit length";
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("unit length"), std::string::npos) << s.warnings[0];
  turned.doc["nodes"][0]["rotation"] = {0, 0, 0.7071, 0.7071};
  EXPECT_TRUE(turned.loadText().warnings.empty()) << "a rotation rounded by its exporter is taken without a word";
}

// A file of another glTF version fails tinygltf's checks on whatever differs first (glTF 1.0's
// named scene was refused as "scene is \"defaultScene\", not an index"): it is named for what it is.
TEST(Loader, OtherVersionsOfGltfAreNamedAsSuch) {
  auto refused = [](const TriangleFile& t, const std::string& expected) {
    for (bool binary : {false, true})
      EXPECT_THAT([&] { binary ? t.loadBinary() : t.loadText(); },
                  ThrowsMessage<LoadError>(AllOf(HasSubstr(binary ? "triangle.glb: " : "triangle.gltf: "),
                                                 HasSubstr(expected + "; ivgi reads glTF 2.0"))));
  };
  TriangleFile t;
  t.doc["asset"]["version"] = "1.0";
  refused(t, "is glTF 1.0 (asset.version \"1.0\")");
  t.doc["asset"]["version"] = "3.0";
  refused(t, "is glTF 3.0 (asset.version \"3.0\")");
  // A later minor version is read, its additions ignored, unless its minVersion asks for more.
  t.doc["asset"]["version"] = "2.1";
  EXPECT_NO_THROW(t.loadText());
  t.doc["asset"]["minVersion"] = "2.0";
  EXPECT_NO_THROW(t.loadBinary());
  t.doc["asset"]["minVersion"] = "2.1";
  refused(t, "needs glTF 2.1 at least (asset.minVersion)");

  TriangleFile glb1;
  glb1.glbVersion = 1;
  EXPECT_THAT([&] { glb1.loadBinary(); },
              ThrowsMessage<LoadError>(HasSubstr("triangle.glb: is binary glTF of version 1 (its header)")));

  // Khronos' glTF 1.0 files as assimp-testmodels holds them; the truck's asset.version is a number.
  const auto dir = test::assimpGltfDir().parent_path() / "glTF";
  for (const auto& [file, expected] : std::vector<std::pair<std::string, std::string>>{
           {"BoxTextured-glTF/BoxTextured.gltf", "is glTF 1.0 (asset.version \"1.0\")"},
           {"BoxTextured-glTF-Binary/BoxTextured.glb", "is binary glTF of version 1"},
           {"CesiumMilkTruck/CesiumMilkTruck.gltf", "is glTF 1.0 (its accessors are named rather than listed)"}}) {
    const std::string path = (dir / file).string();  // (clang 14 captures no structured binding)
    const std::string what = expected;
    EXPECT_THAT([&] { loadGltf(path); }, ThrowsMessage<LoadError>(AllOf(HasSubstr(file), HasSubstr(what))));
  }
}

// tinygltf does not check the default scene's index where the file has no scenes: it was read as
// no scene at all, and the file refused as one with no triangles.
TEST(Loader, ADefaultSceneOutOfRangeIsRefused) {
  TriangleFile t;
  t.doc["scene"] = 1;
  EXPECT_THAT([&] { t.loadText(); },
              ThrowsMessage<LoadError>(HasSubstr("triangle.gltf: scene 1 is out of range (the file has 1 scenes)")));
  t.doc.erase("scenes");
  t.doc["scene"] = 0;
  EXPECT_THAT([&] { t.loadBinary(); },
              ThrowsMessage<LoadError>(HasSubstr("triangle.glb: scene 0 is out of range (the file has 0 scenes)")));
  t.doc.erase("scene");
  EXPECT_EQ(t.loadText().roots.size(), 1u) << "without scenes, every node without a parent is drawn";
}

// tinygltf takes a file's size as 32 bits: a larger file was parsed cut short and refused as
// malformed. It is refused for its size, before a byte of it is read (a sparse file here).
TEST(Loader, AFileOverFourGiBIsRefusedUnread) {
  const auto path = test::scratchDir("huge") / "huge.glb";
  std::filesystem::remove(path);
  std::ofstream(path, std::ios::binary) << "glTF";
  std::error_code ec;
  std::filesystem::resize_file(path, (uintmax_t(1) << 32) + 1, ec);
  if (ec) GTEST_SKIP() << "this file system holds no sparse 4 GiB file: " << ec.message();
  const std::string name = path.string();
  EXPECT_THAT([&] { loadGltf(name); },
              ThrowsMessage<LoadError>(HasSubstr("huge.glb: is 4294967297 bytes, more than a glTF file may hold")));
  std::filesystem::remove(path);
}

TEST(Loader, MalformedAssimpModelsAreRefused) {
  auto dir = test::assimpGltfDir();
  for (const char* file : {"IndexOutOfRange/IndexOutOfRange.gltf", "MissingBin/BoxTextured.gltf",
                           "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "RecursiveNodes/RecursiveNodes.gltf"}) {
    EXPECT_THAT([&] { loadGltf((dir / file).string()); }, ThrowsMessage<LoadError>(HasSubstr(file)))
        << "refused, naming the file";
  }
  // Properties of a type the schema does not allow, which tinygltf read as absent.
  for (const auto& [file, property] : std::vector<std::pair<std::string, std::string>>{
           {"wrongTypes/badArray.gltf", "meshes[0].primitives"},
           {"wrongTypes/badObject.gltf", "materials[0].pbrMetallicRoughness"},
           {"wrongTypes/badUint.gltf", "materials[0].pbrMetallicRoughness.baseColorTexture.index"},
           {"wrongTypes/badExtension.gltf", "baseColorTexture.extensions.KHR_texture_transform"}}) {
    const std::string path = (dir / file).string();  // (clang 14 captures no structured binding)
    EXPECT_THAT([&] { loadGltf(path); }, ThrowsMessage<LoadError>(AllOf(HasSubstr(file), HasSubstr(property))));
  }
  EXPECT_NO_THROW(loadGltf((dir / "wrongTypes/badString.gltf").string())) << "a node's name of another type";
}

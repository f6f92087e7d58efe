// glTF's normal textures: the shading normal each texel gives in the triangle's own tangent frame,
// and the light the path tracer, iv and ar reflect at it, against closed forms.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>

#include "engine/scene/geometry.h"
#include "engine/scene/gltf.h"
#include "engine/scene/texture_sampling.h"
#include "scenes/gltf_builder.h"
#include "shaders/interface.h"
#include "tests/test_support.h"

namespace ivgi {
namespace {

constexpr double kPi = 3.14159265358979;

// A tile of the test floor: a 1 m square facing up at `centre`, its u along +x (or −x, mirrored) and
// v along +z, under a normal texture of one texel `texel` (linear bytes) read at `scale`.
struct Tile {
  glm::vec3 centre;
  std::array<uint8_t, 3> texel;
  float scale;
  bool mirrored;
};

// Four tiles around the origin: the flat texel, a tilt toward +u (red), a tilt toward −v (green) at
// scale 2, and the red tilt on a tile whose u runs the other way.
const std::array<Tile, 4> kTiles = {
    Tile{{-0.6f, 0, -0.6f}, {128, 128, 255}, 1.0f, false}, Tile{{0.6f, 0, -0.6f}, {192, 128, 238}, 1.0f, false},
    Tile{{-0.6f, 0, 0.6f}, {128, 192, 238}, 2.0f, false}, Tile{{0.6f, 0, 0.6f}, {192, 128, 238}, 1.0f, true}};

// The normal glTF defines for tile t: its texel × 2 − 1, x and y scaled, in the frame whose
// tangent runs along increasing u, bitangent along decreasing v (the image's up) and normal up.
glm::dvec3 expectedNormal(const Tile& t) {
  const glm::dvec3 m = glm::dvec3(t.texel[0], t.texel[1], t.texel[2]) / 255.0 * 2.0 - 1.0;
  const glm::dvec3 tangent(t.mirrored ? -1 : 1, 0, 0), bitangent(0, 0, -1), normal(0, 1, 0);
  return glm::normalize(tangent * (m.x * t.scale) + bitangent * (m.y * t.scale) + normal * m.z);
}

struct Floor {
  std::function<void(scenes::GltfBuilder&)> lights;  // what lights it
  bool metal = false;                                // a rough metal, not Lambertian grey 0.5
  bool fromBelow = false;                            // its materials double-sided and the camera under it
};

// The tiles as a glTF model, each with its own one-texel normal texture, seen from 3 m above (x to
// the image's right, z down it) or below (x to its left).
tinygltf::Model tiledFloor(const Floor& floor) {
  scenes::GltfBuilder b;
  std::vector<std::pair<scenes::MeshData, int>> primitives;
  for (size_t i = 0; i < kTiles.size(); ++i) {
    const Tile& t = kTiles[i];
    scenes::MeshData tile;
    const glm::vec3 c = t.centre;
    if (t.mirrored)  // p0 → p1 runs along −x
      scenes::addQuad(tile, c + glm::vec3(0.5f, 0, -0.5f), c + glm::vec3(-0.5f, 0, -0.5f),
                      c + glm::vec3(-0.5f, 0, 0.5f), c + glm::vec3(0.5f, 0, 0.5f), 2, 2, c + glm::vec3(0, 1, 0));
    else
      scenes::addQuad(tile, c + glm::vec3(-0.5f, 0, -0.5f), c + glm::vec3(0.5f, 0, -0.5f), c + glm::vec3(0.5f, 0, 0.5f),
                      c + glm::vec3(-0.5f, 0, 0.5f), 2, 2, c + glm::vec3(0, 1, 0));
    const std::string name = "tile " + std::to_string(i);
    primitives.push_back(
        {tile, floor.metal ? b.glossyMaterial(name, glm::vec3(0.9f), 1.0f, 0.35f) : b.material(name, glm::vec3(0.5f))});
  }
  b.node("floor", b.mesh("floor", primitives));
  floor.lights(b);
  const float side = floor.fromBelow ? -1.0f : 1.0f;
  b.camera("view", 0.9f, 0.01f, {0, 3 * side, 0}, glm::quatLookAtRH(glm::vec3(0, -side, 0), glm::vec3(0, 0, -1)));
  tinygltf::Model m = b.finish();
  for (size_t i = 0; i < kTiles.size(); ++i) {
    m.materials[i].normalTexture.index =
        test::addTexture(m, 1, 1, {kTiles[i].texel[0], kTiles[i].texel[1], kTiles[i].texel[2], 255});
    m.materials[i].normalTexture.scale = kTiles[i].scale;
    m.materials[i].doubleSided = floor.fromBelow;
  }
  return m;
}

// The mean of `value(pixel, the floor's point there)` over a 6×6 patch of the 64×64 image at tile
// t's centre, seen from above (or below, mirrored).
double tileMean(const Tile& t, const std::function<double(size_t, glm::dvec3)>& value, bool fromBelow = false) {
  const double halfWidth = 3.0 * std::tan(0.45), right = fromBelow ? -1.0 : 1.0;
  const int column = int((right * t.centre.x / halfWidth + 1.0) * 32.0),
            row = int((t.centre.z / halfWidth + 1.0) * 32.0);
  double sum = 0.0;
  for (int y = row - 3; y < row + 3; ++y)
    for (int x = column - 3; x < column + 3; ++x)
      sum += value(size_t(y) * 64 + size_t(x),
                   glm::dvec3(right * ((x + 0.5) / 32.0 - 1.0) * halfWidth, 0.0, ((y + 0.5) / 32.0 - 1.0) * halfWidth));
  return sum / 36.0;
}
double tileMean(const std::vector<float>& image, const Tile& t, bool fromBelow = false) {
  return tileMean(
      t, [&](size_t i, glm::dvec3) { return double(image[i]); }, fromBelow);
}

// A sun of irradiance 2 toward `toSun` (unit).
std::function<void(scenes::GltfBuilder&)> sunToward(glm::dvec3 toSun) {
  return [toSun](scenes::GltfBuilder& b) {
    b.light("sun", "directional", 2.0f, glm::vec3(toSun), glm::quatLookAtRH(-glm::vec3(toSun), glm::vec3(0, 1, 0)));
  };
}

// Renders `m` with each method at 64×64 without an environment: the red channel.
std::map<std::string, std::vector<float>> renderRed(const tinygltf::Model& m, const std::string& name,
                                                    const std::string& spp = "64", const std::string& env = "none") {
  const std::filesystem::path file = test::scratchDir(name) / "tiles.gltf";
  scenes::writeModel(m, file.string());
  std::map<std::string, std::vector<float>> red;
  for (const std::string method : {"pt", "iv", "ar"}) {
    std::vector<std::string> args = {file.string(), "--method", method, "--size", "64x64", "--env", env};
    if (method == "pt") args.insert(args.end(), {"--spp", spp});
    red[method] = test::channelOf(test::renderExr(name + "-" + method, args), "R");
    EXPECT_EQ(red[method].size(), 64u * 64u) << method;
  }
  return red;
}

// Each method's mean over each tile of `red` against `expected(tile)`, within `tolerance` of it,
// printed beside what the tile would give unturned.
void expectTileMeans(const std::map<std::string, std::vector<float>>& red, const std::string& what,
                     const std::function<double(const Tile&)>& expected,
                     const std::function<double(const Tile&)>& unturned, double tolerance, bool fromBelow = false) {
  for (size_t i = 0; i < kTiles.size(); ++i) {
    const double want = expected(kTiles[i]);
    for (const std::string method : {"pt", "iv", "ar"}) {
      const double got = tileMean(red.at(method), kTiles[i], fromBelow);
      std::printf("[ normals ] %s, tile %zu, %s: %.4f, expected %.4f (unturned %.4f)\n", what.c_str(), i,
                  method.c_str(), got, want, unturned(kTiles[i]));
      EXPECT_NEAR(got, want, tolerance * want) << what << ", tile " << i << ", " << method;
    }
  }
}

}  // namespace

// The host's shading normal on each tile (the one pt shades with) is glTF's, and the file's scale
// and its tile's mapping decide it: the mirrored tile tilts the other way.
TEST(NormalTextures, TheHostTurnsTheNormalAsGltfDefines) {
  const scene::Scene loaded = scene::sceneFromModel(tiledFloor({.lights = [](scenes::GltfBuilder&) {}}), "tiles");
  ASSERT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  const scene::Geometry g = scene::buildGeometry(loaded, 0);
  ASSERT_TRUE(g.normalTextures);
  const std::vector<gpu::WorldVertex> world =
      scene::animateOnHost(g, g.frameInputs(loaded, scene::evaluatePose(loaded, -1, 0.0f)));
  for (size_t i = 0; i < kTiles.size(); ++i) {
    // The tile's first triangle, at its centroid.
    const gpu::Triangle& t = g.triangles[8 * i];
    const glm::dvec3 got = scene::mappedNormalAt(g, world, t, glm::vec3(1.0f / 3.0f), glm::vec3(0, 1, 0)),
                     expected = expectedNormal(kTiles[i]);
    EXPECT_NEAR(glm::length(got - expected), 0.0, 2e-3)
        << "tile " << i << ": " << got.x << " " << got.y << " " << got.z;
  }
}

// A KHR_texture_transform that turns the +u tile's normal texture a quarter turn turns its tangent
// frame with it. A rotation of π/2 maps (u, v) to (v, −u) (the extension's example,
// TextureTransform.TheSpecificationsExample), so increasing u′ runs along +z and decreasing v′
// along +x, and the tilt toward +u′ lands toward +z: on the host, and under a sun in all three
// methods.
TEST(NormalTextures, ATextureTransformTurnsTheFrame) {
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(0.4, 1.5, -1.0));
  tinygltf::Model m = tiledFloor({.lights = sunToward(toSun)});
  m.materials[1].normalTexture.extensions["KHR_texture_transform"] =
      tinygltf::Value(tinygltf::Value::Object{{"rotation", tinygltf::Value(kPi / 2.0)}});
  m.extensionsUsed.push_back("KHR_texture_transform");
  const Tile& tile = kTiles[1];
  const glm::dvec3 texel = glm::dvec3(tile.texel[0], tile.texel[1], tile.texel[2]) / 255.0 * 2.0 - 1.0;
  const glm::dvec3 expected =
      glm::normalize(glm::dvec3(0, 0, 1) * texel.x + glm::dvec3(1, 0, 0) * texel.y + glm::dvec3(0, 1, 0) * texel.z);

  const scene::Scene loaded = scene::sceneFromModel(m, "turned");
  ASSERT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  const scene::Geometry g = scene::buildGeometry(loaded, 0);
  const std::vector<gpu::WorldVertex> world =
      scene::animateOnHost(g, g.frameInputs(loaded, scene::evaluatePose(loaded, -1, 0.0f)));
  const glm::dvec3 host = scene::mappedNormalAt(g, world, g.triangles[8], glm::vec3(1.0f / 3.0f), glm::vec3(0, 1, 0));
  EXPECT_NEAR(glm::length(host - expected), 0.0, 2e-3) << host.x << " " << host.y << " " << host.z;

  const auto red = renderRed(m, "turned");
  const double want = 0.5 / kPi * 2.0 * std::max(glm::dot(expected, toSun), 0.0),
               unturned = 0.5 / kPi * 2.0 * std::max(glm::dot(expectedNormal(tile), toSun), 0.0);
  for (const std::string method : {"pt", "iv", "ar"}) {
    const double got = tileMean(red.at(method), tile);
    std::printf("[ normals ] turned texture, %s: %.4f, expected %.4f (without the transform %.4f)\n", method.c_str(),
                got, want, unturned);
    EXPECT_NEAR(got, want, 0.01 * want) << method;
  }
}

// The turn stays a unit normal, or leaves the normal as it is, whatever the file gives: a scale of
// 0 or past float's range, a texel of no direction, a triangle that maps no area of the texture,
// coordinates far outside it.
TEST(NormalTextures, TheTurnStaysFiniteAtTheExtremes) {
  const glm::vec3 n(0, 1, 0), a(0, 0, 0), b(1, 0, 0), c(0, 0, 1), tilted(0.9f, 0.5f, 0.6f);
  const glm::vec2 ua(0, 0), ub(1, 0), uc(0, 1);
  auto unit = [](glm::vec3 v) { return std::isfinite(glm::length(v)) && std::abs(glm::length(v) - 1.0f) < 1e-5f; };
  EXPECT_EQ(gpu::mappedNormal(n, a, b, c, ua, ub, uc, tilted, 0.0f), n) << "scale 0: the normal's own share alone";
  for (const float scale : {3.0e38f, -3.0e38f, 1e20f, -1.0f}) {
    const glm::vec3 turned = gpu::mappedNormal(n, a, b, c, ua, ub, uc, tilted, scale);
    EXPECT_TRUE(unit(turned)) << "scale " << scale << ": " << turned.x << " " << turned.y << " " << turned.z;
  }
  EXPECT_EQ(gpu::mappedNormal(n, a, b, c, ua, ub, uc, glm::vec3(0.5f), 1.0f), n) << "a texel of no direction";
  EXPECT_EQ(gpu::mappedNormal(n, a, b, c, ua, ua, ua, tilted, 1.0f), n) << "no area of the texture";
  EXPECT_EQ(gpu::mappedNormal(n, a, b, c, ua, ub, ub, tilted, 1.0f), n) << "a line of the texture";
  const glm::vec3 far =
      gpu::mappedNormal(n, a, b, c, glm::vec2(1e30f), glm::vec2(3e30f, 1e30f), glm::vec2(1e30f, 3e30f), tilted, 1.0f);
  EXPECT_TRUE(unit(far)) << far.x << " " << far.y << " " << far.z;
}

// `ivgi info` counts the materials with a normal texture.
TEST(NormalTextures, InfoCountsThem) {
  const std::filesystem::path file = test::scratchDir("info") / "tiles.gltf";
  scenes::writeModel(tiledFloor({.lights = [](scenes::GltfBuilder&) {}}), file.string());
  const auto r = test::runIvgi({"info", file.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("materials    4 (4 with a normal texture, 0 cut by alphaMode MASK, 0 blended)"),
            std::string::npos)
      << r.out;
}

// A file's TANGENT attribute is not read: the loader says once, for the first primitive whose
// material has a normal texture, that the triangles' own frames are used.
TEST(NormalTextures, TangentsInTheFileAreNamedOnce) {
  tinygltf::Model m = tiledFloor({.lights = [](scenes::GltfBuilder&) {}});
  const std::vector<glm::vec4> tangents(9, glm::vec4(1, 0, 0, 1));  // each tile's 3 × 3 vertices
  scenes::GltfBuilder b;
  b.model() = m;
  const int accessor = b.accessor(tangents.data(), tangents.size(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4,
                                  sizeof(glm::vec4), TINYGLTF_TARGET_ARRAY_BUFFER);
  for (auto& p : b.model().meshes[0].primitives) p.attributes["TANGENT"] = accessor;
  const scene::Scene loaded = scene::sceneFromModel(b.model(), "tangents");
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("TANGENT"), std::string::npos) << loaded.warnings[0];
}

// Under a sun, each tile reflects ρ/π · E · cos between the sun and its turned normal, in all
// three methods: a tilt toward the sun brightens a tile, one away darkens it, as glTF's frame puts it.
TEST(NormalTextures, ASunLightsTheTurnedNormals) {
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(1.0, 1.5, 0.7));
  const auto red = renderRed(tiledFloor({.lights = sunToward(toSun)}), "sun");
  expectTileMeans(
      red, "sun", [&](const Tile& t) { return 0.5 / kPi * 2.0 * std::max(glm::dot(expectedNormal(t), toSun), 0.0); },
      [&](const Tile&) { return 0.5 / kPi * 2.0 * toSun.y; }, 0.01);
}

// Under a uniform white sky alone, a tile turned by θ sees the sky above its surface's side and its
// shading normal's horizon: ρ·(1 + cos θ)/2. The solvers carry the sky in their bins, without its
// direction at the pixels; turned as even light, they give it exactly.
TEST(NormalTextures, TheSkyLightsTheTurnedNormals) {
  const auto red = renderRed(tiledFloor({.lights = [](scenes::GltfBuilder&) {}}), "sky", "256", "1,1,1");
  expectTileMeans(
      red, "sky", [](const Tile& t) { return 0.5 * (0.5 + 0.5 * expectedNormal(t).y); },
      [](const Tile&) { return 0.5; }, 0.02);
}

// A small lamp lights the tiles: iv and ar take the lamp's light at the pixels from the depth maps,
// its shadows' share at the surface's normal, and each pixel's turn by its normal texture; all three
// methods agree with the lamp's light at the turned normals, integrated over the lamp.
TEST(NormalTextures, ALampLightsTheTurnedNormals) {
  const glm::dvec3 lampCentre(1.2, 2.0, 0.9);
  constexpr double kHalf = 0.1, kRadiance = 50.0;
  const auto red = renderRed(
      tiledFloor({.lights =
                      [&](scenes::GltfBuilder& b) {
                        scenes::MeshData lamp;
                        const glm::vec3 c(lampCentre);
                        scenes::addQuad(lamp, c + glm::vec3(-kHalf, 0, -kHalf), c + glm::vec3(kHalf, 0, -kHalf),
                                        c + glm::vec3(kHalf, 0, kHalf), c + glm::vec3(-kHalf, 0, kHalf), 1, 1,
                                        c - glm::vec3(0, 1, 0));
                        b.node(
                            "lamp",
                            b.mesh("lamp", {{lamp, b.material("lamp", glm::vec3(0.0f), glm::vec3(float(kRadiance)))}}));
                      }}),
      "lamp");
  // The irradiance at a point of the floor through a normal, by the lamp's 32 × 32 cells.
  auto irradiance = [&](glm::dvec3 p, glm::dvec3 n) {
    double e = 0.0;
    constexpr int kCells = 32;
    const double cell = 2.0 * kHalf / kCells;
    for (int i = 0; i < kCells; ++i)
      for (int j = 0; j < kCells; ++j) {
        const glm::dvec3 q = lampCentre + glm::dvec3(-kHalf + (i + 0.5) * cell, 0.0, -kHalf + (j + 0.5) * cell);
        const glm::dvec3 d = q - p;
        const double d2 = glm::dot(d, d), toward = glm::dot(n, d) / std::sqrt(d2), fromLamp = d.y / std::sqrt(d2);
        e += kRadiance * cell * cell * std::max(toward, 0.0) * fromLamp / d2;
      }
    return e;
  };
  // Over the same pixels' points of the floor.
  auto reflected = [&](const Tile& t, glm::dvec3 n) {
    return tileMean(t, [&](size_t, glm::dvec3 p) { return 0.5 / kPi * irradiance(p, n); });
  };
  expectTileMeans(
      red, "lamp", [&](const Tile& t) { return reflected(t, expectedNormal(t)); },
      [&](const Tile& t) { return reflected(t, glm::dvec3(0, 1, 0)); }, 0.03);
}

// The sun on rough metal tiles: iv's and ar's highlights at the pixels take the turned normal's
// lobe, as the path tracer's do.
TEST(NormalTextures, MetalReflectsTheSunAboutTheTurnedNormals) {
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(0.3, 1.5, 0.2));
  const auto red = renderRed(tiledFloor({.lights = sunToward(toSun), .metal = true}), "metal", "256");
  for (size_t i = 0; i < kTiles.size(); ++i) {
    const double expected = tileMean(red.at("pt"), kTiles[i]);
    for (const std::string method : {"iv", "ar"}) {
      const double got = tileMean(red.at(method), kTiles[i]);
      std::printf("[ normals ] metal under the sun, tile %zu, %s: %.4f, pt %.4f\n", i, method.c_str(), got, expected);
      EXPECT_NEAR(got, expected, 0.05 * expected) << "tile " << i << ", " << method;
    }
  }
}

// The tiles as rough metal under an even white sky alone: what each reflects is its lobe's albedo at
// its turned normal, less what the tile's plane hides of the lobe. On tile 2 the view mirrors about
// the steep normal into the plane, which hides about two fifths of the lobe (brdf.h's
// lobeShareAbove). iv and ar reflected the vertices' light at the mesh's normal as it was: 0.882 on
// every tile, where pt gives 0.884, 0.806, 0.542 and 0.867; now 0.882, 0.836, 0.538 and 0.856 (the
// lobe's albedo at the turned normal is left out: its change with the view's angle is the vertices'
// Fresnel, found for the light as it arrives).
TEST(NormalTextures, MetalReflectsAnEvenSkyAboutTheTurnedNormals) {
  const auto red =
      renderRed(tiledFloor({.lights = [](scenes::GltfBuilder&) {}, .metal = true}), "metal-sky", "256", "1,1,1");
  for (size_t i = 0; i < kTiles.size(); ++i) {
    const double expected = tileMean(red.at("pt"), kTiles[i]);
    for (const std::string method : {"iv", "ar"}) {
      const double got = tileMean(red.at(method), kTiles[i]);
      std::printf("[ normals ] metal under an even sky, tile %zu, %s: %.4f, pt %.4f\n", i, method.c_str(), got,
                  expected);
      EXPECT_NEAR(got, expected, 0.05 * expected) << "tile " << i << ", " << method;
    }
  }
}

// The tiles double-sided under a sun from below, seen from below: their backs turn the normal
// texture's normals as their fronts do, reversed (the backs' own surfels in iv and ar, both sides of
// a face in pt). Tile 2's steep normal mirrors the view below the tile's plane there, so every method
// shades with it lifted (scene.h's liftedShadingNormal): 0.2634 where the normal as turned gives
// 0.2471.
TEST(NormalTextures, TheBacksOfDoubleSidedTilesTurnTheirNormalsReversed) {
  const glm::dvec3 toSun = glm::normalize(glm::dvec3(1.0, -1.5, 0.7)), eye(0.0, -3.0, 0.0);
  const auto red = renderRed(tiledFloor({.lights = sunToward(toSun), .fromBelow = true}), "below");
  const auto lit = [&](const Tile& t, glm::dvec3 p) {
    const glm::vec3 n = gpu::liftedShadingNormal(glm::vec3(0, -1, 0), glm::vec3(glm::normalize(eye - p)),
                                                 -glm::vec3(expectedNormal(t)));
    return 0.5 / kPi * 2.0 * std::max(glm::dot(glm::dvec3(n), toSun), 0.0);
  };
  expectTileMeans(
      red, "from below",
      [&](const Tile& t) {
        return tileMean(
            t, [&](size_t, glm::dvec3 p) { return lit(t, p); }, true);
      },
      [&](const Tile&) { return 0.5 / kPi * 2.0 * -toSun.y; }, 0.01, true);
}

// A smooth ball under a striped normal texture, lit by a small lamp from the side, over a floor: iv
// and ar agree with the path tracer across the ball, also where the lamp lies near the horizon of
// the ball's smooth normal and well above that of the turned one (the pixels' turn of the lamp's
// light stays bounded there).
TEST(NormalTextures, AStripedBallAgreesWithThePathTracer) {
  scenes::GltfBuilder b;
  scenes::MeshData ball, floor, lamp;
  constexpr int kRings = 24, kSegments = 48;
  constexpr double kRadius = 0.4;
  for (int i = 0; i <= kRings; ++i)
    for (int j = 0; j <= kSegments; ++j) {
      const double theta = kPi * i / kRings, phi = 2.0 * kPi * j / kSegments;
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      ball.positions.push_back(float(kRadius) * n + glm::vec3(0, float(kRadius), 0));
      ball.normals.push_back(n);
      ball.uvs.push_back(glm::vec2(float(j) / kSegments, float(i) / kRings));
    }
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) {
      const uint32_t v = uint32_t(i * (kSegments + 1) + j), w = kSegments + 1;
      if (i > 0) ball.indices.insert(ball.indices.end(), {v, v + 1, v + w});
      if (i + 1 < kRings) ball.indices.insert(ball.indices.end(), {v + 1, v + w + 1, v + w});
    }
  scenes::addQuad(floor, {-1.5f, 0, -1.5f}, {1.5f, 0, -1.5f}, {1.5f, 0, 1.5f}, {-1.5f, 0, 1.5f}, 4, 4, {0, 1, 0});
  const glm::vec3 lampAt(1.2f, 0.45f, 0.3f);
  scenes::addQuad(lamp, lampAt + glm::vec3(0, -0.1f, -0.1f), lampAt + glm::vec3(0, 0.1f, -0.1f),
                  lampAt + glm::vec3(0, 0.1f, 0.1f), lampAt + glm::vec3(0, -0.1f, 0.1f), 1, 1, glm::vec3(0, 0.45f, 0));
  b.node("ball", b.mesh("ball", {{ball, b.material("ball", glm::vec3(0.7f))}}));
  b.node("floor", b.mesh("floor", {{floor, b.material("floor", glm::vec3(0.5f))}}));
  b.node("lamp", b.mesh("lamp", {{lamp, b.material("lamp", glm::vec3(0.0f), glm::vec3(40.0f))}}));
  b.camera("view", 0.7f, 0.01f, {0.2f, 0.9f, 1.6f},
           glm::quatLookAtRH(glm::normalize(glm::vec3(-0.2f, -0.5f, -1.6f)), glm::vec3(0, 1, 0)));
  tinygltf::Model m = b.finish();
  // Eight stripes along u, tilted 40° toward +u and −u in turn.
  std::vector<uint8_t> stripes;
  for (int x = 0; x < 8; ++x) stripes.insert(stripes.end(), {uint8_t(x % 2 ? 46 : 209), 128, 225, 255});
  tinygltf::Sampler nearest;
  nearest.magFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  m.samplers.push_back(nearest);
  const int stripesTexture = test::addTexture(m, 8, 1, std::move(stripes), int(m.samplers.size() - 1));
  // The direct light alone, each method against pt, with the texture and without (the same
  // scene's error from what the normal texture does not touch).
  auto errors = [&](bool striped) {
    m.materials[0].normalTexture.index = striped ? stripesTexture : -1;
    const std::string name = striped ? "striped" : "plain";
    const std::filesystem::path file = test::scratchDir(name) / "ball.gltf";
    scenes::writeModel(m, file.string());
    std::map<std::string, std::vector<float>> red;
    for (const std::string method : {"pt", "iv", "ar"}) {
      std::vector<std::string> args = {file.string(), "--method", method,      "--size", "80x60",
                                       "--env",       "none",     "--bounces", "0"};
      args.insert(args.end(), {method == "pt" ? "--spp" : "--supersample", method == "pt" ? "1024" : "4"});
      red[method] = test::channelOf(test::renderExr(name + "-" + method, args), "R");
      EXPECT_EQ(red[method].size(), 80u * 60u) << method;
    }
    std::map<std::string, double> relMse;
    for (const std::string method : {"iv", "ar"}) {
      double squares = 0.0;
      for (size_t i = 0; i < red["pt"].size(); ++i) {
        const double reference = red["pt"][i], got = red[method][i];
        EXPECT_TRUE(std::isfinite(got)) << method;
        squares += (got - reference) * (got - reference) / (reference * reference + 0.01);
      }
      relMse[method] = squares / double(red["pt"].size());
    }
    return relMse;
  };
  const auto plain = errors(false), striped = errors(true);
  for (const std::string method : {"iv", "ar"}) {
    std::printf("[ normals ] %s against pt, the direct light: relMSE %.5f striped, %.5f plain\n", method.c_str(),
                striped.at(method), plain.at(method));
    EXPECT_LT(striped.at(method), 1.5 * plain.at(method) + 0.002) << method;
  }
}

}  // namespace ivgi

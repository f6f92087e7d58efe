// The backs of open double-sided surfaces (engine/scene/back_faces.h): which faces get one, what it
// is, and that iv and ar then light a sheet from behind as the path tracer does.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "engine/scene/back_faces.h"
#include "engine/scene/geometry.h"
#include "engine/scene/gltf.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

namespace ivgi {
namespace {

using scene::Geometry;

// `mesh` on one node, its material grey and double-sided (or not), and with `pebble` a single-sided
// cube of side 0.4 m at (0, −0.6, 0); its geometry as modelled, open space lit or dark.
Geometry geometryOf(const scenes::MeshData& mesh, bool doubleSided, scene::OpenSpace openSpace = scene::OpenSpace::Lit,
                    bool pebble = false) {
  scenes::GltfBuilder b;
  b.node("mesh", b.mesh("mesh", {{mesh, b.material("grey", glm::vec3(0.5f))}}));
  if (pebble) {
    scenes::MeshData cube;
    scenes::addBox(cube, {0, -0.6f, 0}, glm::vec3(0.2f), 1);
    b.node("pebble", b.mesh("pebble", {{cube, b.material("pebble", glm::vec3(0.5f))}}));
  }
  tinygltf::Model m = b.finish();
  m.materials[0].doubleSided = doubleSided;
  return scene::buildGeometry(scene::sceneFromModel(m, "mesh"), 0, {}, {}, openSpace);
}

// The faces of an axis-aligned box's six sides, `cells` × `cells` each, facing out, less the first
// `missing` cells of its top (+y).
scenes::MeshData boxWithHole(int cells, int missing) {
  scenes::MeshData box;
  scenes::addBox(box, glm::vec3(0.0f), glm::vec3(1.0f), cells);
  scenes::MeshData out = box;
  out.indices.clear();
  int removed = 0;
  for (size_t t = 0; t + 2 < box.indices.size(); t += 6) {  // two triangles a cell
    bool top = true;
    for (size_t k = t; k < t + 6; ++k) top = top && box.positions[box.indices[k]].y > 0.999f;
    if (top && removed < missing) {
      ++removed;
      continue;
    }
    out.indices.insert(out.indices.end(), box.indices.begin() + std::ptrdiff_t(t),
                       box.indices.begin() + std::ptrdiff_t(t + 6));
  }
  EXPECT_EQ(removed, missing);
  return out;
}

TEST(BackFaces, AnOpenDoubleSidedSheetGetsAWholeBack) {
  scenes::MeshData sheet;
  scenes::addQuad(sheet, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 4, 4, {0, 1, 0});
  const Geometry one = geometryOf(sheet, false), two = geometryOf(sheet, true);
  EXPECT_EQ(one.backTriangles, 0u) << "a single-sided material has none";
  ASSERT_EQ(two.triangles.size(), 2 * one.triangles.size());
  ASSERT_EQ(two.backTriangles, one.triangles.size());
  EXPECT_EQ(two.backSurfels, one.surfels.size());
  for (const scene::Triangle& t : two.triangles) EXPECT_NE(t.material & gpu::kTwinned, 0u);
  // The back: the same places, the normals reversed, wound the other way, on a material without
  // emission of its own.
  const size_t fronts = one.triangles.size();
  for (size_t t = 0; t < fronts; ++t) {
    const scene::Triangle &front = two.triangles[t], &back = two.triangles[fronts + t];
    const glm::vec3 a = two.vertices[front.v0].position, b = two.vertices[front.v1].position,
                    c = two.vertices[front.v2].position;
    EXPECT_EQ(two.vertices[back.v0].position, a);
    EXPECT_EQ(two.vertices[back.v1].position, c);
    EXPECT_EQ(two.vertices[back.v2].position, b);
    EXPECT_EQ(two.vertices[back.v0].normal, -two.vertices[front.v0].normal);
    EXPECT_NE(back.material & ~gpu::kTriangleFlags, front.material & ~gpu::kTriangleFlags);
  }
  const std::vector<bool> twinned = scene::twinnedSurfels(two);
  EXPECT_EQ(std::count(twinned.begin(), twinned.end(), true), std::ptrdiff_t(two.surfels.size()));
}

// A closed box's backs face its inside, where every ray from them meets another back: none is
// copied. With its top missing, every back sees the open sky: all are, where open space is lit (a
// sky, a sun); where it is dark, only those that see another object, a pebble inside. With 16 cells
// of 384 missing, only the faces that see out through them, through an eighth of their hemisphere.
TEST(BackFaces, OnlyTheBacksThatSeeOut) {
  const Geometry closed = geometryOf(boxWithHole(8, 0), true);
  EXPECT_EQ(closed.backTriangles, 0u);

  // The backs whose faces lie in the bottom, which sees the open top above it.
  auto bottomBacks = [](const Geometry& g) {
    size_t n = 0;
    for (size_t t = g.triangles.size() - g.backTriangles; t < g.triangles.size(); ++t)
      n += g.vertices[g.triangles[t].v0].position.y < -0.999f && g.vertices[g.triangles[t].v1].position.y < -0.999f &&
           g.vertices[g.triangles[t].v2].position.y < -0.999f;
    return n;
  };
  const Geometry open = geometryOf(boxWithHole(8, 64), true);
  EXPECT_EQ(bottomBacks(open), 128u) << "the bottom's faces, under the open top";
  std::printf("[ backs ] a box without a top, open space lit: %u of %zu faces get a back\n", open.backTriangles,
              open.triangles.size() - open.backTriangles);
  const Geometry dark = geometryOf(boxWithHole(8, 64), true, scene::OpenSpace::Dark);
  EXPECT_EQ(dark.backTriangles, 0u) << "nothing but dark open space outside";
  const Geometry pebbled = geometryOf(boxWithHole(8, 64), true, scene::OpenSpace::Dark, true);
  std::printf("[ backs ] a box without a top, a pebble inside, open space dark: %u backs\n", pebbled.backTriangles);
  EXPECT_GT(pebbled.backTriangles, 0u);
  // The bottom's middle, right under the pebble, sees it whole.
  bool middle = false;
  for (size_t t = pebbled.triangles.size() - pebbled.backTriangles; t < pebbled.triangles.size(); ++t) {
    const scene::Triangle& x = pebbled.triangles[t];
    const glm::vec3 centroid =
        (pebbled.vertices[x.v0].position + pebbled.vertices[x.v1].position + pebbled.vertices[x.v2].position) / 3.0f;
    middle = middle || (centroid.y < -0.999f && std::abs(centroid.x) < 0.25f && std::abs(centroid.z) < 0.25f);
  }
  EXPECT_TRUE(middle);

  const Geometry holed = geometryOf(boxWithHole(8, 16), true);
  const size_t fronts = holed.triangles.size() - holed.backTriangles;
  std::printf("[ backs ] a box with 16 cells of 384 open: %u of %zu faces get a back\n", holed.backTriangles, fronts);
  EXPECT_GT(holed.backTriangles, 0u);
  EXPECT_LT(holed.backTriangles, fronts / 2);
}

// A sheet facing up, a small lamp under it facing up at its back, the camera under both: the sheet's
// underside is lit in pt, and where its material is double-sided, in iv and ar as well, by the same
// light within a few per cent. The lamp, double-sided too, shows its unlit back to the camera in all
// three: its back neither glows nor lights.
TEST(BackFaces, ASheetLitFromBehind) {
  scenes::GltfBuilder b;
  scenes::MeshData sheet, lamp;
  scenes::addQuad(sheet, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 8, 8, {0, 1, 0});
  scenes::addQuad(lamp, {-0.2f, -1, -0.2f}, {0.2f, -1, -0.2f}, {0.2f, -1, 0.2f}, {-0.2f, -1, 0.2f}, 1, 1, {0, 1, 0});
  b.node("sheet", b.mesh("sheet", {{sheet, b.material("paper", glm::vec3(0.8f))}}));
  b.node("lamp", b.mesh("lamp", {{lamp, b.material("lamp", glm::vec3(0.0f), glm::vec3(20.0f))}}));
  // Under the lamp, looking up (+y), the image's up along -z.
  b.camera("under", 0.9f, 0.01f, {0, -3, 0}, glm::quatLookAtRH(glm::vec3(0, 1, 0), glm::vec3(0, 0, -1)));
  tinygltf::Model m = b.finish();
  for (auto& material : m.materials) material.doubleSided = true;
  const std::filesystem::path file = test::scratchDir("lit_from_behind") / "sheet.gltf";
  scenes::writeModel(m, file.string());

  std::map<std::string, std::vector<float>> green;
  for (const std::string method : {"pt", "iv", "ar"}) {
    std::vector<std::string> args = {file.string(), "--method", method, "--size", "64x48", "--env", "none"};
    if (method == "pt") args.insert(args.end(), {"--spp", "256"});
    green[method] = test::channelOf(test::renderExr("lit_from_behind-" + method, args), "G");
    ASSERT_EQ(green[method].size(), 64u * 48u) << method;
  }
  // The sheet: rows 9–18 and columns 17–47 (the lamp covers rows 19–29 and columns 27–37); the lamp:
  // the image's centre.
  auto meanOver = [](const std::vector<float>& image, int row0, int row1, int column0, int column1) {
    double sum = 0.0;
    for (int y = row0; y < row1; ++y)
      for (int x = column0; x < column1; ++x) sum += image[size_t(y) * 64 + size_t(x)];
    return sum / double((row1 - row0) * (column1 - column0));
  };
  const double underside = meanOver(green["pt"], 9, 18, 17, 47), lampBack = meanOver(green["pt"], 22, 26, 30, 34);
  std::printf("[ backs ] pt: the sheet's underside %.4f, the lamp's back %.4f\n", underside, lampBack);
  ASSERT_GT(underside, 0.02);
  EXPECT_LT(lampBack, 0.01 * underside);
  for (const std::string method : {"iv", "ar"}) {
    const double got = meanOver(green[method], 9, 18, 17, 47), back = meanOver(green[method], 22, 26, 30, 34);
    std::printf("[ backs ] %s: the sheet's underside %.4f (pt's × %.3f), the lamp's back %.4f\n", method.c_str(), got,
                got / underside, back);
    EXPECT_NEAR(got, underside, 0.05 * underside) << method;
    EXPECT_LT(back, 0.01 * underside) << method;
  }
}

// The same sheet and lamp over a floor, seen from the side. The lamp faces up, so without a sky the
// floor is lit only by what the sheet's underside sends down: in iv and ar, by its back's surfels,
// which the floor's receivers see in place of the fronts turned away from them. Under a white sky
// the sheet also shades the floor: in ar, its antiradiance, which the fronts alone send (both
// copies sending it took 14 % off the floor's light).
TEST(BackFaces, TheUndersideLightsTheFloorBelow) {
  scenes::GltfBuilder b;
  scenes::MeshData sheet, lamp, floor;
  scenes::addQuad(sheet, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 8, 8, {0, 1, 0});
  scenes::addQuad(lamp, {-0.2f, -1, -0.2f}, {0.2f, -1, -0.2f}, {0.2f, -1, 0.2f}, {-0.2f, -1, 0.2f}, 1, 1, {0, 1, 0});
  scenes::addQuad(floor, {-2, -2, -2}, {2, -2, -2}, {2, -2, 2}, {-2, -2, 2}, 8, 8, {0, 1, 0});
  b.node("sheet", b.mesh("sheet", {{sheet, b.material("paper", glm::vec3(0.8f))}}));
  b.node("lamp", b.mesh("lamp", {{lamp, b.material("lamp", glm::vec3(0.0f), glm::vec3(20.0f))}}));
  b.node("floor", b.mesh("floor", {{floor, b.material("floor", glm::vec3(0.8f))}}));
  b.camera("side", 0.9f, 0.01f, {0, -1.3f, 3.0f},
           glm::quatLookAtRH(glm::normalize(glm::vec3(0, -0.5f, -1)), glm::vec3(0, 1, 0)));
  tinygltf::Model m = b.finish();
  m.materials[0].doubleSided = true;
  const std::filesystem::path file = test::scratchDir("floor_below") / "sheet.gltf";
  scenes::writeModel(m, file.string());
  // The floor fills rows 10–32 of the image; its far edge, rows 9 and 10, is left out.
  auto floorMean = [](const std::vector<float>& image) {
    double sum = 0.0;
    for (int y = 12; y < 31; ++y)
      for (int x = 4; x < 60; ++x) sum += image[size_t(y) * 64 + size_t(x)];
    return sum / (19.0 * 56.0);
  };
  for (const std::string env : {"none", "1,1,1"}) {
    double pt = 0.0;
    for (const std::string method : {"pt", "iv", "ar"}) {
      std::vector<std::string> args = {file.string(), "--method", method, "--size", "64x48", "--env", env};
      if (method == "pt") args.insert(args.end(), {"--spp", "256"});
      const std::vector<float> green = test::channelOf(test::renderExr("floor_below-" + method, args), "G");
      ASSERT_EQ(green.size(), 64u * 48u) << method;
      const double mean = floorMean(green);
      if (method == "pt") pt = mean;
      std::printf("[ backs ] --env %s, %s: the floor under the sheet %.4f (pt's × %.3f)\n", env.c_str(), method.c_str(),
                  mean, mean / pt);
      EXPECT_NEAR(mean, pt, 0.05 * pt) << method << ", --env " << env;
    }
    EXPECT_GT(pt, 0.01);
  }
}

}  // namespace
}  // namespace ivgi

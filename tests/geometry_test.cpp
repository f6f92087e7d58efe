// The animate and surfel passes on the GPU against their host evaluations, and the surfel rules of
// docs/design.md §2.1: areas, welded seams, degenerate triangles, tessellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include "engine/gi/frame_renderer.h"
#include "engine/gi/hierarchy.h"
#include "engine/gi/pass.h"
#include "engine/gi/raster.h"
#include "engine/scene/gltf.h"
#include "engine/scene/map_meshes.h"
#include "engine/scene/planar_faces.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
using namespace ivgi::scene;

namespace {

struct Case {
  std::string name;
  Scene scene;
  int animation;
  float time;
};

float scaleOf(const std::vector<WorldVertex>& w) {
  Bounds b = worldBounds(w);
  return std::max(glm::length(b.max - b.min), 1e-6f);
}

// Animates `c` on the GPU and on the host; returns how far the animated vertices are from the rest pose
// (so that a test can check the case really moves).
float compareGpuWithHost(const Case& c) {
  Geometry g = buildGeometry(c.scene);
  FrameInputs in = g.frameInputs(c.scene, evaluatePose(c.scene, c.animation, c.time));
  gi::FrameRenderer renderer(test::gpu(), g, {32, 24, 1});
  renderer.render(in, framingCamera(worldBounds(animateOnHost(g, in)), 32.0f / 24.0f));

  auto host = animateOnHost(g, in);
  auto device = renderer.worldVertices();
  EXPECT_EQ(host.size(), device.size());
  float scale = scaleOf(host), worstPosition = 0, worstNormal = 0;
  for (size_t i = 0; i < host.size(); ++i) {
    worstPosition = std::max(worstPosition, glm::length(glm::vec3(host[i].position - device[i].position)) / scale);
    worstNormal = std::max(worstNormal, glm::length(glm::vec3(host[i].normal - device[i].normal)));
  }
  EXPECT_LT(worstPosition, 1e-5f) << c.name;
  EXPECT_LT(worstNormal, 1e-4f) << c.name;

  auto hostSurfels = surfelsOnHost(g, host), deviceSurfels = renderer.surfels();
  EXPECT_EQ(hostSurfels.size(), deviceSurfels.size());
  float worstArea = 0, worstExtent = 0;
  for (size_t i = 0; i < hostSurfels.size(); ++i) {
    float a = hostSurfels[i].positionArea.w, b = deviceSurfels[i].positionArea.w;
    worstArea = std::max(worstArea, std::abs(a - b) / std::max(a, 1e-20f));
    // Per half-extent: sliver surfels (230:1 in BoxAnimated) keep float's relative precision on each side.
    for (int k : {2, 3})
      worstExtent = std::max(worstExtent, std::abs(hostSurfels[i].shape[k] - deviceSurfels[i].shape[k]) /
                                              std::max(hostSurfels[i].shape[k], 1e-20f));
  }
  EXPECT_LT(worstArea, 1e-4f) << c.name;
  EXPECT_LT(worstExtent, 1e-3f) << c.name;

  auto rest = animateOnHost(g, g.frameInputs(c.scene, evaluatePose(c.scene, -1, 0.0f)));
  float moved = 0;
  for (size_t i = 0; i < rest.size(); ++i)
    moved = std::max(moved, glm::length(glm::vec3(rest[i].position - host[i].position)) / scale);
  return moved;
}

float totalArea(const std::vector<Surfel>& surfels) {
  double sum = 0;
  for (const auto& s : surfels) sum += s.positionArea.w;
  return float(sum);
}

}  // namespace

TEST(GpuAnimation, MorphTargetsMatchTheHost) {
  auto path = test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  Case c{"AnimatedMorphCube", loadGltf(path.string()), 0, 1.3f};
  EXPECT_GT(compareGpuWithHost(c), 0.01f) << "the morph animation should move vertices";
}

TEST(GpuAnimation, SkinningMatchesTheHost) {
  auto path = test::assimpGltfDir() / "simple_skin/simple_skin.gltf";
  Case c{"simple_skin", loadGltf(path.string()), 0, 1.25f};
  EXPECT_GT(compareGpuWithHost(c), 0.01f);
}

TEST(GpuAnimation, NodeTransformsMatchTheHost) {
  Case c{"cornell", sceneFromModel(scenes::cornellBox({.cells = 4}), "cornell"), 0, 0.5f};
  EXPECT_GT(compareGpuWithHost(c), 0.01f);
}

TEST(GpuAnimation, SharedAssetsMatchTheHost) {
  auto dir = test::sharedGltfDir();
  if (!dir) GTEST_SKIP() << "../shared/data/gltf is not present";
  for (const char* file : {"Fox.gltf", "RiggedSimple.gltf", "SimpleMorph.gltf", "BoxAnimated.gltf",
                           "AnimatedTriangle.gltf", "SimpleSkin.gltf"}) {
    Scene s = loadGltf((*dir / file).string());
    int anim = s.animations.empty() ? -1 : int(s.animations.size()) - 1;
    float t = anim >= 0 ? 0.37f * (s.animations[anim].end - s.animations[anim].start) + s.animations[anim].start : 0.0f;
    Case c{file, std::move(s), anim, t};
    EXPECT_GT(compareGpuWithHost(c), 1e-3f) << file;
  }
}

TEST(Surfels, AreasSumToTheMeshArea) {
  // The furnace is a closed unit cube: 6 m² whatever its tessellation.
  for (int cells : {1, 3, 8}) {
    Scene s = sceneFromModel(scenes::furnace({.cells = cells}), "furnace");
    Geometry g = buildGeometry(s);
    auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
    EXPECT_NEAR(totalArea(surfels), 6.0f, 6.0f * 1e-5f) << cells << " cells";
    EXPECT_EQ(surfels.size(), size_t(6 * (cells + 1) * (cells + 1))) << "cube edges are hard: not welded";
  }
  // The Cornell box, against the sum of its triangles' areas.
  Scene s = sceneFromModel(scenes::cornellBox({.cells = 5}), "cornell");
  Geometry g = buildGeometry(s);
  auto world = animateOnHost(g, g.frameInputs(s, evaluatePose(s, 0, 0.7f)));
  double triangles = 0;
  for (const auto& t : g.triangles)
    triangles += 0.5 * glm::length(glm::cross(glm::vec3(world[t.v1].position - world[t.v0].position),
                                              glm::vec3(world[t.v2].position - world[t.v0].position)));
  EXPECT_NEAR(totalArea(surfelsOnHost(g, world)), triangles, triangles * 1e-5);
}

// The rectangles the pruning files senders as: on a regular grid they tile the face as the surfels'
// areas do (inner surfels their cell, border ones the half-cell strip from their vertex in),
// whatever the grid's turn in the tangent frame, since their axes follow the mesh's edges and reach
// half way to the neighbours. Sampled on a fine grid, at least 95 % of a 1 m square lies in exactly
// one rectangle (96.5 % and 97.4 % at 4 cells, straight and turned, 99.7 % at 9); the rectangles of
// the areas' second moments left 93 %, squares of the same areas less than that at 4 cells, and
// rectangles along the tangent frame 78 % of the square turned by half a radian. A border surfel's
// centroid lies off its vertex along the border, so its strip is shifted against the row inside.
TEST(Surfels, RectanglesTileAFlatFace) {
  for (int cells : {4, 9})
    for (float turn : {0.0f, 0.5f}) {
      const float c = std::cos(turn), sn = std::sin(turn);
      auto at = [&](float u, float v) { return glm::vec3(c * u - sn * v, 0.0f, sn * u + c * v); };  // u, v in [0, 1]
      scenes::MeshData square;
      scenes::addQuad(square, at(0, 0), at(1, 0), at(1, 1), at(0, 1), cells, cells, {0, 1, 0});
      scenes::GltfBuilder b;
      b.node("square", b.mesh("square", {{square, b.material("grey", glm::vec3(0.5f))}}));
      Scene s = sceneFromModel(b.finish(), "square");
      Geometry g = buildGeometry(s);
      auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
      const int samples = 180;
      int once = 0;
      for (int i = 0; i < samples; ++i)
        for (int j = 0; j < samples; ++j) {
          const glm::vec3 point = at((i + 0.5f) / samples, (j + 0.5f) / samples);
          int inside = 0;
          for (const auto& sf : surfels) {
            glm::vec3 u1, u2, d = point - glm::vec3(sf.positionArea);
            gpu::rectangleAxes(glm::vec3(sf.normal), sf.shape.y, u1, u2);
            inside += std::abs(glm::dot(d, u1)) < sf.shape.z && std::abs(glm::dot(d, u2)) < sf.shape.w;
          }
          once += inside == 1;
        }
      EXPECT_GE(once, 0.95 * samples * samples) << cells << " cells, turned " << turn;
      std::printf("[ tile ] %d cells, turned %.1f: %.3f\n", cells, turn, once / double(samples * samples));
    }
}

TEST(Surfels, UvSeamsAreWeldedHardEdgesAreNot) {
  // Two triangles of one square; the diagonal's vertices are duplicated with other UVs (a seam).
  scenes::MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.normals.assign(6, glm::vec3(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0.5f, 0}, {0.5f, 1}, {0, 1}};
  m.indices = {0, 1, 2, 3, 4, 5};
  // A second square folded at 90° along x = 1: same positions on the fold, other normals (hard edge).
  scenes::MeshData fold;
  fold.positions = {{1, 0, 0}, {1, 0, -1}, {1, 1, -1}, {1, 1, 0}};
  fold.normals.assign(4, glm::vec3(-1, 0, 0));
  fold.indices = {0, 1, 2, 0, 2, 3};
  scenes::GltfBuilder b;
  int mat = b.material("grey", glm::vec3(0.5f));
  b.node("seam", b.mesh("seam", {{m, mat}}));
  b.node("fold", b.mesh("fold", {{fold, mat}}));
  Scene s = sceneFromModel(b.finish(), "seam");
  Geometry g = buildGeometry(s);
  ASSERT_EQ(g.surfels.size(), 4u + 4u) << "6 seam vertices weld to 4; the fold's 4 stay apart";
  auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
  // Corner (0,0,0) and (1,1,0) touch both triangles: area 2 × (0.5 / 3); the others one triangle.
  std::vector<float> areas;
  for (size_t i = 0; i < 4; ++i) areas.push_back(surfels[i].positionArea.w);
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], 1.0f / 6.0f, 1e-6f);
  EXPECT_NEAR(areas[1], 1.0f / 6.0f, 1e-6f);
  EXPECT_NEAR(areas[2], 1.0f / 3.0f, 1e-6f);
  EXPECT_NEAR(areas[3], 1.0f / 3.0f, 1e-6f);
  EXPECT_NEAR(totalArea(surfels), 2.0f, 1e-5f);
}

// The resolve shows a surfel's irradiance at its vertex, which on a border lies a quarter of a cell
// from the centroid the solver gave it for: vertex_irradiance carries it there along the gradient of
// its neighbours on its own face. A field linear along a floor reaches every vertex (up to the fit's
// ridge); a wall meeting the floor at a hard edge, of another value, neither pulls on the floor nor
// moves. Where part of the floor lies inside another object (buried_surfels: under a block standing
// on it) and its surfels hold no light, the floor outside still shows its own field, and a buried
// surfel beside it shows its neighbours' light outside (the triangles reaching out from under the
// block share its vertex), not the darkness. Its neighbours outside stand in one column, so their
// fit has no slope across the contact: it shows the column's field near it.
TEST(Surfels, IrradianceIsCarriedToTheVertexAlongItsFace) {
  scenes::MeshData mesh;
  scenes::addQuad(mesh, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, {0, 0, 0}, 6, 6, {0, 1, 0});  // floor
  scenes::addQuad(mesh, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, 6, 6, {0, 0, 1});  // wall on its edge
  scenes::GltfBuilder b;
  b.node("corner", b.mesh("corner", {{mesh, b.material("grey", glm::vec3(0.5f))}}));
  Scene s = sceneFromModel(b.finish(), "corner");
  Geometry g = buildGeometry(s);
  const auto world = animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0)));
  const auto surfels = surfelsOnHost(g, world);
  auto field = [](glm::vec3 p) { return 1.0f + 2.0f * p.x + 3.0f * p.z; };
  const glm::vec3 channels(1.0f, 2.0f, 0.5f);
  auto onFloor = [&](size_t i) { return surfels[i].normal.y > 0.9f; };
  auto vertexOf = [&](size_t i) { return glm::vec3(world[g.surfelVertices[g.surfels[i].firstVertex]].position); };

  auto& ctx = test::gpu();
  const vk::Buffer sources = vk::makeBuffer(ctx, g.surfels), vertices = vk::makeBuffer(ctx, g.surfelVertices),
                   triangles = vk::makeBuffer(ctx, g.surfelTriangles), meshTriangles = vk::makeBuffer(ctx, g.triangles),
                   worldBuffer = vk::makeBuffer(ctx, world), surfelBuffer = vk::makeBuffer(ctx, surfels),
                   vertexSurfel = vk::makeBuffer(ctx, vertexSurfels(g));
  const vk::Buffer noDirectLight = vk::makeBuffer(ctx, std::vector<glm::vec4>(surfels.size()));
  const vk::Program pass = gi::shaderProgram(ctx, "vertex_irradiance");
  const uint32_t count = uint32_t(surfels.size());
  // The vertices' irradiance, given the surfels' and which lie inside another object.
  auto carried = [&](const std::vector<glm::vec4>& solved, const std::vector<uint32_t>& buried) {
    vk::Buffer out(ctx, surfels.size() * sizeof(glm::vec4), vk::Memory::Host);
    const vk::Buffer irradiance = vk::makeBuffer(ctx, solved), buriedBuffer = vk::makeBuffer(ctx, buried);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
      pass.dispatchItems(cmd, count,
                         {{"surfelSources", sources},
                          {"surfelVertices", vertices},
                          {"surfelTriangles", triangles},
                          {"triangles", meshTriangles},
                          {"world", worldBuffer},
                          {"surfels", surfelBuffer},
                          {"vertexSurfel", vertexSurfel},
                          {"surfelIrradiance", irradiance},
                          {"surfelDirect", noDirectLight},  // read only where the pixels take it (kDirectPixels)
                          {"shownSurfels", noDirectLight},  // read only for the reflections (kShownOnly)
                          {"surfelBuried", buriedBuffer},
                          {"vertexIrradiance", out}},
                         gpu::CountPush{.count = count});
    });
    return out.read<glm::vec4>(surfels.size());
  };

  std::vector<glm::vec4> solved(surfels.size());
  for (size_t i = 0; i < surfels.size(); ++i)
    solved[i] = glm::vec4(onFloor(i) ? field(glm::vec3(surfels[i].positionArea)) * channels : glm::vec3(5.0f), 0.0f);
  const auto shown = carried(solved, std::vector<uint32_t>(surfels.size(), 0u));
  int moved = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    const glm::vec3 own(solved[i]), want = onFloor(i) ? field(vertexOf(i)) * channels : glm::vec3(5.0f);
    moved += glm::length(want - own) > 0.01f;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(shown[i][c], want[c], 0.015f * std::abs(want[c] - own[c]) + 1e-5f)
          << "surfel " << i << " at " << vertexOf(i).x << ", " << vertexOf(i).y << ", " << vertexOf(i).z << " channel "
          << c;
  }
  EXPECT_GE(moved, 4 * 6) << "the floor's border surfels lie off their vertices";

  // A block over the floor's strip x < 0.4: its surfels there (vertices x = 0, 1/6, 1/3) are buried
  // and dark. The floor's surfels at x = 1/3 have neighbours outside; those at 0 and 1/6 have none
  // and keep their own light.
  std::vector<uint32_t> buried(surfels.size(), 0u);
  int continued = 0;
  for (size_t i = 0; i < surfels.size(); ++i)
    if (onFloor(i) && vertexOf(i).x < 0.4f) buried[i] = 1u, solved[i] = glm::vec4(0.0f);
  const auto contact = carried(solved, buried);
  for (size_t i = 0; i < surfels.size(); ++i) {
    if (!onFloor(i)) continue;
    const glm::vec3 v = vertexOf(i);
    if (buried[i] && v.x > 0.3f) {  // the field of the column outside, within a cell of its vertex
      const glm::vec3 lo = field({0.5f, 0.0f, std::max(v.z - 1.0f / 6.0f, 0.0f)}) * channels,
                      hi = field({0.5f, 0.0f, std::min(v.z + 1.0f / 6.0f, 1.0f)}) * channels;
      for (int c = 0; c < 3; ++c) {
        EXPECT_GE(contact[i][c], lo[c] - 1e-4f) << "surfel " << i << " at z " << v.z << " channel " << c;
        EXPECT_LE(contact[i][c], hi[c] + 1e-4f) << "surfel " << i << " at z " << v.z << " channel " << c;
      }
      ++continued;
      continue;
    }
    const glm::vec3 own(solved[i]), want = buried[i] ? own : field(v) * channels;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(contact[i][c], want[c], 0.015f * std::abs(want[c] - own[c]) + 1e-5f)
          << "surfel " << i << (buried[i] ? " (buried)" : "") << " at " << v.x << ", " << v.z << " channel " << c;
  }
  EXPECT_EQ(continued, 7) << "a column of the floor's vertices, at x = 1/3";
}

TEST(Surfels, DegenerateTrianglesAreCountedAndExcluded) {
  scenes::MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 0}, {3, 3, 0}, {4, 4, 0}, {5, 0, 0}};
  m.indices = {0, 1, 2,   // a real triangle
               3, 4, 5,   // collinear
               0, 0, 1,   // repeated index
               6, 6, 6};  // a point
  scenes::GltfBuilder b;
  b.node("mesh", b.mesh("mesh", {{m, b.material("grey", glm::vec3(0.5f))}}));
  Scene s = sceneFromModel(b.finish(), "degenerate");
  Geometry g = buildGeometry(s);
  EXPECT_EQ(g.degenerateTriangles, 3u);
  EXPECT_EQ(g.triangles.size(), 1u);
  EXPECT_EQ(g.surfels.size(), 3u) << "vertices on degenerate triangles only get no surfel";
  auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
  EXPECT_NEAR(totalArea(surfels), 0.5f, 1e-6f);
  for (const auto& sf : surfels) EXPECT_NEAR(sf.normal.z, 1.0f, 1e-6f) << "no normals given: from the face";
}

// Tessellation (docs/design.md §2.1): a 10 m floor with a 1 cm cube on it, at --tessellate 16. The
// floor is sampled no coarser than 1/16 of the scene anywhere, and near the cube about as finely as
// the cube's own faces: its surfels within 2 cm of the cube are at most a few cube faces in area,
// while those beyond 2 m keep the uniform size, so that the floor grows by a few hundred surfels,
// not by the 10⁶ a uniform 1 cm sampling would take.
TEST(Tessellation, NearASmallObjectAsFineAsIt) {
  scenes::MeshData floor, cube;
  scenes::addQuad(floor, {-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}, 1, 1, {0, 1, 0});
  const float h = 0.005f;  // the cube's half side, standing on the floor at (1.3, 0, 0.7)
  const glm::vec3 c(1.3f, h, 0.7f);
  scenes::addBox(cube, c, glm::vec3(h), 1);
  scenes::GltfBuilder b;
  b.node("world", b.mesh("world", {{floor, b.material("grey", glm::vec3(0.5f))},
                                   {cube, b.material("red", glm::vec3(0.8f, 0.2f, 0.2f))}}));
  Scene s = sceneFromModel(b.finish(), "pebble");
  Geometry g = buildGeometry(s, 16);
  auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
  const float uniform = glm::length(glm::vec3(10, 2 * h, 10)) / 16, face = 4 * h * h;
  size_t floorSurfels = 0;
  float nearest = 1e30f;
  for (const auto& sf : surfels) {
    const glm::vec3 p(sf.positionArea);
    if (p.y > 1e-6f) continue;  // the cube's
    ++floorSurfels;
    const float d =
        glm::length(glm::vec2(std::max(std::abs(p.x - c.x) - h, 0.0f), std::max(std::abs(p.z - c.z) - h, 0.0f)));
    nearest = std::min(nearest, d);
    if (d < 0.02f) {
      EXPECT_LE(sf.positionArea.w, 16 * face) << "a floor surfel " << d << " m from the cube";
    }
    if (d > 2.0f) {
      EXPECT_GE(sf.positionArea.w, 0.05f * uniform * uniform) << "a floor surfel " << d << " m away";
    }
    EXPECT_LE(sf.positionArea.w, 2 * uniform * uniform);
  }
  EXPECT_LT(nearest, 0.01f) << "the floor is sampled beside the cube";
  EXPECT_LT(floorSurfels, 2000u);
  std::printf("[ tessellation ] %zu floor surfels\n", floorSurfels);
  EXPECT_NEAR(totalArea(surfels), 100.0f + 6 * face, 1e-3f) << "the surfaces do not change";
}

// A grid of right triangles whose diagonals alone are too long (1/12 m cells, limit √2/16 m) halves
// its spacing: 25×25 surfels of equal area inside, not the grid's vertices plus one at each cell's
// centre (a lattice turned 45°, whose square surfels overlap and leave gaps in the bins).
TEST(Tessellation, AGridWhoseDiagonalsAreTooLongHalvesItsSpacing) {
  scenes::MeshData square;
  scenes::addQuad(square, {0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, 12, 12, {0, 1, 0});
  scenes::GltfBuilder b;
  b.node("square", b.mesh("square", {{square, b.material("grey", glm::vec3(0.5f))}}));
  Scene s = sceneFromModel(b.finish(), "grid");
  Geometry g = buildGeometry(s, 16);
  auto surfels = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0))));
  EXPECT_EQ(surfels.size(), 25u * 25u);
  const float cell = 1.0f / 24.0f;
  for (const auto& sf : surfels) {
    const glm::vec3 p(sf.positionArea);
    if (p.x > cell && p.x < 1 - cell && p.z > cell && p.z < 1 - cell) {
      EXPECT_NEAR(sf.positionArea.w, cell * cell, 1e-6f) << "an inner surfel at " << p.x << ", " << p.z;
    }
  }
  EXPECT_NEAR(totalArea(surfels), 1.0f, 1e-5f);
}

// The tessellation follows the scene's shape, not its size: the Cornell box under a node that scales
// it by 10⁻³, 10³, 2⁻¹⁰ or 2¹⁰ is sampled by as many surfels as at scale 1.
TEST(Tessellation, TheSameAtEveryScale) {
  auto surfelsAt = [](float factor) {
    tinygltf::Model model = test::scaled(scenes::cornellBox({.cells = 8, .animated = false}), factor);
    return buildGeometry(sceneFromModel(model, "scaled"), 16).surfels.size();
  };
  const size_t unit = surfelsAt(1.0f);
  EXPECT_GT(unit, 539u) << "the 8-cell box is tessellated";
  for (float factor : {1e-3f, 1e3f, 1.0f / 1024.0f, 1024.0f}) EXPECT_EQ(surfelsAt(factor), unit) << "scale " << factor;
}

// A cluster that stands for two faces of a box sits at a point off both, and sees what neither
// face sees (ar read the closed cube's light there, 7 % short). So in the furnace's tree every node
// with more than one normal under it holds each of those faces whole.
TEST(Hierarchy, ABoxsFacesAreSubtreesOfTheirOwn) {
  tinygltf::Model model = scenes::furnace({.cells = 8, .albedo = 0.5f, .emission = 1.0f});
  const Scene s = sceneFromModel(model, "furnace");
  const Geometry g = buildGeometry(s, 16);
  const gi::Hierarchy h = gi::restPoseHierarchy(s, g);
  const auto rest = surfelsOnHost(g, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0.0f))));
  auto faceOf = [&](int32_t surfel) {
    const glm::vec3 n(rest[size_t(surfel)].normal);
    const int axis = std::abs(n.x) > 0.9f ? 0 : (std::abs(n.y) > 0.9f ? 1 : 2);
    return 2 * axis + (n[axis] > 0.0f ? 1 : 0);
  };
  std::array<size_t, 6> faceSize{};
  for (size_t i = 0; i < rest.size(); ++i) ++faceSize[size_t(faceOf(int32_t(i)))];
  // Per node, its surfels per face; children are numbered after their parents.
  std::vector<std::array<size_t, 6>> under(h.nodes.size(), std::array<size_t, 6>{});
  size_t mixed = 0;
  for (size_t i = h.nodes.size(); i-- > 0;) {
    const gpu::TreeNode& t = h.nodes[i];
    if (t.childCount == 0) ++under[i][size_t(faceOf(t.surfel))];
    int faces = 0;
    for (size_t f = 0; f < 6; ++f) faces += under[i][f] > 0;
    if (faces > 1) {
      ++mixed;
      for (size_t f = 0; f < 6; ++f)
        if (under[i][f]) {
          EXPECT_EQ(under[i][f], faceSize[f]) << "node " << i << " holds part of face " << f;
        }
    }
    if (t.parent >= 0)
      for (size_t f = 0; f < 6; ++f) under[size_t(t.parent)][f] += under[i][f];
  }
  EXPECT_GE(mixed, 5u) << "six faces under one root take five nodes above them";
  EXPECT_EQ(under[h.roots[0]][0] + under[h.roots[0]][1] + under[h.roots[0]][2] + under[h.roots[0]][3] +
                under[h.roots[0]][4] + under[h.roots[0]][5],
            rest.size());
}

// What the solver may link once: instances whose world-space geometry no animation channel reaches.
TEST(MovingInstances, OnlyWhatTheAnimationReaches) {
  Scene cornell = sceneFromModel(scenes::cornellBox({.cells = 2}), "cornell");
  Geometry g = buildGeometry(cornell);
  auto moving = movingInstances(cornell, g, 0);
  ASSERT_EQ(moving.size(), g.instances.size());
  for (size_t i = 0; i < moving.size(); ++i)
    EXPECT_EQ(moving[i], cornell.nodes[g.instanceNode[i]].name == "short block")
        << cornell.nodes[g.instanceNode[i]].name;
  auto none = movingInstances(cornell, g, -1);
  EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);

  // Morph weights move geometry without any node transform.
  Scene cube =
      loadGltf((test::assimpGltfDir() / "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf").string());
  Geometry cg = buildGeometry(cube);
  auto morphing = movingInstances(cube, cg, 0);
  EXPECT_EQ(std::count(morphing.begin(), morphing.end(), true), long(cg.instances.size()));
}

// Which instances enclose a volume: a box, also where its faces are meshed apart (T-junctions along
// its edges) or tessellated, and two coincident squares back to back; not a box without its lid,
// nor a lone square.
TEST(ClosedInstances, HolesNotCracks) {
  scenes::GltfBuilder b;
  const int grey = b.material("grey", glm::vec3(0.5f));
  scenes::MeshData box, crackedBox, lidless, square, backToBack;
  scenes::addBox(box, {0, 0, 0}, glm::vec3(0.5f), 3);
  // The six faces of a unit box, corners in order around each, and the cells each is meshed at in the
  // cracked box: no vertex of an edge's shorter side is on the other. Faces are turned outward.
  const float h = 0.5f;
  const std::array<std::array<glm::vec3, 4>, 6> faces = {{{glm::vec3(-h, -h, -h), {h, -h, -h}, {h, -h, h}, {-h, -h, h}},
                                                          {glm::vec3(-h, h, -h), {h, h, -h}, {h, h, h}, {-h, h, h}},
                                                          {glm::vec3(-h, -h, -h), {h, -h, -h}, {h, h, -h}, {-h, h, -h}},
                                                          {glm::vec3(-h, -h, h), {h, -h, h}, {h, h, h}, {-h, h, h}},
                                                          {glm::vec3(-h, -h, -h), {-h, -h, h}, {-h, h, h}, {-h, h, -h}},
                                                          {glm::vec3(h, -h, -h), {h, -h, h}, {h, h, h}, {h, h, -h}}}};
  const std::array<int, 6> crackedCells = {1, 2, 4, 8, 3, 5};
  auto addFace = [](scenes::MeshData& m, const std::array<glm::vec3, 4>& f, glm::vec3 at, int cells) {
    scenes::addQuad(m, at + f[0], at + f[1], at + f[2], at + f[3], cells, cells, at + (f[0] + f[1] + f[2] + f[3]));
  };
  for (size_t i = 0; i < faces.size(); ++i) {
    addFace(crackedBox, faces[i], {3, 0, 0}, crackedCells[i]);
    if (i != 1) addFace(lidless, faces[i], {6, 0, 0}, 2);  // all but the top
  }
  scenes::addQuad(square, {9, 0, 0}, {10, 0, 0}, {10, 0, 1}, {9, 0, 1}, 2, 2, {9.5f, 1, 0.5f});
  scenes::addQuad(backToBack, {12, 0, 0}, {13, 0, 0}, {13, 0, 1}, {12, 0, 1}, 2, 2, {12.5f, 1, 0.5f});
  scenes::addQuad(backToBack, {12, 0, 0}, {13, 0, 0}, {13, 0, 1}, {12, 0, 1}, 2, 2, {12.5f, -1, 0.5f});
  const std::vector<std::pair<std::string, scenes::MeshData>> parts = {{"box", box},
                                                                       {"cracked box", crackedBox},
                                                                       {"lidless box", lidless},
                                                                       {"square", square},
                                                                       {"back to back", backToBack}};
  const std::vector<bool> expected = {true, true, false, false, true};
  for (const auto& [name, mesh] : parts) b.node(name, b.mesh(name, {{mesh, grey}}));
  const Scene s = sceneFromModel(b.finish(), "closed");
  for (uint32_t tessellation : {0u, 16u}) {
    const Geometry g = buildGeometry(s, tessellation);
    const std::vector<bool> closed = closedInstances(g);
    ASSERT_EQ(closed.size(), parts.size());
    for (size_t i = 0; i < parts.size(); ++i)
      EXPECT_EQ(closed[i], expected[i]) << parts[i].first << ", tessellation " << tessellation;
  }
}

// Seen from inside the closed furnace, every sample hits a wall, and each wall's triangles reach
// past the near plane, so that their screen bounds are the whole image. At 3840×2160 samples a
// workgroup walking such bounds alone would run out of lavapipe's loop budget (common.glsl) and
// leave the lower rows of the image empty; here every pixel must be covered by all of its samples.
TEST(Raster, BoundsAsLargeAsA4KFrameAreCoveredWhole) {
  const tinygltf::Model model = scenes::furnace({.cells = 1});
  Scene s = sceneFromModel(model, "furnace");
  Geometry g = buildGeometry(s);
  gi::FrameRenderer renderer(test::gpu(), g, {960, 540, 4});
  const Pose pose = evaluatePose(s, -1, 0.0f);
  const gi::FrameResult frame = renderer.render(g.frameInputs(s, pose), cameraView(s, pose, s.cameraNodes()[0]));
  size_t partly = 0;
  for (const glm::vec4& r : frame.channels.radiance) partly += r.a < 1.0f ? 1 : 0;
  EXPECT_EQ(partly, 0u) << "pixels not wholly covered, of " << frame.channels.radiance.size();
}

// Seen from its centre, the furnace's 26×26 cells a face meet along its creases, where rays cross
// shared edges steeply. Each sample must hit a triangle: a test with a tolerance on barycentrics
// left a few samples between two triangles (3 pixels at 320×240, 5 at 640×480) as holes.
TEST(Raster, SharedEdgesLeaveNoCracks) {
  const tinygltf::Model model = scenes::furnace({.cells = 26});
  Scene s = sceneFromModel(model, "furnace");
  Geometry g = buildGeometry(s);
  const Pose pose = evaluatePose(s, -1, 0.0f);
  for (glm::uvec2 size : {glm::uvec2(320, 240), glm::uvec2(640, 480)}) {
    gi::FrameRenderer renderer(test::gpu(), g, {size.x, size.y, 1});
    const gi::FrameResult frame = renderer.render(g.frameInputs(s, pose), cameraView(s, pose, s.cameraNodes()[0]));
    size_t holes = 0;
    for (const glm::vec4& r : frame.channels.radiance) holes += r.a < 1.0f ? 1 : 0;
    EXPECT_EQ(holes, 0u) << "samples that hit no triangle at " << size.x << "×" << size.y;
  }
}

namespace {

// The depth maps (raster.comp, kDepthOnly) of g's triangles, at rest, in `views` of `size` texels
// each: each texel's nearest depth as float bits, 0xFFFFFFFF where none; and how many views the
// raster drew.
std::pair<std::vector<uint32_t>, uint32_t> depthMapsOf(const Scene& s, const Geometry& g,
                                                       const std::vector<gpu::Camera>& views, glm::uvec2 size) {
  auto& ctx = test::gpu();
  const size_t texels = views.size() * size.x * size.y;
  gi::Raster raster(ctx, uint32_t(g.triangles.size()), nullptr, true, uint32_t(views.size()));
  const vk::Buffer world = vk::makeBuffer(ctx, animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0)))),
                   triangles = vk::makeBuffer(ctx, g.triangles), viewBuffer = vk::makeBuffer(ctx, views),
                   none = vk::makeBuffer(ctx, std::vector<glm::vec4>(1));
  vk::Buffer depths(ctx, texels * sizeof(uint32_t), vk::Memory::Host);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    raster.record(cmd,
                  vk::Bindings::pool({{"world", world},
                                      {"triangles", triangles},
                                      {"uvs", none},  // read only where a material cuts its surface
                                      {"colors", none},
                                      {"materials", none},
                                      {"textures", none},
                                      {"texels", none}}),
                  viewBuffer, uint32_t(views.size()), size, depths);
  });
  return {depths.read<uint32_t>(texels), raster.viewsDrawn()};
}

}  // namespace

// A light's depth maps are drawn several views to a raster workgroup (raster.comp), each large
// triangle in slices of its tiles that those views share. Seen from points inside the closed
// furnace, every texel of every cube face must hold the nearest wall's depth along the face's axis:
// none left empty by a view or a slice that the batches miss, or by lavapipe's loop budget, where
// the walls' triangles cover a face whole and reach behind its near plane.
TEST(Raster, DepthMapsDrawnManyViewsTogetherHoldTheNearestWall) {
  const tinygltf::Model model = scenes::furnace({.cells = 2});
  Scene s = sceneFromModel(model, "furnace");
  Geometry g = buildGeometry(s);
  const auto world = animateOnHost(g, g.frameInputs(s, evaluatePose(s, -1, 0)));
  Bounds box;
  for (const gpu::WorldVertex& v : world) box.add(glm::vec3(v.position));
  // Cube faces as light_views.comp writes them, around 7 points (42 views: not a whole number of
  // workgroups), from the centre to a hair from a corner.
  const std::array<glm::vec3, 7> at = {glm::vec3(0.5f),      {0.1f, 0.5f, 0.5f}, {0.5f, 0.02f, 0.9f},
                                       {0.9f, 0.9f, 0.1f},   {0.3f, 0.7f, 0.6f}, {0.01f, 0.99f, 0.5f},
                                       {0.25f, 0.25f, 0.75f}};
  std::vector<gpu::Camera> views;
  for (glm::vec3 f : at)
    for (uint32_t face = 0; face < 6; ++face) {
      const uint32_t axis = face / 2;
      glm::vec3 forward(0.0f), right(0.0f), up(0.0f);
      forward[axis] = (face & 1u) == 0 ? 1.0f : -1.0f;
      right[axis == 2 ? 0 : axis + 1] = 1.0f;
      up[axis == 0 ? 2 : axis - 1] = 1.0f;
      views.push_back({glm::vec4(box.min + f * (box.max - box.min), 1e-3f), glm::vec4(right, 0.0f), glm::vec4(up, 0.0f),
                       glm::vec4(forward, 0.0f)});
    }
  const glm::uvec2 size(384, 384);
  const size_t side = size_t(size.x) * size.y, texels = views.size() * side;

  const auto [drawn, viewsDrawn] = depthMapsOf(s, g, views, size);
  EXPECT_EQ(viewsDrawn, views.size());
  size_t empty = 0, wrong = 0;
  for (size_t v = 0; v < views.size(); ++v)
    for (uint32_t y = 0; y < size.y; ++y)
      for (uint32_t x = 0; x < size.x; ++x) {
        const uint32_t bits = drawn[v * side + size_t(y) * size.x + x];
        if (bits == 0xFFFFFFFFu) {
          ++empty;
          continue;
        }
        const glm::vec3 o(views[v].origin), d = gpu::cameraRay(views[v], glm::vec2(x, y) + 0.5f, size);
        float exit = 3.4e38f;  // where the ray leaves the box
        for (int i = 0; i < 3; ++i)
          if (d[i] != 0.0f) exit = std::min(exit, ((d[i] > 0.0f ? box.max[i] : box.min[i]) - o[i]) / d[i]);
        wrong += std::abs(std::bit_cast<float>(bits) - exit) > 1e-4f * (1.0f + exit) ? 1 : 0;
      }
  EXPECT_EQ(empty, 0u) << "of " << texels << " texels";
  EXPECT_EQ(wrong, 0u) << "of " << texels << " texels";
}

// The worst case of lavapipe's loop budget for depth maps: a workgroup's 64 triangles all large in
// every one of the views it draws. 32 squares stacked one behind another each fill a view, drawn into
// 8 copies of it: every texel must hold the nearest square's depth, which it would not if the
// workgroup walked more tiles than the budget allows (common.glsl: later rounds silently dropped).
TEST(Raster, AStackOfLargeTrianglesInManyViewsIsDrawnWhole) {
  scenes::MeshData stack;
  for (int k = 0; k < 32; ++k) {
    const float z = 1.0f + 0.1f * float(k), h = 40.0f;
    scenes::addQuad(stack, {-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}, 1, 1, {0, 0, -1});
  }
  scenes::GltfBuilder b;
  b.node("stack", b.mesh("stack", {{stack, b.material("grey", glm::vec3(0.5f))}}));
  Scene s = sceneFromModel(b.finish(), "stack");
  Geometry g = buildGeometry(s);
  ASSERT_EQ(g.triangles.size(), 64u);
  const std::vector<gpu::Camera> views(8, gpu::Camera{glm::vec4(0.0f, 0.0f, 0.0f, 1e-3f), glm::vec4(1, 0, 0, 0),
                                                      glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0)});
  const glm::uvec2 size(512, 512);
  const size_t texels = views.size() * size.x * size.y;
  const std::vector<uint32_t> drawn = depthMapsOf(s, g, views, size).first;
  const size_t nearest = size_t(std::count(drawn.begin(), drawn.end(), std::bit_cast<uint32_t>(1.0f)));
  EXPECT_EQ(nearest, texels);
}

namespace {

// An n×n grid over the unit square in the plane y = 0, facing +y, with the cells `skip` left out.
scenes::MeshData gridSquare(int n, const std::vector<glm::ivec2>& skip = {}) {
  scenes::MeshData m;
  for (int z = 0; z <= n; ++z)
    for (int x = 0; x <= n; ++x) m.positions.push_back(glm::vec3(x, 0, z) / float(n));
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      if (std::find(skip.begin(), skip.end(), glm::ivec2(x, z)) != skip.end()) continue;
      const uint32_t v = uint32_t(z * (n + 1) + x), w = uint32_t(n + 1);
      m.indices.insert(m.indices.end(), {v, v + w, v + 1, v + 1, v + w, v + w + 1});
    }
  return m;
}

Geometry geometryOf(const scenes::MeshData& mesh) {
  scenes::GltfBuilder b;
  b.node("surface", b.mesh("surface", {{mesh, b.material("grey", glm::vec3(0.5f))}}));
  return buildGeometry(sceneFromModel(b.finish(), "planar"));
}

// Summed area vector of triangles (½ Σ cross): equal for two meshes of one oriented surface.
glm::dvec3 areaVector(const Geometry& g, const std::vector<Triangle>& tris) {
  glm::dvec3 sum(0.0);
  for (const Triangle& t : tris) {
    const glm::dvec3 a = g.vertices[t.v0].position, b = g.vertices[t.v1].position, c = g.vertices[t.v2].position;
    sum += 0.5 * glm::cross(b - a, c - a);
  }
  return sum;
}

}  // namespace

// The depth maps draw a surface as its shape: a grid of 128 triangles is the square's two, facing
// as the grid did; a shape that is not convex, or has a hole, keeps its triangles.
TEST(PlanarFaces, AGridIsDrawnAsItsSquare) {
  const Geometry grid = geometryOf(gridSquare(8));
  const std::vector<Triangle> faces = planarFaces(grid, grid.triangles);
  EXPECT_EQ(faces.size(), 2u);
  const glm::dvec3 before = areaVector(grid, grid.triangles), after = areaVector(grid, faces);
  EXPECT_NEAR(glm::length(after - before), 0.0, 1e-6);
  EXPECT_NEAR(before.y, 1.0, 1e-6);  // wound toward +y: the cells' winding, kept

  const Geometry notch = geometryOf(gridSquare(4, {{3, 3}}));  // an L-like outline: not convex
  EXPECT_EQ(planarFaces(notch, notch.triangles).size(), notch.triangles.size());
  const Geometry ring = geometryOf(gridSquare(3, {{1, 1}}));  // a hole
  EXPECT_EQ(planarFaces(ring, ring.triangles).size(), ring.triangles.size());
}

// The Cornell box at 26 cells: each face of its blocks (the moving block's are drawn into every map,
// every frame) becomes two triangles. The red wall, whose measured corners lie out of one plane by a
// few millimetres, keeps its grid, and so does the ceiling's ring of pieces around the lamp (a hole).
TEST(PlanarFaces, TheCornellBlocksFacesAreTwoTrianglesEach) {
  const Scene s = sceneFromModel(scenes::cornellBox({.cells = 26}), "cornell");
  const Geometry g = buildGeometry(s);
  std::map<std::string, std::vector<Triangle>> byNode;  // and primitive: the room's walls by material
  for (const Triangle& t : g.triangles) {
    const uint32_t instance = g.vertices[t.v0].instance;
    byNode[s.nodes[size_t(g.instanceNode[instance])].name + " " + std::to_string(t.material & ~gpu::kTriangleFlags)]
        .push_back(t);
  }
  size_t blocks = 0;
  for (const auto& [name, tris] : byNode) {
    const std::vector<Triangle> faces = planarFaces(g, tris);
    const glm::dvec3 before = areaVector(g, tris), after = areaVector(g, faces);
    EXPECT_NEAR(glm::length(after - before), 0.0, 1e-6 * (1.0 + glm::length(before))) << name;
    if (name.find("block") != std::string::npos) {
      EXPECT_EQ(faces.size(), 10u) << name << ": five faces";
      ++blocks;
    }
    if (name.find("room") != std::string::npos) {
      EXPECT_LE(faces.size(), tris.size()) << name;
    }
  }
  EXPECT_EQ(blocks, 2u);
}

// The farthest every `stride`-th vertex of `g` lies from `drawn`, by brute force.
double farthestVertex(const Geometry& g, const std::vector<Triangle>& drawn, size_t stride) {
  double farthest = 0.0;
  for (size_t v = 0; v < g.vertices.size(); v += stride) {
    double nearest = 1e30;
    for (const Triangle& t : drawn)
      nearest = std::min(nearest, distanceToTriangle(g.vertices[v].position, g.vertices[t.v0].position,
                                                     g.vertices[t.v1].position, g.vertices[t.v2].position));
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

// A smooth sphere of 16,000 triangles, and one with hills and hollows, drawn for the maps at each
// level of the ladder: no more triangles the coarser the level (a hundredth at the coarsest), every vertex of the
// surface as modelled within the level's error of the simplified surface (the one-sided distance that moves a shadow's
// edge), and drawn exactly where the error asked for is under the finest level's.
TEST(MapMeshes, ASphereIsDrawnWithinEachLevelsError) {
  for (bool bumps : {false, true}) {
    const Geometry g = geometryOf(test::uvSphere(64, bumps));
    MapMeshes meshes(g, g.triangles);
    ASSERT_EQ(meshes.parts().size(), 1u);
    const MapMeshes::Part& sphere = meshes.parts()[0];
    EXPECT_NEAR(sphere.radius, bumps ? 1.15 : 1.0, 0.03);       // about the mean of its vertices
    EXPECT_EQ(meshes.draw({0.0f}).size(), g.triangles.size());  // curved: planarFaces merges nothing
    EXPECT_EQ(meshes.draw({1e-7f}).size(), g.triangles.size());
    size_t coarser = g.triangles.size();
    for (int k = 6; k >= MapMeshes::kCoarsestLevel; --k) {
      const float error = std::ldexp(sphere.radius, -k);
      ASSERT_EQ(MapMeshes::levelWithin(sphere, error), k);
      const std::vector<Triangle> drawn = meshes.draw({error});
      const double farthest = farthestVertex(g, drawn, 5);
      std::printf("[ maps   ] %s, level %d (error %.4f): %zu triangles, its vertices at most %.4f off\n",
                  bumps ? "hills" : "sphere", k, error, drawn.size(), farthest);
      EXPECT_LE(drawn.size(), coarser) << "level " << k;
      EXPECT_LE(farthest, error) << "level " << k;
      coarser = drawn.size();
    }
    EXPECT_LT(coarser, g.triangles.size() / 100);
  }
}

// One instance of a metre-wide tilted quad and a sphere 2 mm wide beside it (a panel and a bolt of
// one CAD part): the bolt is drawn simplified within the level's error. Measuring the level lists
// each triangle in the grid cells its bounds overlap; with cells as wide as the triangles' mean,
// the panel's two took 2.3·10⁷ listings (the test's peak 660 MB); widened to 64 listings a
// triangle, 145 MB.
TEST(MapMeshes, APanelWithABoltIsSimplifiedWithinItsError) {
  scenes::MeshData part = test::ball(64, 1e-3f, {0.5f, 0.3f, 0.5f});
  const uint32_t base = uint32_t(part.positions.size());
  part.positions.insert(part.positions.end(), {{0, 0, 0}, {1, 0.5f, 0}, {1, 1, 1}, {0, 0.5f, 1}});
  part.indices.insert(part.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  const Geometry g = geometryOf(part);
  MapMeshes meshes(g, g.triangles);
  ASSERT_EQ(meshes.parts().size(), 1u);
  const float error = std::ldexp(meshes.parts()[0].radius, -12);  // a fifth of the bolt's radius
  const std::vector<Triangle> drawn = meshes.draw({error});
  const double farthest = farthestVertex(g, drawn, 7);
  std::printf("[ maps   ] panel and bolt at %.2e: %zu of %zu triangles, its vertices at most %.2e off\n", error,
              drawn.size(), g.triangles.size(), farthest);
  EXPECT_LT(drawn.size(), g.triangles.size() / 4);
  EXPECT_LE(farthest, error);
}

// Found by the gltf_scene fuzzer: an edge whose middle lies past float's range (two corners near
// 3·10³⁸) made the tessellation's neighbour test convert an infinite cell index to int, undefined
// behaviour that the sanitized suite reports. Such a point asks nothing of its neighbours now.
TEST(Tessellation, AnEdgePastFloatsRangeHasNoCellToConvert) {
  scenes::MeshData near, far;
  near.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  near.indices = {0, 1, 2};
  far.positions = {{3e38f, 0, 0}, {3e38f, 1, 0}, {3e38f, 0, 1}};
  far.indices = {0, 1, 2};
  scenes::GltfBuilder b;
  const int grey = b.material("grey", glm::vec3(0.5f));
  b.node("near", b.mesh("near", {{near, grey}}));
  b.node("far", b.mesh("far", {{far, grey}}));
  const Geometry g = buildGeometry(sceneFromModel(b.finish(), "far"), 16);
  EXPECT_EQ(g.triangles.size(), 2u);  // neither is split: the far one's edges are short, the near one alone
}

// glTF: a node whose transform mirrors (a negative determinant) turns its triangles' front faces
// clockwise. A floor and a lamp modelled without normals, so that each face's side is its corners'
// order, render the same mirrored as not, in every method; before, mirrored, the floor faced down and
// the lamp up, and the floor came out black.
TEST(Geometry, AMirroredNodeKeepsItsFacesFront) {
  std::map<std::string, double> unmirrored;
  for (const float sx : {1.0f, -1.0f}) {
    scenes::GltfBuilder b;
    scenes::MeshData floor, lamp;
    scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 4, 4, {0, 1, 0});
    scenes::addQuad(lamp, {-0.2f, 1, -0.2f}, {0.2f, 1, -0.2f}, {0.2f, 1, 0.2f}, {-0.2f, 1, 0.2f}, 1, 1, {0, -1, 0});
    floor.normals.clear(), lamp.normals.clear();
    const int f = b.node("floor", b.mesh("floor", {{floor, b.material("grey", glm::vec3(0.5f))}}));
    const int l = b.node("lamp", b.mesh("lamp", {{lamp, b.material("lamp", glm::vec3(0.0f), glm::vec3(10.0f))}}));
    b.camera("camera", 0.9f, 0.01f, {0, 0.5f, 2.5f}, glm::quat(1, 0, 0, 0));
    tinygltf::Model m = b.finish();
    m.nodes[size_t(f)].scale = m.nodes[size_t(l)].scale = {sx, 1, 1};
    const std::string name = sx < 0.0f ? "mirrored" : "plain";
    const std::filesystem::path file = test::scratchDir(name) / (name + ".gltf");
    scenes::writeModel(m, file.string());
    for (const std::string method : {"pt", "iv", "ar"}) {
      std::vector<std::string> args = {file.string(), "--method", method, "--size", "64x48", "--env", "none"};
      if (method == "pt") args.insert(args.end(), {"--spp", "64"});
      const auto radiance = test::channelOf(test::renderExr(name + "-" + method, args), "G");
      double mean = 0.0;
      for (float v : radiance) mean += v / double(radiance.size());
      std::printf("[ mirror ] %s, %s: mean radiance %.5f\n", name.c_str(), method.c_str(), mean);
      if (sx > 0.0f)
        unmirrored[method] = mean;
      else
        EXPECT_NEAR(mean, unmirrored[method], 0.01 * unmirrored[method]) << method;
    }
  }
}

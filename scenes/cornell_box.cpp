// The Cornell box, from the measured data published by the Cornell Program of Computer Graphics
// (coordinates in millimetres there, metres here). Its camera looks along +z from z = -0.8 m with
// a 35 mm focal length on a 25 mm film: a vertical field of view of 2·atan(12.5/35) = 39.31°.
#include <cmath>

#include "engine/core/errors.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"

namespace ivgi::scenes {

namespace {

glm::vec3 mm(float x, float y, float z) { return glm::vec3(x, y, z) * 0.001f; }

struct Face {
  glm::vec3 p[4];
};

void addFace(MeshData& mesh, const Face& f, float cellsPerMetre, glm::vec3 facing) {
  int nu = cellsFor(std::max(glm::length(f.p[1] - f.p[0]), glm::length(f.p[2] - f.p[3])), cellsPerMetre);
  int nv = cellsFor(std::max(glm::length(f.p[3] - f.p[0]), glm::length(f.p[2] - f.p[1])), cellsPerMetre);
  addQuad(mesh, f.p[0], f.p[1], f.p[2], f.p[3], nu, nv, facing);
}

// A block: top face and four sides (the data has no bottom), relative to `centre`, facing out.
MeshData block(const Face& top, float height, glm::vec3 centre, float cellsPerMetre) {
  MeshData m;
  glm::vec3 inside = centre + glm::vec3(0, height * 0.5f, 0);
  auto rel = [&](glm::vec3 p) { return p - centre; };
  auto outward = [&](const Face& f) { return 2.0f * (0.25f * (f.p[0] + f.p[1] + f.p[2] + f.p[3])) - inside; };
  Face t{{rel(top.p[0]), rel(top.p[1]), rel(top.p[2]), rel(top.p[3])}};
  addFace(m, t, cellsPerMetre, rel(outward(top)));
  for (int i = 0; i < 4; ++i) {
    glm::vec3 a = top.p[i], b = top.p[(i + 1) % 4];
    Face side{{rel(glm::vec3(a.x, 0, a.z)), rel(glm::vec3(b.x, 0, b.z)), rel(b), rel(a)}};
    Face world{{glm::vec3(a.x, 0, a.z), glm::vec3(b.x, 0, b.z), b, a}};
    addFace(m, side, cellsPerMetre, rel(outward(world)));
  }
  return m;
}

// The room's walls, its ceiling in eight pieces around the light (so that light and ceiling never
// overlap: the lamp's piece goes to `lamp`), and the front wall where the camera looks in when `front`.
struct RoomFaces {
  MeshData whites, reds, greens, lamp, floor;
};
// The floor goes to `floor` when `separateFloor`, else with the other whites.
RoomFaces roomFaces(float cellsPerMetre, bool front, bool separateFloor = false) {
  const CornellLight& l = kCornellLight;
  const glm::vec3 inside = mm(278, 274, 280);
  RoomFaces r;
  addFace(separateFloor ? r.floor : r.whites,
          {{mm(552.8f, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2f), mm(549.6f, 0, 559.2f)}}, cellsPerMetre,
          inside);  // floor
  addFace(r.whites, {{mm(549.6f, 0, 559.2f), mm(0, 0, 559.2f), mm(0, 548.8f, 559.2f), mm(556, 548.8f, 559.2f)}},
          cellsPerMetre, inside);  // back
  addFace(r.reds, {{mm(552.8f, 0, 0), mm(549.6f, 0, 559.2f), mm(556, 548.8f, 559.2f), mm(556, 548.8f, 0)}},
          cellsPerMetre, inside);  // left
  addFace(r.greens, {{mm(0, 0, 559.2f), mm(0, 0, 0), mm(0, 548.8f, 0), mm(0, 548.8f, 559.2f)}}, cellsPerMetre,
          inside);  // right
  const float xs[] = {0, l.x0, l.x1, 556}, zs[] = {0, l.z0, l.z1, 559.2f};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      Face f{{mm(xs[i], l.height, zs[k]), mm(xs[i + 1], l.height, zs[k]), mm(xs[i + 1], l.height, zs[k + 1]),
              mm(xs[i], l.height, zs[k + 1])}};
      addFace(i == 1 && k == 1 ? r.lamp : r.whites, f, cellsPerMetre, inside);
    }
  if (front)  // the open side closed: its corners are the side walls' and the floor's and ceiling's
    addFace(r.whites, {{mm(0, 0, 0), mm(552.8f, 0, 0), mm(556, 548.8f, 0), mm(0, 548.8f, 0)}}, cellsPerMetre, inside);
  return r;
}

const glm::vec3 kShortCentre = mm(185.5f, 0, 169), kTallCentre = mm(368.5f, 0, 351.5f);
MeshData shortBlock(float cellsPerMetre) {
  const Face top{{mm(130, 165, 65), mm(82, 165, 225), mm(240, 165, 272), mm(290, 165, 114)}};
  return block(top, 0.165f, kShortCentre, cellsPerMetre);
}
MeshData tallBlock(float cellsPerMetre) {
  const Face top{{mm(423, 330, 247), mm(265, 330, 296), mm(314, 330, 456), mm(472, 330, 406)}};
  return block(top, 0.33f, kTallCentre, cellsPerMetre);
}

float cellsPerMetreFor(int cells) { return float(std::max(cells, 1)) / 0.5592f; }

}  // namespace

tinygltf::Model cornellBox(const CornellOptions& o) {
  checkCells(o.cells);
  const float cellsPerMetre = cellsPerMetreFor(o.cells);
  GltfBuilder b;
  int white = b.material("white", {0.725f, 0.71f, 0.68f});
  int red = b.material("red", {0.63f, 0.065f, 0.05f});
  int green = b.material("green", {0.14f, 0.45f, 0.091f});
  const CornellLight& l = kCornellLight;
  int light = b.material("light", {0.78f, 0.78f, 0.78f}, {l.radiance[0], l.radiance[1], l.radiance[2]});

  RoomFaces r = roomFaces(cellsPerMetre, false, o.glossy);
  std::vector<std::pair<MeshData, int>> roomParts = {
      {r.whites, white}, {r.reds, red}, {r.greens, green}, {r.lamp, light}};
  int shortMaterial = white, tallMaterial = white;
  if (o.glossy) {
    const glm::vec3 whiteBase(0.725f, 0.71f, 0.68f);
    roomParts.push_back({r.floor, b.glossyMaterial("polished floor", whiteBase, 0.0f, 0.2f)});
    shortMaterial = b.glossyMaterial("satin", whiteBase, 0.0f, 0.5f);
    tallMaterial = b.glossyMaterial("brushed aluminium", {0.91f, 0.92f, 0.92f}, 1.0f, 0.3f);
  }
  b.node("room", b.mesh("room", roomParts));

  int shortNode = -1;
  if (o.blocks) {
    shortNode =
        b.node("short block", b.mesh("short block", {{shortBlock(cellsPerMetre), shortMaterial}}), kShortCentre);
    b.node("tall block", b.mesh("tall block", {{tallBlock(cellsPerMetre), tallMaterial}}), kTallCentre);
  }

  // Camera: at (278, 273, -800) mm looking along +z, so turned 180° about y from glTF's -z.
  b.camera("Cornell camera", 2.0f * std::atan(12.5f / 35.0f), 0.01f, mm(278, 273, -800), glm::quat(0, 0, 1, 0));

  if (o.animated && shortNode >= 0) {
    // The short block slides toward the green wall and back while turning ±12°.
    std::vector<float> times = {0.0f, 0.5f, 1.0f, 1.5f, 2.0f};
    std::vector<float> slide, turn;
    const float dx[] = {0.0f, -0.03f, -0.06f, -0.03f, 0.0f}, angle[] = {0.0f, 12.0f, 0.0f, -12.0f, 0.0f};
    for (int k = 0; k < 5; ++k) {
      glm::vec3 t = kShortCentre + glm::vec3(dx[k], 0, 0);
      slide.insert(slide.end(), {t.x, t.y, t.z});
      glm::quat q = glm::angleAxis(glm::radians(angle[k]), glm::vec3(0, 1, 0));
      turn.insert(turn.end(), {q.x, q.y, q.z, q.w});
    }
    b.animate("block moves", shortNode, "translation", times, slide);
    b.animate("block moves", shortNode, "rotation", times, turn);
  }
  return b.finish();
}

tinygltf::Model cornellFurnace(const FurnaceOptions& o) {
  const float cellsPerMetre = cellsPerMetreFor(o.cells);
  GltfBuilder b;
  int wall = b.material("furnace wall", glm::vec3(o.albedo), glm::vec3(o.emission));
  RoomFaces r = roomFaces(cellsPerMetre, true);
  b.node("furnace", b.mesh("furnace", {{r.whites, wall}, {r.reds, wall}, {r.greens, wall}, {r.lamp, wall}}));
  b.node("short block", b.mesh("short block", {{shortBlock(cellsPerMetre), wall}}), kShortCentre);
  b.node("tall block", b.mesh("tall block", {{tallBlock(cellsPerMetre), wall}}), kTallCentre);
  // Just inside the closing wall, looking in (+z) with a field of view that takes in the room.
  b.camera("furnace camera", glm::radians(80.0f), 0.001f, mm(278, 274, 5), glm::quat(0, 0, 1, 0));
  return b.finish();
}

std::vector<std::string> builtinSceneNames() { return {"cornell", "furnace"}; }

void checkCells(int cells) {
  if (cells < 1 || cells > 512) throw SettingsError("--cells " + std::to_string(cells) + ": must be 1 to 512");
}

}  // namespace ivgi::scenes

#pragma once
// The scenes ivgi makes itself. Each is a glTF model, so that `ivgi scene` can write it out and the
// renderer loads it through the same path as any file.
#include <tiny_gltf.h>

#include <optional>
#include <string>
#include <vector>

namespace ivgi::scenes {

struct CornellOptions {
  int cells = 8;         // cells along the box's 0.56 m side; other faces in proportion
  bool animated = true;  // the short block slides and turns over 2 s
  bool blocks = true;    // false: the empty room
  // glTF's metallic-roughness on the floor and the blocks (a polished floor, a metal tall block, a
  // satin short block); the walls and the light stay Lambertian, as measured.
  bool glossy = false;
};
// The Cornell box from the measured Cornell data, in metres, with its camera (yfov 39.31°).
tinygltf::Model cornellBox(const CornellOptions& options = {});

// The Cornell box's light: a rectangle in the ceiling, in millimetres, facing down, and its
// radiance (red, green, blue). Tests integrate its direct light.
struct CornellLight {
  float x0 = 213, x1 = 343, z0 = 227, z1 = 332, height = 548.8f;
  float radiance[3] = {17, 12, 4};
};
inline constexpr CornellLight kCornellLight{};

struct FurnaceOptions {
  int cells = 4;          // per face side
  float albedo = 0.5f;    // uniform, grey
  float emission = 1.0f;  // uniform radiance of every face
  bool blocks = false;    // the Cornell box's room closed, with its two blocks (cells as the box's)
};
// A closed 1 m cube, inward facing, every face with the same albedo and emission: radiosity
// E/(1-ρ) everywhere. Camera at the centre. With blocks: the Cornell box's room, closed by a wall
// where its camera looks in, with its two blocks standing on the floor, every face the furnace's;
// the radiosity is still E/(1-ρ) everywhere, so that what a solver loses in corners, at contacts
// and in the blocks' shadows shows as a departure from one number. Camera inside the closing wall.
tinygltf::Model furnace(const FurnaceOptions& options = {});
tinygltf::Model cornellFurnace(const FurnaceOptions& options);  // furnace() with blocks

std::vector<std::string> builtinSceneNames();

// Throws SettingsError naming --cells unless 1 ≤ cells ≤ 512 (the scenes above check their own).
void checkCells(int cells);

}  // namespace ivgi::scenes

// The furnace: a closed enclosure whose faces all have the same albedo ρ and emission E, so that
// the radiosity is E/(1-ρ) everywhere — the energy-conservation check of docs/design.md §6.
#include <cmath>

#include "engine/core/errors.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"

namespace ivgi::scenes {

tinygltf::Model furnace(const FurnaceOptions& o) {
  checkCells(o.cells);
  if (!(o.albedo >= 0.0f && o.albedo <= 1.0f)) throw SettingsError("--albedo must lie in [0, 1]");
  if (!(o.emission >= 0.0f && std::isfinite(o.emission))) throw SettingsError("--emission must be finite and >= 0");
  if (o.blocks) return cornellFurnace(o);
  GltfBuilder b;
  int wall = b.material("furnace wall", glm::vec3(o.albedo), glm::vec3(o.emission));
  MeshData box;
  const glm::vec3 c(0.5f);
  int n = std::max(o.cells, 1);
  auto p = [](float x, float y, float z) { return glm::vec3(x, y, z); };
  addQuad(box, p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1), n, n, c);  // floor
  addQuad(box, p(0, 1, 0), p(1, 1, 0), p(1, 1, 1), p(0, 1, 1), n, n, c);  // ceiling
  addQuad(box, p(0, 0, 0), p(1, 0, 0), p(1, 1, 0), p(0, 1, 0), n, n, c);  // z = 0
  addQuad(box, p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1), n, n, c);  // z = 1
  addQuad(box, p(0, 0, 0), p(0, 1, 0), p(0, 1, 1), p(0, 0, 1), n, n, c);  // x = 0
  addQuad(box, p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1), n, n, c);  // x = 1
  b.node("furnace", b.mesh("furnace", {{box, wall}}));
  b.camera("furnace camera", glm::radians(90.0f), 0.01f, c, glm::quat(1, 0, 0, 0));
  return b.finish();
}

}  // namespace ivgi::scenes

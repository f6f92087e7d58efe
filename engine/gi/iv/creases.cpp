#include "engine/gi/iv/creases.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace ivgi::gi {

namespace {

// Normals more than 45° apart meet at a crease; a surfel lies in front of another's plane where
// the offset between them leans out of it by more than this share of its length.
constexpr float kCreaseCos = 0.7071f, kInFront = 0.1f;

uint64_t cellKey(glm::ivec3 c) {
  return (uint64_t(uint32_t(c.x) & 0x1fffffu) << 42) | (uint64_t(uint32_t(c.y) & 0x1fffffu) << 21) |
         uint64_t(uint32_t(c.z) & 0x1fffffu);
}

}  // namespace

std::vector<uint32_t> creaseSurfels(const std::vector<gpu::Surfel>& surfels, const std::vector<bool>& still) {
  // A grid of cells twice the mean reach: a surfel looks as many cells out as its own reach spans,
  // so that a few large surfels (a coarse floor) do not put every small one into one cell.
  double reaches = 0.0;
  size_t count = 0;
  for (size_t s = 0; s < surfels.size(); ++s)
    if (still[s] && surfels[s].shape.x > 0.0f) reaches += kCreaseReach * surfels[s].shape.x, ++count;
  if (count == 0) return {};
  const float cell = float(2.0 * reaches / double(count));
  auto cellOf = [&](glm::vec3 p) { return glm::ivec3(glm::floor(p / cell)); };
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  for (uint32_t s = 0; s < surfels.size(); ++s)
    if (still[s]) grid[cellKey(cellOf(glm::vec3(surfels[s].positionArea)))].push_back(s);
  // Whether still surfel q lies within `reach` of p (normal n) across a concave crease.
  auto meets = [&](glm::vec3 p, glm::vec3 n, float reach, uint32_t q) {
    const glm::vec3 d = glm::vec3(surfels[q].positionArea) - p, m(surfels[q].normal);
    const float length = glm::length(d);
    return length > 0.0f && length <= reach && glm::dot(n, m) <= kCreaseCos && glm::dot(d, n) > kInFront * length &&
           -glm::dot(d, m) > kInFront * length;
  };
  std::vector<uint32_t> creases;
  for (uint32_t s = 0; s < surfels.size(); ++s) {
    if (!still[s] || !(surfels[s].shape.x > 0.0f)) continue;
    const glm::vec3 p(surfels[s].positionArea), n(surfels[s].normal);
    const float reach = kCreaseReach * surfels[s].shape.x;
    const glm::ivec3 lo = cellOf(p - reach), hi = cellOf(p + reach);
    auto meetsAny = [&](const std::vector<uint32_t>& cellSurfels) {
      return std::any_of(cellSurfels.begin(), cellSurfels.end(),
                         [&](uint32_t q) { return q != s && meets(p, n, reach, q); });
    };
    bool crease = false;
    const glm::dvec3 span = glm::dvec3(hi - lo) + 1.0;
    if (span.x * span.y * span.z > double(grid.size())) {  // a surfel wider than most of the scene
      for (const auto& [key, cellSurfels] : grid)
        if ((crease = meetsAny(cellSurfels))) break;
    } else {
      for (int z = lo.z; z <= hi.z && !crease; ++z)
        for (int y = lo.y; y <= hi.y && !crease; ++y)
          for (int x = lo.x; x <= hi.x && !crease; ++x)
            if (const auto at = grid.find(cellKey({x, y, z})); at != grid.end()) crease = meetsAny(at->second);
    }
    if (crease) creases.push_back(s);
  }
  return creases;
}

}  // namespace ivgi::gi

#include "engine/scene/tessellation.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ivgi::scene {

namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) { return uint64_t(std::min(a, b)) << 32 | std::max(a, b); }

// Joints and weights of a vertex between a and b: the four heaviest of both, halved, renormalised.
void blendSkin(Primitive& p, uint32_t a, uint32_t b) {
  std::array<std::pair<float, uint32_t>, 8> all;
  for (int k = 0; k < 4; ++k)
    all[k] = {0.5f * p.weights[a][k], p.joints[a][k]}, all[4 + k] = {0.5f * p.weights[b][k], p.joints[b][k]};
  std::array<std::pair<float, uint32_t>, 8> merged{};
  size_t count = 0;
  for (const auto& [w, j] : all) {
    const uint32_t joint = j;  // clang 14 cannot capture a structured binding in a lambda
    auto it =
        std::find_if(merged.begin(), merged.begin() + long(count), [&](const auto& m) { return m.second == joint; });
    if (it != merged.begin() + long(count))
      it->first += w;
    else
      merged[count++] = {w, j};
  }
  std::stable_sort(merged.begin(), merged.begin() + long(count),
                   [](const auto& x, const auto& y) { return x.first > y.first; });
  glm::vec4 weights(0.0f);
  glm::uvec4 joints(0u);
  float sum = 0.0f;
  for (size_t k = 0; k < std::min<size_t>(count, 4); ++k)
    weights[int(k)] = merged[k].first, joints[int(k)] = merged[k].second, sum += merged[k].first;
  p.weights.push_back(sum > 0.0f ? weights / sum : weights);
  p.joints.push_back(joints);
}

// Appends the vertex halfway between a and b, its attributes interpolated; returns its index.
uint32_t addMidpoint(Primitive& p, uint32_t a, uint32_t b) {
  const uint32_t m = uint32_t(p.positions.size());
  p.positions.push_back(0.5f * (p.positions[a] + p.positions[b]));
  if (!p.normals.empty()) {
    const glm::vec3 n = p.normals[a] + p.normals[b];
    p.normals.push_back(glm::length(n) > 0.0f ? glm::normalize(n) : p.normals[a]);
  }
  if (!p.uvs.empty()) p.uvs.push_back(0.5f * (p.uvs[a] + p.uvs[b]));
  if (!p.uvs1.empty()) p.uvs1.push_back(0.5f * (p.uvs1[a] + p.uvs1[b]));
  if (!p.colors.empty()) p.colors.push_back(0.5f * (p.colors[a] + p.colors[b]));
  if (!p.joints.empty()) blendSkin(p, a, b);
  for (MorphTarget& t : p.targets) {
    if (!t.positions.empty()) t.positions.push_back(0.5f * (t.positions[a] + t.positions[b]));
    if (!t.normals.empty()) t.normals.push_back(0.5f * (t.normals[a] + t.normals[b]));
  }
  return m;
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

uint64_t cellKey(glm::ivec3 c) {
  return (uint64_t(uint32_t(c.x)) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(uint32_t(c.y)) * 0xC2B2AE3D27D4EB4Full) ^
         (uint64_t(uint32_t(c.z)) * 0x165667B19E3779F9ull);
}

}  // namespace

// Clamped into int's range: a point far outside the scene's bounds (found by fuzzing: a transform
// that overflows) has a cell, not undefined behaviour. Callers pass finite points only.
glm::ivec3 EdgeLimits::cellOf(glm::vec3 p) const {
  return glm::ivec3(glm::clamp(glm::floor(p / uniform_), glm::vec3(-1e9f), glm::vec3(1e9f)));
}

void EdgeLimits::addSurface(uint32_t owner, const std::vector<glm::vec3>& positions,
                            const std::vector<uint32_t>& indices) {
  if (!(uniform_ > 0.0f) || indices.empty()) return;
  Box box{positions[indices[0]], positions[indices[0]], 0.0f, owner};
  for (uint32_t i : indices) box.lo = glm::min(box.lo, positions[i]), box.hi = glm::max(box.hi, positions[i]);
  box.extent = glm::length(box.hi - box.lo);
  // A surface at least as large as the uniform limit asks nothing finer of its neighbours; nor does
  // one whose placed corners are not finite (an overflowing transform).
  if (!(box.extent < uniform_) || !finite(box.lo) || !finite(box.hi)) return;
  const glm::ivec3 lo = cellOf(box.lo), hi = cellOf(box.hi);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) cells_[cellKey({x, y, z})].push_back(uint32_t(boxes_.size()));
  boxes_.push_back(box);
}

void EdgeLimits::finish() {
  for (auto& [key, boxes] : cells_)
    std::stable_sort(boxes.begin(), boxes.end(),
                     [&](uint32_t a, uint32_t b) { return boxes_[a].extent < boxes_[b].extent; });
}

bool EdgeLimits::tooLong(glm::vec3 p, float length, uint32_t owner) const {
  if (!(uniform_ > 0.0f)) return false;
  if (length > uniform_) return true;
  if (!finite(p)) return false;  // placed past float's range: no neighbour is nearer
  // A small surface asks for edges no longer than the larger of their distance to its bounds and
  // its extent: only those nearer than `length` can, and they reach the cells next to p's (cells
  // are `uniform_` wide).
  const glm::ivec3 c = cellOf(p);
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x) {
        auto it = cells_.find(cellKey(c + glm::ivec3(x, y, z)));
        if (it == cells_.end()) continue;
        for (uint32_t i : it->second) {
          const Box& b = boxes_[i];
          if (!(b.extent < length)) break;  // the rest are larger still (finish())
          if (b.owner != owner && glm::length(glm::clamp(p, b.lo, b.hi) - p) < length) return true;
        }
      }
  return false;
}

Primitive tessellated(const Primitive& input, const glm::mat4& toWorld, const EdgeLimits& limits, uint32_t owner,
                      size_t maxVertices) {
  Primitive p = input;
  if (!(limits.uniform() > 0.0f)) return p;
  // Whether edge ab, stretched by `scale`, is longer than its limit.
  auto longEdge = [&](uint32_t a, uint32_t b, float scale = 1.0f) {
    const glm::vec3 pa = glm::vec3(toWorld * glm::vec4(p.positions[a], 1.0f)),
                    pb = glm::vec3(toWorld * glm::vec4(p.positions[b], 1.0f));
    return limits.tooLong(0.5f * (pa + pb), scale * glm::length(pa - pb), owner);
  };
  for (;;) {
    const size_t triangles = p.indices.size() / 3;
    std::unordered_map<uint64_t, uint32_t> split;  // marked edges, then their midpoints
    for (size_t t = 0; t < triangles; ++t)
      for (int e = 0; e < 3; ++e) {
        const uint32_t a = p.indices[3 * t + e], b = p.indices[3 * t + (e + 1) % 3];
        if (a != b && longEdge(a, b)) split.emplace(edgeKey(a, b), 0u);
      }
    if (split.empty()) break;
    // A triangle with one long edge whose others are longer than half their limit splits into four,
    // not two: a grid of right triangles whose diagonals alone are too long then halves its spacing,
    // where bisecting the diagonals would leave a lattice turned 45° from the surfels' tangent frame,
    // whose rectangles overlap and leave gaps (light lost to the bins' cap). Only long edges decide
    // this, so that it does not spread to the neighbours.
    std::vector<size_t> quartered;
    for (size_t t = 0; t < triangles; ++t) {
      const uint32_t* v = &p.indices[3 * t];
      bool marked[3];
      for (int e = 0; e < 3; ++e) marked[e] = split.count(edgeKey(v[e], v[(e + 1) % 3])) != 0;
      if (int(marked[0]) + int(marked[1]) + int(marked[2]) != 1) continue;
      int halfLong = 0;
      for (int e = 0; e < 3; ++e) halfLong += !marked[e] && longEdge(v[e], v[(e + 1) % 3], 2.0f) ? 1 : 0;
      if (halfLong == 2) quartered.push_back(t);
    }
    for (size_t t : quartered)
      for (int e = 0; e < 3; ++e) split.emplace(edgeKey(p.indices[3 * t + e], p.indices[3 * t + (e + 1) % 3]), 0u);
    // A triangle with two marked edges has its third marked too (it splits into four, not three).
    for (bool changed = true; changed;) {
      changed = false;
      for (size_t t = 0; t < triangles; ++t) {
        const uint32_t* v = &p.indices[3 * t];
        int marked = 0;
        for (int e = 0; e < 3; ++e) marked += split.count(edgeKey(v[e], v[(e + 1) % 3])) ? 1 : 0;
        if (marked == 2)
          for (int e = 0; e < 3; ++e) changed |= split.emplace(edgeKey(v[e], v[(e + 1) % 3]), 0u).second;
      }
    }
    if (p.positions.size() + split.size() > maxVertices) break;
    // Midpoints in the triangles' order, so that the result does not depend on the map's.
    std::vector<uint32_t> out;
    out.reserve(p.indices.size() * 2);
    auto midpoint = [&](uint32_t a, uint32_t b) -> uint32_t {
      auto it = split.find(edgeKey(a, b));
      if (it == split.end()) return ~0u;
      if (it->second == 0u) it->second = addMidpoint(p, a, b) + 1;
      return it->second - 1;
    };
    for (size_t t = 0; t < triangles; ++t) {
      const uint32_t v0 = p.indices[3 * t], v1 = p.indices[3 * t + 1], v2 = p.indices[3 * t + 2];
      const uint32_t m01 = midpoint(v0, v1), m12 = midpoint(v1, v2), m20 = midpoint(v2, v0);
      const int marked = (m01 != ~0u) + (m12 != ~0u) + (m20 != ~0u);
      if (marked == 0) {
        out.insert(out.end(), {v0, v1, v2});
      } else if (marked == 3) {
        out.insert(out.end(), {v0, m01, m20, m01, v1, m12, m20, m12, v2, m01, m12, m20});
      } else if (m01 != ~0u) {
        out.insert(out.end(), {v0, m01, v2, m01, v1, v2});
      } else if (m12 != ~0u) {
        out.insert(out.end(), {v1, m12, v0, m12, v2, v0});
      } else {
        out.insert(out.end(), {v2, m20, v1, m20, v0, v1});
      }
    }
    p.indices = std::move(out);
  }
  return p;
}

}  // namespace ivgi::scene

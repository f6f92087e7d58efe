#include "engine/scene/planar_faces.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <unordered_map>

namespace ivgi::scene {

namespace {

// Vertices that share a position (seams in UV or normal) are one corner of the surface.
struct Corners {
  std::unordered_map<uint64_t, std::vector<std::pair<glm::vec3, uint32_t>>> byHash;
  uint32_t count = 0;
  uint32_t of(glm::vec3 p) {
    auto& list = byHash[hashPoint(p)];
    for (const auto& [q, id] : list)
      if (q == p) return id;
    list.emplace_back(p, count);
    return count++;
  }
};

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

// One instance's triangles, merged where they make convex planar polygons.
void mergeInstance(const Geometry& g, const std::vector<Triangle>& tris, std::vector<Triangle>& out) {
  const size_t n = tris.size();
  Corners corners;
  std::vector<std::array<uint32_t, 3>> cornerOf(n);
  std::vector<glm::vec3> normal(n);
  std::vector<float> offset(n);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (size_t t = 0; t < n; ++t) {
    const glm::vec3 p[3] = {g.vertices[tris[t].v0].position, g.vertices[tris[t].v1].position,
                            g.vertices[tris[t].v2].position};
    for (int k = 0; k < 3; ++k)
      cornerOf[t][size_t(k)] = corners.of(p[k]), lo = glm::min(lo, p[k]), hi = glm::max(hi, p[k]);
    const glm::vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
    normal[t] = glm::length(c) > 0.0f ? glm::normalize(c) : glm::vec3(0.0f);
    offset[t] = glm::dot(normal[t], p[0]);
  }
  const float tolerance = 1e-5f * std::max(glm::length(hi - lo), 1e-30f);
  auto coplanar = [&](size_t a, size_t b) {
    return glm::dot(normal[a], normal[b]) >= 1.0f - 1e-5f && std::abs(offset[a] - offset[b]) <= tolerance;
  };
  // Triangles joined across an edge that exactly two of them share, in one plane and facing alike.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> byEdge;
  for (size_t t = 0; t < n; ++t)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = cornerOf[t][size_t(e)], b = cornerOf[t][size_t((e + 1) % 3)];
      byEdge[{std::min(a, b), std::max(a, b)}].push_back(uint32_t(t));
    }
  UnionFind groups(n);
  for (const auto& [edge, list] : byEdge)
    if (list.size() == 2 && coplanar(list[0], list[1])) groups.join(list[0], list[1]);
  std::map<uint32_t, std::vector<uint32_t>> members;
  for (size_t t = 0; t < n; ++t) members[groups.find(uint32_t(t))].push_back(uint32_t(t));

  for (const auto& member : members) {
    const std::vector<uint32_t>& group = member.second;  // a name of its own: clang 14 captures no binding
    auto keep = [&] {
      for (uint32_t t : group) out.push_back(tris[t]);
    };
    if (group.size() < 3) {
      keep();
      continue;
    }
    // The boundary: directed edges whose reverse no triangle of the group has; one loop, each
    // corner left by one edge.
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    std::unordered_map<uint32_t, uint32_t> vertexAt;  // corner -> a vertex there
    for (uint32_t t : group) {
      const uint32_t v[3] = {tris[t].v0, tris[t].v1, tris[t].v2};
      for (int e = 0; e < 3; ++e) {
        directed[{cornerOf[t][size_t(e)], cornerOf[t][size_t((e + 1) % 3)]}] += 1;
        vertexAt.emplace(cornerOf[t][size_t(e)], v[e]);
      }
    }
    std::unordered_map<uint32_t, uint32_t> next;
    bool simple = true;
    size_t boundaryEdges = 0;
    for (const auto& [edge, count] : directed) {
      if (directed.count({edge.second, edge.first})) continue;
      simple = simple && count == 1 && next.emplace(edge.first, edge.second).second;
      ++boundaryEdges;
    }
    std::vector<uint32_t> loop;
    if (simple && !next.empty()) {
      const uint32_t start = next.begin()->first;
      for (uint32_t c = start; loop.size() <= boundaryEdges;) {
        loop.push_back(c);
        auto it = next.find(c);
        if (it == next.end()) break;
        c = it->second;
        if (c == start) break;
      }
    }
    if (!simple || loop.size() != boundaryEdges) {  // holes, several pieces, or a broken loop
      keep();
      continue;
    }
    // Corners where the boundary turns: those on a straight run add nothing.
    const glm::vec3 n = normal[group[0]];
    auto at = [&](uint32_t corner) { return g.vertices[vertexAt[corner]].position; };
    std::vector<uint32_t> turns;
    bool convex = true;
    for (size_t i = 0; i < loop.size(); ++i) {
      const glm::vec3 a = at(loop[(i + loop.size() - 1) % loop.size()]), b = at(loop[i]),
                      c = at(loop[(i + 1) % loop.size()]);
      const glm::vec3 e0 = b - a, e1 = c - b;
      const float turn = glm::dot(glm::cross(e0, e1), n), scale = glm::length(e0) * glm::length(e1);
      if (std::abs(turn) <= 1e-5f * scale) continue;
      convex = convex && turn > 0.0f;
      turns.push_back(loop[i]);
    }
    if (!convex || turns.size() < 3 || turns.size() - 2 >= group.size()) {
      keep();
      continue;
    }
    for (size_t i = 1; i + 1 < turns.size(); ++i)
      out.push_back({vertexAt[turns[0]], vertexAt[turns[i]], vertexAt[turns[i + 1]], tris[group[0]].material});
  }
}

}  // namespace

std::vector<Triangle> planarFaces(const Geometry& g, const std::vector<Triangle>& triangles) {
  std::map<uint32_t, std::vector<Triangle>> byInstance;
  for (const Triangle& t : triangles) byInstance[g.vertices[t.v0].instance].push_back(t);
  std::vector<Triangle> out;
  out.reserve(triangles.size());
  for (const auto& [instance, tris] : byInstance) {
    const Instance& inst = g.instances[instance];
    if (inst.skinned || inst.morphTargets > 0)
      out.insert(out.end(), tris.begin(), tris.end());
    else
      mergeInstance(g, tris, out);
  }
  return out;
}

}  // namespace ivgi::scene

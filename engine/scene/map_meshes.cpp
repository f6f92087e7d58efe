#include "engine/scene/map_meshes.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "engine/core/parallel.h"
#include "engine/scene/planar_faces.h"

namespace ivgi::scene {

double distanceToTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(ap);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = 1.0 / (va + vb + vc);
  return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

namespace {

// The maps' raster takes triangles 64 to a workgroup and judges each workgroup's bounds against a
// light's views: triangles listed in meshoptimizer's spatial order (of their centres along a
// Morton curve) keep each workgroup's bounds to a patch of the surface, which few views reach.
void sortSpatially(std::vector<uint32_t>& corners, const float* positions, size_t count, size_t stride) {
  std::vector<uint32_t> sorted(corners.size());
  meshopt_spatialSortTriangles(sorted.data(), corners.data(), corners.size(), positions, count, stride);
  corners = std::move(sorted);
}

// A part of `triangles`, all of one instance.
MapMeshes::Part partOf(const Geometry& g, uint32_t instance, const std::vector<Triangle>& triangles) {
  MapMeshes::Part part;
  part.instance = instance;
  part.rigid = !g.instances[instance].skinned && g.instances[instance].morphTargets == 0;
  part.material = triangles.front().material;
  part.cutout = gpu::alphaMatters(g.materials[part.material & ~gpu::kTriangleFlags].alphaCutoff);
  std::vector<uint32_t> exact;
  for (const Triangle& t : part.cutout ? triangles : planarFaces(g, triangles))
    exact.insert(exact.end(), {t.v0, t.v1, t.v2});
  sortSpatially(exact, &g.vertices[0].position.x, g.vertices.size(), sizeof(Vertex));
  for (size_t i = 0; i < exact.size(); i += 3)
    part.exact.push_back({exact[i], exact[i + 1], exact[i + 2], part.material});
  // Vertices of one position are one corner, so the simplification may collapse across the seams
  // of normals and texture coordinates, which the maps do not draw.
  std::map<std::tuple<float, float, float>, uint32_t> welded;
  glm::dvec3 sum(0.0);
  for (const Triangle& t : triangles)
    for (uint32_t v : {t.v0, t.v1, t.v2}) {
      const glm::vec3 p = g.vertices[v].position;
      const auto [at, added] = welded.try_emplace({p.x, p.y, p.z}, uint32_t(part.positions.size()));
      if (added) part.positions.push_back(p), part.vertexAt.push_back(v), sum += glm::dvec3(p);
      part.corners.push_back(at->second);
    }
  part.centre = glm::vec3(sum / double(part.positions.size()));
  for (const glm::vec3& p : part.positions) part.radius = std::max(part.radius, glm::length(p - part.centre));
  return part;
}

// A level asks for a smaller error by this factor while its result is too far, at most
// kMostAsks times, then draws its part exactly.
constexpr float kSmallerAsk = 0.70710678f;
constexpr int kMostAsks = 8;

// The farthest any of `positions` lies from the triangles `corners` makes of them, where that is
// within `reach`; past it, some distance past it. The triangles are found through a grid of cells
// as wide as a triangle's bounds on average (no narrower than `reach`, and wider where the
// listings would pass 64 a triangle), each listing those whose bounds, widened by `reach`, overlap
// it: a vertex needs only its own cell's.
double farthestVertex(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& corners, float reach) {
  const size_t triangles = corners.size() / 3;
  std::vector<Bounds> boxes(triangles);
  Bounds bounds;
  double widths = 0.0;
  for (size_t t = 0; t < triangles; ++t) {
    for (size_t k = 0; k < 3; ++k) boxes[t].add(positions[corners[3 * t + k]]);
    widths += glm::length(boxes[t].max - boxes[t].min);
  }
  for (const glm::vec3& p : positions) bounds.add(p);
  const glm::dvec3 lo = glm::dvec3(bounds.min) - double(reach);
  double cell = std::max({double(reach), widths / double(std::max<size_t>(triangles, 1)),
                          double(glm::length(bounds.max - bounds.min)) / 1024.0});
  // Wider cells where a few large triangles among many small ones would be listed in too many.
  auto listings = [&](double side) {
    double count = 0.0;
    for (const Bounds& box : boxes) {
      const glm::dvec3 from = glm::floor((glm::dvec3(box.min) - double(reach) - lo) / side),
                       to = glm::floor((glm::dvec3(box.max) + double(reach) - lo) / side);
      count += (to.x - from.x + 1.0) * (to.y - from.y + 1.0) * (to.z - from.z + 1.0);
    }
    return count;
  };
  while (listings(cell) > 64.0 * double(triangles) + double(1 << 20)) cell *= 2.0;
  const glm::ivec3 cells = glm::ivec3(glm::dvec3(bounds.max - bounds.min) / cell) + 3;
  auto cellOf = [&](glm::dvec3 p) {
    return glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), cells - 1);
  };
  auto key = [&](glm::ivec3 c) {
    return (uint64_t(c.z) * uint64_t(cells.y) + uint64_t(c.y)) * uint64_t(cells.x) + uint64_t(c.x);
  };
  std::vector<std::pair<uint64_t, uint32_t>> listed;  // (cell, triangle), sorted by cell
  for (uint32_t t = 0; t < triangles; ++t) {
    const glm::ivec3 from = cellOf(glm::dvec3(boxes[t].min) - double(reach)),
                     to = cellOf(glm::dvec3(boxes[t].max) + double(reach));
    for (int z = from.z; z <= to.z; ++z)
      for (int y = from.y; y <= to.y; ++y)
        for (int x = from.x; x <= to.x; ++x) listed.emplace_back(key({x, y, z}), t);
  }
  std::sort(listed.begin(), listed.end());
  double farthest = 0.0;
  for (const glm::vec3& p : positions) {
    double nearest = 2.0 * reach + 1e-30;  // past the reach: no triangle listed is nearer
    const uint64_t at = key(cellOf(glm::dvec3(p)));
    for (auto it = std::lower_bound(listed.begin(), listed.end(), std::make_pair(at, 0u));
         it != listed.end() && it->first == at; ++it) {
      const uint32_t* c = &corners[3 * size_t(it->second)];
      nearest = std::min(nearest, distanceToTriangle(p, positions[c[0]], positions[c[1]], positions[c[2]]));
    }
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

}  // namespace

MapMeshes::MapMeshes(const Geometry& g, const std::vector<Triangle>& triangles) : triangleCount_(triangles.size()) {
  std::map<uint32_t, std::vector<Triangle>> byInstance;
  for (const Triangle& t : triangles) byInstance[g.vertices[t.v0].instance].push_back(t);
  std::vector<const std::pair<const uint32_t, std::vector<Triangle>>*> instances;
  for (const auto& entry : byInstance) instances.push_back(&entry);
  parts_.resize(instances.size());
  parallelFor(instances.size(), [&](size_t p) { parts_[p] = partOf(g, instances[p]->first, instances[p]->second); });
  for (const Part& part : parts_) {
    exactCount_ += part.exact.size();
    cutouts_ = cutouts_ || part.cutout;
  }
}

int MapMeshes::levelWithin(const Part& part, float error) {
  if (!part.rigid || part.cutout || !(error > 0.0f) || !(part.radius > 0.0f)) return kFinestLevel + 1;
  // The least k with radius × 2^-k ≤ error.
  const int k = int(std::ceil(std::log2(double(part.radius) / double(error))));
  return std::clamp(k, kCoarsestLevel, kFinestLevel + 1);
}

const std::vector<Triangle>& MapMeshes::level(Part& part, int k) {
  auto [at, added] = part.levels.try_emplace(k);
  if (!added) return at->second;
  const float error = std::ldexp(part.radius, -k);
  // meshoptimizer judges a collapse by the distances to the planes around the collapsed vertex, and
  // a curved surface's sag between the kept vertices can go past that: each level's result is
  // measured, and asked for again with a smaller error while a vertex lies farther than the level's
  // error from it. meshoptimizer takes the error relative to its own measure of the mesh's size.
  const float scale = meshopt_simplifyScale(&part.positions[0].x, part.positions.size(), sizeof(glm::vec3));
  std::vector<uint32_t> kept(part.corners.size());
  float asked = error;
  for (int tries = 0;; ++tries, asked *= kSmallerAsk) {
    kept.resize(part.corners.size());
    kept.resize(meshopt_simplify(kept.data(), part.corners.data(), part.corners.size(), &part.positions[0].x,
                                 part.positions.size(), sizeof(glm::vec3), 0, scale > 0.0f ? asked / scale : 0.0f));
    const double far = kept.size() == part.corners.size() ? 0.0 : farthestVertex(part.positions, kept, error);
    if (kept.size() == part.corners.size() || far <= error) break;
    if (tries == kMostAsks) {
      kept = part.corners;
      break;
    }
  }
  sortSpatially(kept, &part.positions[0].x, part.positions.size(), sizeof(glm::vec3));
  std::vector<Triangle>& simplified = at->second;
  for (size_t i = 0; i + 2 < kept.size(); i += 3)
    simplified.push_back(
        {part.vertexAt[kept[i]], part.vertexAt[kept[i + 1]], part.vertexAt[kept[i + 2]], part.material});
  return simplified;
}

std::vector<Triangle> MapMeshes::draw(const std::vector<float>& errors) {
  auto levelOf = [&](size_t p) { return levelWithin(parts_[p], p < errors.size() ? errors[p] : 0.0f); };
  // The levels asked for the first time are made first, spread over the cores: each is a part's own.
  std::vector<size_t> unmade;
  for (size_t p = 0; p < parts_.size(); ++p)
    if (const int k = levelOf(p); k <= kFinestLevel && !parts_[p].levels.contains(k)) unmade.push_back(p);
  parallelFor(unmade.size(), [&](size_t i) { level(parts_[unmade[i]], levelOf(unmade[i])); });
  std::vector<Triangle> out;
  out.reserve(exactCount_);
  for (size_t p = 0; p < parts_.size(); ++p) {
    Part& part = parts_[p];
    const int k = levelOf(p);
    const std::vector<Triangle>* drawn = &part.exact;
    if (k <= kFinestLevel) {
      const std::vector<Triangle>& simplified = level(part, k);
      if (simplified.size() < part.exact.size()) drawn = &simplified;
    }
    out.insert(out.end(), drawn->begin(), drawn->end());
  }
  return out;
}

}  // namespace ivgi::scene

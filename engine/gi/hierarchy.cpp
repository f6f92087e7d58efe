#include "engine/gi/hierarchy.h"

#include "engine/gi/bins.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "engine/scene/animation.h"

namespace ivgi::gi {

namespace {

// The least difference of a normal's component between two groups of surfels that a node splits
// apart before it splits in space (about 17° between normals at the least): faces meeting at an edge.
constexpr float kFacetGap = 0.3f;

// A tree under construction: nodes with their depth, children by index.
struct BuildNode {
  std::vector<uint32_t> children;
  int32_t surfel = -1;
  uint32_t depth = 0;
};

// Per surfel of `items` and axis, the rank of its coordinate among theirs, coordinates within a
// part in 10⁶ of their extent counting as equal: grid points that lie on one line at one scale may
// be a rounding apart at another, and the trees must not depend on the scene's scale.
void rankCoordinates(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& items,
                     std::vector<glm::uvec3>& ranks) {
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<uint32_t> order = items;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      return positions[a][axis] < positions[b][axis] || (positions[a][axis] == positions[b][axis] && a < b);
    });
    const float extent = positions[order.back()][axis] - positions[order.front()][axis];
    uint32_t rank = 0;
    for (size_t k = 0; k < order.size(); ++k) {
      if (k > 0 && positions[order[k]][axis] - positions[order[k - 1]][axis] > 1e-6f * extent) ++rank;
      ranks[order[k]][axis] = rank;
    }
  }
}

// How far the points reach across, whatever their orientation: from the point farthest from their
// centroid to the point farthest from that one (the diagonal of a box, the diameter of a ball; never
// below half the set's diameter). The diagonal of their bounds along the world's axes would grow by
// up to √3 as the same scene turns.
float extentOf(const std::vector<glm::vec3>& points) {
  if (points.empty()) return 0.0f;
  glm::dvec3 centroid(0.0);
  for (const glm::vec3& p : points) centroid += glm::dvec3(p);
  centroid /= double(points.size());
  const auto farthestFrom = [&](glm::dvec3 from) {
    glm::dvec3 far = from;
    double most = -1.0;
    for (const glm::vec3& p : points)
      if (const double d = glm::distance(glm::dvec3(p), from); d > most) most = d, far = glm::dvec3(p);
    return far;
  };
  const glm::dvec3 a = farthestFrom(centroid);
  return float(glm::distance(a, farthestFrom(a)));
}

class TreeBuilder {
 public:
  TreeBuilder(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
              const std::vector<glm::uvec3>& ranks, const std::vector<glm::vec2>& uvs, bool uv)
      : pos_(positions), normal_(normals), rank_(ranks), uv_(uvs), useUv_(uv) {}

  std::vector<BuildNode> build(std::vector<uint32_t> surfels) {
    nodes_.clear();
    nodes_.push_back({});
    split(0, surfels, glm::vec2(0), glm::vec2(1), 0);
    return nodes_;
  }

 private:
  uint32_t add(uint32_t parent, uint32_t depth) {
    nodes_.push_back({});
    nodes_.back().depth = depth;
    nodes_[parent].children.push_back(uint32_t(nodes_.size() - 1));
    return uint32_t(nodes_.size() - 1);
  }

  void split(uint32_t node, std::vector<uint32_t>& items, glm::vec2 lo, glm::vec2 hi, int uvDepth) {
    if (items.size() == 1) {
      nodes_[node].surfel = int32_t(items[0]);
      return;
    }
    std::vector<std::vector<uint32_t>> parts;
    std::vector<std::pair<glm::vec2, glm::vec2>> boxes;
    // Faces that meet at an edge first: where the normals fall into groups apart by more than
    // kFacetGap along an axis, the node splits at the widest gap, so that a box's faces make flat
    // subtrees, while a smoothly curved surface (no gap) is split in space.
    float widest = 0.0f, cut = 0.0f;
    int cutAxis = -1;
    std::vector<float> values(items.size());
    for (int axis = 0; axis < 3; ++axis) {
      for (size_t k = 0; k < items.size(); ++k) values[k] = normal_[items[k]][axis];
      std::sort(values.begin(), values.end());
      for (size_t k = 1; k < values.size(); ++k)
        if (values[k] - values[k - 1] > widest)
          widest = values[k] - values[k - 1], cut = 0.5f * (values[k] + values[k - 1]), cutAxis = axis;
    }
    if (widest > kFacetGap) {
      parts.resize(2);
      for (uint32_t s : items) parts[normal_[s][cutAxis] >= cut ? 1 : 0].push_back(s);
      for (size_t q = 0; q < 2; ++q) {
        uint32_t child = add(node, nodes_[node].depth + 1);
        split(child, parts[q], lo, hi, uvDepth);
      }
      return;
    }
    if (useUv_ && uvDepth < 40) {  // quadrants of the UV square; past float resolution: spatial
      glm::vec2 mid = 0.5f * (lo + hi);
      parts.resize(4);
      for (uint32_t s : items) parts[(uv_[s].x >= mid.x ? 1 : 0) + (uv_[s].y >= mid.y ? 2 : 0)].push_back(s);
      boxes = {{lo, mid}, {{mid.x, lo.y}, {hi.x, mid.y}}, {{lo.x, mid.y}, {mid.x, hi.y}}, {mid, hi}};
      int nonEmpty = 0;
      for (auto& p : parts) nonEmpty += !p.empty();
      if (nonEmpty == 1) {  // all in one quadrant: descend without making a node
        for (size_t q = 0; q < 4; ++q)
          if (!parts[q].empty()) return split(node, parts[q], boxes[q].first, boxes[q].second, uvDepth + 1);
      }
    } else {  // median split along the longest axis of the positions' bounds (the first of equal ones)
      glm::vec3 mn(1e30f), mx(-1e30f);
      for (uint32_t s : items) mn = glm::min(mn, pos_[s]), mx = glm::max(mx, pos_[s]);
      const glm::vec3 ext = mx - mn;
      const float longest = std::max({ext.x, ext.y, ext.z});
      const int axis = ext.x >= longest * (1 - 1e-4f) ? 0 : (ext.y >= longest * (1 - 1e-4f) ? 1 : 2);
      size_t half = items.size() / 2;
      std::nth_element(items.begin(), items.begin() + long(half), items.end(), [&](uint32_t a, uint32_t b) {
        return rank_[a][axis] < rank_[b][axis] || (rank_[a][axis] == rank_[b][axis] && a < b);
      });
      parts = {std::vector<uint32_t>(items.begin(), items.begin() + long(half)),
               std::vector<uint32_t>(items.begin() + long(half), items.end())};
      boxes.assign(2, {lo, hi});
    }
    for (size_t q = 0; q < parts.size(); ++q) {
      if (parts[q].empty()) continue;
      uint32_t child = add(node, nodes_[node].depth + 1);
      split(child, parts[q], boxes[q].first, boxes[q].second, uvDepth + 1);
    }
  }

  const std::vector<glm::vec3>& pos_;
  const std::vector<glm::vec3>& normal_;
  const std::vector<glm::uvec3>& rank_;
  const std::vector<glm::vec2>& uv_;
  bool useUv_;
  std::vector<BuildNode> nodes_;
};

// Children are numbered after their parents: from the last node back, every node's children are done.
void chooseRepresentatives(Hierarchy& h, const std::vector<scene::Surfel>& rest) {
  const size_t n = h.nodes.size();
  std::vector<glm::dvec3> weighted(n, glm::dvec3(0.0));
  std::vector<double> area(n, 0.0);
  h.representatives.assign(n, 0u);
  for (size_t i = n; i-- > 0;) {
    const gpu::TreeNode& t = h.nodes[i];
    if (t.childCount == 0) {
      const glm::vec4 pa = rest[size_t(t.surfel)].positionArea;
      // A surfel of no area still has a position: weigh it a little.
      area[i] = std::max(double(pa.w), 1e-30);
      weighted[i] = area[i] * glm::dvec3(pa);
      h.representatives[i] = uint32_t(t.surfel);
      continue;
    }
    for (uint32_t c = t.firstChild; c < t.firstChild + t.childCount; ++c)
      weighted[i] += weighted[c], area[i] += area[c];
    const glm::dvec3 centroid = weighted[i] / area[i];
    // The nearest, distances within a part in 10⁴ of the node's extent counting as equal (the lower
    // surfel then): on a regular grid several children are equally near, and which one rounding
    // would pick must not depend on the scene's scale.
    double nearest = 1e300, extent = 0.0;
    for (uint32_t c = t.firstChild; c < t.firstChild + t.childCount; ++c)
      extent = std::max(extent, glm::length(glm::dvec3(glm::vec3(rest[h.representatives[c]].positionArea)) - centroid));
    for (uint32_t c = t.firstChild; c < t.firstChild + t.childCount; ++c) {
      const uint32_t s = h.representatives[c];
      const double d = glm::length(glm::dvec3(glm::vec3(rest[s].positionArea)) - centroid);
      if (d < nearest - 1e-4 * extent || (d <= nearest + 1e-4 * extent && s < h.representatives[i]))
        nearest = std::min(nearest, d), h.representatives[i] = s;
    }
  }
}

// Per root: 1 where its surface at rest, normals out, encloses a volume: its signed volume about its
// centroid, Σ a n·(c − o)/3 over its surfels, is positive beyond rounding. Only such an object can
// hold another's surfels inside (shaders/gi/buried_surfels.comp); a plane, or a room whose normals
// face in, cannot.
std::vector<uint8_t> enclosingRoots(const Hierarchy& h, const std::vector<scene::Surfel>& rest) {
  const size_t roots = h.roots.size();
  const std::vector<uint32_t>& rootOf = h.rootOfSurfel;
  std::vector<glm::dvec3> weighted(roots, glm::dvec3(0.0));
  std::vector<double> area(roots, 0.0), volume(roots, 0.0);
  for (size_t s = 0; s < rootOf.size(); ++s) {
    const double a = rest[s].positionArea.w;
    weighted[rootOf[s]] += a * glm::dvec3(glm::vec3(rest[s].positionArea));
    area[rootOf[s]] += a;
  }
  for (size_t s = 0; s < rootOf.size(); ++s) {
    const uint32_t r = rootOf[s];
    const glm::dvec3 centroid = area[r] > 0.0 ? weighted[r] / area[r] : glm::dvec3(0.0);
    volume[r] +=
        rest[s].positionArea.w *
        glm::dot(glm::dvec3(glm::vec3(rest[s].normal)), glm::dvec3(glm::vec3(rest[s].positionArea)) - centroid) / 3.0;
  }
  std::vector<uint8_t> encloses(roots, 0);
  for (size_t r = 0; r < roots; ++r) encloses[r] = volume[r] > 1e-4 * std::pow(area[r], 1.5) ? 1 : 0;
  return encloses;
}

}  // namespace

bool usableUvAtlas(const std::vector<glm::vec2>& uvs, const std::vector<glm::uvec3>& triangles) {
  if (triangles.empty()) return false;
  constexpr int kGrid = 512;
  std::vector<uint8_t> covered(size_t(kGrid) * kGrid, 0);
  double uvArea = 0;
  for (const auto& t : triangles) {
    glm::vec2 a = uvs[t.x], b = uvs[t.y], c = uvs[t.z];
    for (glm::vec2 p : {a, b, c})
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || p.x < -1e-4f || p.y < -1e-4f || p.x > 1.0001f || p.y > 1.0001f)
        return false;
    float area2 = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (area2 == 0.0f) return false;  // collapsed UVs: no atlas
    uvArea += 0.5 * std::abs(area2);
    glm::ivec2 lo = glm::clamp(glm::ivec2(glm::floor(glm::min(a, glm::min(b, c)) * float(kGrid))), 0, kGrid - 1);
    glm::ivec2 hi = glm::clamp(glm::ivec2(glm::ceil(glm::max(a, glm::max(b, c)) * float(kGrid))), 0, kGrid - 1);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        glm::vec2 p((x + 0.5f) / kGrid, (y + 0.5f) / kGrid);
        float w0 = (b.x - p.x) * (c.y - p.y) - (c.x - p.x) * (b.y - p.y);
        float w1 = (c.x - p.x) * (a.y - p.y) - (a.x - p.x) * (c.y - p.y);
        float w2 = (a.x - p.x) * (b.y - p.y) - (b.x - p.x) * (a.y - p.y);
        bool inside = (w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0);
        if (inside) covered[size_t(y) * kGrid + x] = 1;
      }
  }
  double coveredArea = double(std::accumulate(covered.begin(), covered.end(), size_t(0))) / (double(kGrid) * kGrid);
  // Overlapping charts cover less than their summed area. Tiny atlases are below the grid's
  // resolution; treat them as unusable rather than guess.
  return coveredArea > 0.01 && uvArea <= coveredArea * 1.05 + 4.0 / kGrid;
}

Hierarchy buildHierarchy(const scene::Geometry& g, const std::vector<scene::Surfel>& rest) {
  const size_t surfelCount = g.surfels.size();
  std::vector<glm::vec3> positions(surfelCount), normals(surfelCount);
  std::vector<glm::vec2> uvs(surfelCount);
  std::vector<std::vector<uint32_t>> byInstance(g.instances.size());
  for (size_t s = 0; s < surfelCount; ++s) {
    uint32_t v = g.surfelVertices[g.surfels[s].firstVertex];
    positions[s] = glm::vec3(rest[s].positionArea);
    normals[s] = glm::vec3(rest[s].normal);
    uvs[s] = glm::vec2(g.uvs[v]);
    byInstance[g.vertices[v].instance].push_back(uint32_t(s));
  }
  // Triangles per instance, in surfel-independent vertex indices, for the atlas test.
  std::vector<std::vector<glm::uvec3>> instanceTriangles(g.instances.size());
  for (const auto& t : g.triangles) instanceTriangles[g.vertices[t.v0].instance].push_back({t.v0, t.v1, t.v2});
  std::vector<glm::vec2> vertexUvs(g.uvs.size());  // TEXCOORD_0
  for (size_t v = 0; v < g.uvs.size(); ++v) vertexUvs[v] = glm::vec2(g.uvs[v]);

  std::vector<std::vector<BuildNode>> trees;
  std::vector<glm::uvec3> ranks(surfelCount);
  Hierarchy h;
  h.size = extentOf(positions);
  for (size_t i = 0; i < g.instances.size(); ++i) {
    if (byInstance[i].empty()) continue;
    bool uv = usableUvAtlas(vertexUvs, instanceTriangles[i]);
    h.uvTree.push_back(uv);
    h.rootInstance.push_back(uint32_t(i));
    rankCoordinates(positions, byInstance[i], ranks);
    trees.push_back(TreeBuilder(positions, normals, ranks, uvs, uv).build(byInstance[i]));
  }
  // Number level by level over all trees: a node's children, in order, are contiguous.
  struct Pending {
    size_t tree;
    uint32_t local;
    int32_t parent;
  };
  std::vector<Pending> level;
  for (size_t t = 0; t < trees.size(); ++t) level.push_back({t, 0, -1});
  h.leafOfSurfel.assign(surfelCount, ~0u);
  while (!level.empty()) {
    h.levelStart.push_back(uint32_t(h.nodes.size()));
    uint32_t nextIndex = uint32_t(h.nodes.size() + level.size());
    std::vector<Pending> next;
    for (const Pending& p : level) {
      const BuildNode& b = trees[p.tree][p.local];
      uint32_t self = uint32_t(h.nodes.size());
      if (p.parent < 0) h.roots.push_back(self);
      h.nodes.push_back({p.parent, nextIndex, uint32_t(b.children.size()), b.surfel});
      if (b.surfel >= 0) h.leafOfSurfel[size_t(b.surfel)] = self;
      for (uint32_t c : b.children) next.push_back({p.tree, c, int32_t(self)});
      nextIndex += uint32_t(b.children.size());
    }
    level = std::move(next);
  }
  h.levelStart.push_back(uint32_t(h.nodes.size()));
  chooseRepresentatives(h, rest);
  const uint32_t end = uint32_t(h.nodes.size());
  h.skip.assign(end, end);
  for (uint32_t i = 0; i < end; ++i) {  // parents come before their children
    const int32_t parent = h.nodes[i].parent;
    const uint32_t last =
        parent < 0 ? uint32_t(h.roots.size()) : h.nodes[parent].firstChild + h.nodes[parent].childCount;
    h.skip[i] = i + 1 < last ? i + 1 : (parent < 0 ? end : h.skip[uint32_t(parent)]);
  }
  h.rootOfSurfel.resize(surfelCount);
  for (size_t s = 0; s < surfelCount; ++s) {
    uint32_t node = h.leafOfSurfel[s];
    while (h.nodes[node].parent >= 0) node = uint32_t(h.nodes[node].parent);
    h.rootOfSurfel[s] = node;
  }
  h.rootEncloses = enclosingRoots(h, rest);
  std::vector<uint32_t> groupNode(surfelCount);
  for (size_t s = 0; s < surfelCount; ++s) {
    uint32_t node = h.leafOfSurfel[s];
    for (int up = 0; up < 2 && h.nodes[node].parent >= 0; ++up) node = uint32_t(h.nodes[node].parent);
    groupNode[s] = node;
  }
  h.groups = groupNode;
  std::sort(h.groups.begin(), h.groups.end());
  h.groups.erase(std::unique(h.groups.begin(), h.groups.end()), h.groups.end());
  h.groupOfSurfel.resize(surfelCount);
  for (size_t s = 0; s < surfelCount; ++s)
    h.groupOfSurfel[s] = uint32_t(std::lower_bound(h.groups.begin(), h.groups.end(), groupNode[s]) - h.groups.begin());
  return h;
}

}  // namespace ivgi::gi

namespace ivgi::gi {

Hierarchy restPoseHierarchy(const scene::Scene& scene, const scene::Geometry& g) {
  const auto world = scene::animateOnHost(g, g.frameInputs(scene, scene::evaluatePose(scene, -1, 0.0f)));
  const auto rest = scene::surfelsOnHost(g, world);
  Hierarchy h = buildHierarchy(g, rest);
  h.rootAxes = objectAxes(g, world, rest, h.rootOfSurfel, h.rootInstance);
  return h;
}

namespace {

std::vector<bool> perRoot(const Hierarchy& h, const std::vector<bool>& perInstance) {
  std::vector<bool> roots;
  for (uint32_t instance : h.rootInstance) roots.push_back(perInstance[instance]);
  return roots;
}

}  // namespace

std::vector<bool> movingRoots(const Hierarchy& h, const scene::Scene& scene, const scene::Geometry& g, int animation) {
  return perRoot(h, scene::movingInstances(scene, g, animation));
}

std::vector<bool> rigidRoots(const Hierarchy& h, const scene::Scene& scene, const scene::Geometry& g, int animation) {
  return perRoot(h, scene::rigidlyMovingInstances(scene, g, animation));
}

}  // namespace ivgi::gi

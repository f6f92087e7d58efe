#include "engine/gi/bins.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>

#include "engine/core/notes.h"
#include "engine/core/parallel.h"
#include "shaders/interface.h"

namespace ivgi::gi {

float meanBinSolidAngle(uint32_t n) { return 4.0f * gpu::kPi / float(6 * n * n); }
float senderBinSpread(uint32_t n) { return meanBinSolidAngle(n) / (4.0f * gpu::kPi); }
float tableBinSpread(uint32_t n) { return meanBinSolidAngle(n) / 4.0f; }

void noteUnresolvedRoughness(const scene::Geometry& g, float spread, const char* method, const std::string& option) {
  float smoothest = 1.0f;
  bool glossy = false;
  for (const gpu::SurfaceBrdf& m : g.surfelBrdf)
    if (!gpu::isLambertian(m)) smoothest = std::min(smoothest, m.alpha), glossy = true;
  if (!glossy || smoothest * smoothest >= spread) return;
  char line[320];
  std::snprintf(line, sizeof line,
                "ivgi: %s: glossy surfaces of roughness %.2g are smoother than the %.2g that %s resolve: their "
                "reflections of the indirect light are drawn as of roughness %.2g (a larger %s resolves finer)\n",
                method, std::sqrt(smoothest), roughnessOfSpread(spread), option.c_str(), roughnessOfSpread(spread),
                option.substr(0, option.find(' ')).c_str());
  noteOnce(line);
}

namespace {

std::vector<glm::vec4> computeBinVectorTable(uint32_t n, BinFrame frame) {
  // Each bin cut into k×k cells of exact solid angle, each at its centre direction: the error falls
  // as 1/k², far below float precision at k = 32.
  constexpr int k = 32;
  auto phi = [](double u, double v) { return std::atan2(u * v, std::sqrt(u * u + v * v + 1.0)); };  // in double
  std::vector<glm::vec4> table(6 * n * n);
  const double step = 2.0 / n, cell = step / k;
  parallelFor(table.size(), [&](size_t bin) {
    const uint32_t b = uint32_t(bin), face = b / (n * n), r = b % (n * n);
    const double u0 = -1.0 + (r % n) * step, v0 = -1.0 + (r / n) * step;
    // The whole bin, and its part above the normal's horizon (z > 0; for odd n the middle row of
    // the side faces is cut along its middle, between two rows of the k cells).
    glm::dvec3 sum(0.0), sumAbove(0.0);
    double omegaAbove = 0.0;
    bool below = false;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const double a0 = u0 + i * cell, b0 = v0 + j * cell, a1 = a0 + cell, b1 = b0 + cell;
        const double omega = phi(a1, b1) - phi(a0, b1) - phi(a1, b0) + phi(a0, b0);
        const glm::vec3 centre = gpu::faceDirection(face, glm::vec2(float(a0 + 0.5 * cell), float(b0 + 0.5 * cell)));
        const glm::dvec3 part = glm::dvec3(glm::normalize(centre)) * omega;
        sum += part;
        if (centre.z > 0.0f)
          sumAbove += part, omegaAbove += omega;
        else
          below = true;
      }
    const bool cut = frame == BinFrame::Normal && below && omegaAbove > 0.0;
    table[b] =
        cut ? glm::vec4(glm::vec3(sumAbove), float(omegaAbove)) : glm::vec4(glm::vec3(sum), gpu::binSolidAngle(b, n));
  });
  return table;
}

}  // namespace

const std::vector<glm::vec4>& binVectorTable(uint32_t n, BinFrame frame) {
  static std::mutex lock;
  static std::map<std::pair<uint32_t, BinFrame>, std::vector<glm::vec4>> tables;
  const std::lock_guard<std::mutex> guard(lock);
  auto it = tables.find({n, frame});
  if (it == tables.end()) it = tables.emplace(std::pair(n, frame), computeBinVectorTable(n, frame)).first;
  return it->second;
}

std::vector<glm::vec4> environmentTable(const std::optional<scene::Environment>& environment, uint32_t n) {
  return environment ? environment->bins(n) : std::vector<glm::vec4>{glm::vec4(0)};
}

std::vector<glm::mat3> objectAxes(const scene::Geometry& g, const std::vector<scene::WorldVertex>& world,
                                  const std::vector<scene::Surfel>& surfels,
                                  const std::vector<uint32_t>& objectOfSurfel,
                                  const std::vector<uint32_t>& objectInstance) {
  const size_t objects = objectInstance.size();
  std::vector<std::vector<uint32_t>> members(objects), faces(objects);
  for (uint32_t i = 0; i < surfels.size(); ++i) members.at(objectOfSurfel[i]).push_back(i);
  std::vector<int> objectOf(g.instances.size(), -1);
  for (size_t o = 0; o < objects; ++o) objectOf.at(objectInstance[o]) = int(o);
  for (uint32_t t = 0; t < g.triangles.size(); ++t)
    if (const int o = objectOf[g.vertices[g.triangles[t].v0].instance]; o >= 0) faces[size_t(o)].push_back(t);
  std::vector<glm::mat3> axes(objects, glm::mat3(1.0f));
  parallelFor(objects, [&](size_t o) {
    std::vector<uint32_t>& own = members[o];
    if (own.empty()) return;
    auto area = [&](uint32_t i) { return double(surfels[i].positionArea.w); };
    auto normal = [&](uint32_t i) { return glm::vec3(surfels[i].normal); };
    // a: among the world's axes and the normals of the 32 largest surfels.
    std::vector<glm::vec3> candidates = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const size_t largest = std::min<size_t>(own.size(), 32);
    std::partial_sort(own.begin(), own.begin() + largest, own.end(),
                      [&](uint32_t x, uint32_t y) { return area(x) > area(y) || (area(x) == area(y) && x < y); });
    for (size_t k = 0; k < largest; ++k)
      if (glm::dot(normal(own[k]), normal(own[k])) > 0.5f) candidates.push_back(glm::normalize(normal(own[k])));
    glm::vec3 a = candidates[0];
    double best = -1;
    for (const glm::vec3& c : candidates) {
      double score = 0;
      for (uint32_t i : own) score += area(i) * std::pow(double(glm::dot(normal(i), c)), 4);
      if (score > best * (1 + 1e-9)) best = score, a = c;
    }
    // b: the orientation about a, modulo a right angle, that most of the normals across a (by area)
    // and of the edges of the faces along a's plane (by length) take: the most weighted degree of
    // the quarter turn, then the weighted mean about it. (A mean over all of them would lean
    // toward the diagonals that split a face: 10° on a quad twice as wide as high.)
    glm::vec3 t1, t2;
    gpu::tangentFrame(a, t1, t2);
    std::vector<std::pair<float, float>> turns;  // angle in [0, π/2), weight
    auto addTurn = [&](glm::vec3 d, float weight) {
      const float x = glm::dot(d, t1), y = glm::dot(d, t2);
      if (!(weight > 0.0f) || (x == 0.0f && y == 0.0f)) return;
      float angle = std::fmod(std::atan2(y, x) + 2.0f * gpu::kPi, 0.5f * gpu::kPi);
      turns.push_back({angle < 0.5f * gpu::kPi ? angle : 0.0f, weight});
    };
    for (uint32_t i : own) {
      const float along = glm::dot(normal(i), a);
      addTurn(normal(i), float(area(i)) * (1.0f - along * along));
    }
    for (uint32_t t : faces[o]) {
      const glm::vec3 p0(world[g.triangles[t].v0].position), p1(world[g.triangles[t].v1].position),
          p2(world[g.triangles[t].v2].position), n = glm::cross(p1 - p0, p2 - p0);
      const float twiceArea = glm::length(n), along = twiceArea > 0.0f ? glm::dot(n, a) / twiceArea : 0.0f;
      for (glm::vec3 e : {p1 - p0, p2 - p1, p0 - p2}) addTurn(e, along * along * glm::length(e));
    }
    constexpr int kDegrees = 90;
    std::array<double, kDegrees> byDegree{};
    const float perDegree = float(kDegrees) / (0.5f * gpu::kPi);
    for (const auto& [angle, weight] : turns) byDegree[std::min(int(angle * perDegree), kDegrees - 1)] += weight;
    int peak = 0;
    for (int k = 1; k < kDegrees; ++k) {
      auto around = [&](int c) {
        return byDegree[size_t((c + kDegrees - 1) % kDegrees)] + byDegree[size_t(c)] +
               byDegree[size_t((c + 1) % kDegrees)];
      };
      if (around(k) > around(peak)) peak = k;
    }
    const float centre = (float(peak) + 0.5f) / perDegree;
    double sum = 0, weights = 0;
    for (const auto& [angle, weight] : turns) {
      float offset = std::remainder(angle - centre, 0.5f * gpu::kPi);  // in (−π/4, π/4]
      if (std::abs(offset) <= 1.5f / perDegree) sum += double(weight) * offset, weights += weight;
    }
    const float angle = weights > 0 ? centre + float(sum / weights) : 0.0f;
    const glm::vec3 b = std::cos(angle) * t1 + std::sin(angle) * t2;
    axes[o] = glm::transpose(glm::mat3(b, glm::cross(a, b), a));
  });
  return axes;
}

}  // namespace ivgi::gi

#include "engine/gi/bins.h"

#include <algorithm>
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

std::vector<glm::vec4> computeBinVectorTable(uint32_t n) {
  // Each bin cut into k×k cells of exact solid angle, each at its centre direction: the error falls
  // as 1/k², far below float precision at k = 32.
  constexpr int k = 32;
  auto phi = [](double u, double v) { return std::atan2(u * v, std::sqrt(u * u + v * v + 1.0)); };  // in double
  std::vector<glm::vec4> table(6 * n * n);
  const double step = 2.0 / n, cell = step / k;
  parallelFor(table.size(), [&](size_t bin) {
    const uint32_t b = uint32_t(bin), face = b / (n * n), r = b % (n * n);
    const double u0 = -1.0 + (r % n) * step, v0 = -1.0 + (r / n) * step;
    glm::dvec3 sum(0.0);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const double a0 = u0 + i * cell, b0 = v0 + j * cell, a1 = a0 + cell, b1 = b0 + cell;
        const double omega = phi(a1, b1) - phi(a0, b1) - phi(a1, b0) + phi(a0, b0);
        const glm::vec3 centre = gpu::faceDirection(face, glm::vec2(float(a0 + 0.5 * cell), float(b0 + 0.5 * cell)));
        sum += glm::dvec3(glm::normalize(centre)) * omega;
      }
    table[b] = glm::vec4(glm::vec3(sum), gpu::binSolidAngle(b, n));
  });
  return table;
}

}  // namespace

const std::vector<glm::vec4>& binVectorTable(uint32_t n) {
  static std::mutex lock;
  static std::map<uint32_t, std::vector<glm::vec4>> tables;
  const std::lock_guard<std::mutex> guard(lock);
  auto it = tables.find(n);
  if (it == tables.end()) it = tables.emplace(n, computeBinVectorTable(n)).first;
  return it->second;
}

std::vector<glm::vec4> environmentTable(const std::optional<scene::Environment>& environment, uint32_t n) {
  return environment ? environment->bins(n) : std::vector<glm::vec4>{glm::vec4(0)};
}

}  // namespace ivgi::gi

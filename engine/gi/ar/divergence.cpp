#include "engine/gi/ar/divergence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ivgi::gi {

namespace {

constexpr float kNegativeBound = 0.5f, kGrowthBound = 10.0f;
constexpr size_t kFirstJudged = 8, kSettleSpan = 16;

std::string figure(const char* format, double value, size_t index) {
  char text[160];
  std::snprintf(text, sizeof text, format, value);
  return std::string(text) + " at iteration " + std::to_string(index + 1);
}

}  // namespace

std::optional<std::string> divergence(std::span<const float> changes, std::span<const float> negatives, size_t fresh,
                                      float damping) {
  const size_t n = changes.size(), first = n - std::min(fresh, n);
  if (first == n) return std::nullopt;
  for (size_t i = first; i < n; ++i)
    if (!std::isfinite(changes[i]) || !std::isfinite(negatives[i]))
      return "a change that is not a finite number at iteration " + std::to_string(i + 1);
  const float best = *std::min_element(changes.begin(), changes.end());
  const size_t worst = size_t(std::max_element(changes.begin() + first, changes.end()) - changes.begin());
  if (n >= kFirstJudged && changes[worst] > 1.0f && changes[worst] > kGrowthBound * best)
    return figure("the irradiance changed by %.3g of itself", changes[worst], worst);
  if (damping == 1.0f) {
    const size_t most = size_t(std::max_element(negatives.begin() + first, negatives.end()) - negatives.begin());
    if (n >= 3 && negatives[most] > kNegativeBound)
      return figure("light cancelled past zero %.3g times the light", negatives[most], most);
    return std::nullopt;
  }
  if (n >= kFirstJudged && changes.back() > 1.0f)
    return figure("the irradiance changed by %.3g of itself", changes.back(), n - 1);
  if (n > kSettleSpan && changes.back() > 0.75f * changes[n - 1 - kSettleSpan])
    return figure("the change fell by less than a quarter over 16 iterations, to %.3g of the irradiance",
                  changes.back(), n - 1);
  return std::nullopt;
}

}  // namespace ivgi::gi

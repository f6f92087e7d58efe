#include "engine/gi/ar/settings.h"

#include "engine/core/errors.h"

namespace ivgi::gi {

void validate(const ArSettings& s) {
  if (s.dirs < 1 || s.dirs > 32) throw SettingsError("--dirs " + std::to_string(s.dirs) + ": must be 1 to 32");
  if (!(s.epsilon > 0.0f && s.epsilon <= 1.0f)) throw SettingsError("--eps must lie in (0, 1]");
  if (!(s.kappa >= 0.01f && s.kappa <= 1000.0f)) throw SettingsError("--kappa must lie in [0.01, 1000]");
  if (s.iterations && (*s.iterations < 1 || *s.iterations > kMaxIterations))
    throw SettingsError("--iterations must be 1 to " + std::to_string(kMaxIterations));
  if (!(s.tolerance > 0.0f && s.tolerance < 1.0f)) throw SettingsError("--iteration-tol must lie in (0, 1)");
  if (s.restartEvery < 1 || s.restartEvery > kMostRestartEvery)
    throw SettingsError("--restart-every must be 1 to " + std::to_string(kMostRestartEvery));
  if (!(s.leastDamping > 0.0f && s.leastDamping <= 1.0f))
    throw SettingsError("ar: the least damping must lie in (0, 1]");
}

ArScheme parseScheme(const std::string& text) {
  if (text == "symmetric") return ArScheme::Symmetric;
  if (text == "asymmetric") return ArScheme::Asymmetric;
  throw SettingsError("--scheme '" + text + "': schemes are symmetric and asymmetric");
}

const char* schemeName(ArScheme scheme) { return scheme == ArScheme::Symmetric ? "symmetric" : "asymmetric"; }

}  // namespace ivgi::gi

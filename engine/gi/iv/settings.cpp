#include "engine/gi/iv/settings.h"

#include <string>

#include "engine/core/errors.h"

namespace ivgi::gi {

void validate(const IvSettings& s) {
  if (s.bins < 1 || s.bins > 64) throw SettingsError("--bins " + std::to_string(s.bins) + ": must be 1 to 64");
  if (!(s.epsilon > 0.0f && s.epsilon <= 1.0f)) throw SettingsError("--eps must lie in (0, 1]");
  if (s.bounces && *s.bounces > kMaxBounces)
    throw SettingsError("--bounces must be 0 to " + std::to_string(kMaxBounces));
  if (!(s.bounceTolerance > 0.0f && s.bounceTolerance < 1.0f)) throw SettingsError("--bounce-tol must lie in (0, 1)");
  if (s.receiverTolerance && !(*s.receiverTolerance >= 0.0f && *s.receiverTolerance <= 10.0f))
    throw SettingsError("--receiver-tol must lie in [0, 10]");
  if (!(s.unseenTolerance >= 1.0f && s.unseenTolerance <= 1000.0f))
    throw SettingsError("--unseen-tol must lie in [1, 1000]");
  if (!(s.kappa >= 0.01f && s.kappa <= 1000.0f)) throw SettingsError("--kappa must lie in [0.01, 1000]");
}

float receiverToleranceOn(const IvSettings& s, bool cpuDevice) {
  return s.receiverTolerance.value_or(cpuDevice ? kCpuReceiverTolerance : 0.0f);
}

bool rigidOnceOn(const IvSettings& s) { return s.rigidOnce.value_or(true); }

}  // namespace ivgi::gi

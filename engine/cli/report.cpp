#include "engine/cli/report.h"

#include "engine/gi/ar/solver.h"
#include "engine/gi/iv/solver.h"

namespace ivgi::gi {

// IvStats as JSON, its fields' names as the keys.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(IvStats, nodes, levels, links, leafLinks, staticLinks, staticLeafLinks, bytes,
                                   sharedBins, pruneBatches, pruneGroupSize, sendersWalked, staticSendersWalked,
                                   mergedSendersWalked, rigidSendersWalked, rigidLeaves, framesRedone, staticPasses,
                                   bounces, bounceRemaining, receivers, receiverFills)

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ArStats, nodes, levels, links, staticLinks, longestList, gatherChunks, bytes,
                                   tableBytes, iterations, warm, residual, negative, diverged, damping, framesRedone,
                                   residuals)

}  // namespace ivgi::gi

namespace ivgi::cli {

nlohmann::json bouncesJson(const gi::IvSettings& s) {
  return s.bounces ? nlohmann::json(*s.bounces) : nlohmann::json("auto");
}

std::string bouncesText(const gi::IvSettings& s) { return s.bounces ? std::to_string(*s.bounces) : "auto"; }

nlohmann::json settingsJson(const std::string& method, const gi::IvSettings& iv, uint32_t tessellation,
                            const gi::ArSettings& ar, const std::optional<gi::DirectLightSettings>& directLight) {
  const nlohmann::json direct = directLight
                                    ? nlohmann::json{{"from", directLight->perPixel ? "pixels" : "maps"},
                                                     {"lightSamples", directLight->samples},
                                                     {"shadowMap", directLight->resolution},
                                                     {"environmentDirections", directLight->environmentLights().size()}}
                                    : nlohmann::json{{"from", "bins"}};
  if (method == "ar")
    return {{"method", method},
            {"dirs", ar.dirs},
            {"eps", ar.epsilon},
            {"kappa", ar.kappa},
            {"iterations", ar.iterations ? nlohmann::json(*ar.iterations) : nlohmann::json("auto")},
            {"iterationTolerance", ar.tolerance},
            {"scheme", gi::schemeName(ar.scheme)},
            {"restartEvery", ar.restartEvery},
            {"tessellation", tessellation},
            {"direct", direct}};
  return {{"method", method},
          {"bins", iv.bins},
          {"eps", iv.epsilon},
          {"bounces", bouncesJson(iv)},
          {"bounceTolerance", iv.bounceTolerance},
          {"kappa", iv.kappa},
          {"receiverTolerance", iv.receiverTolerance ? nlohmann::json(*iv.receiverTolerance) : nlohmann::json("auto")},
          {"unseenTolerance", iv.unseenTolerance},
          {"rigid", iv.rigidOnce ? (*iv.rigidOnce ? "once" : "every-frame") : "auto"},
          {"tessellation", tessellation},
          {"direct", direct}};
}

nlohmann::json solverJson(const gi::Solver* solver) {
  if (!solver) return nullptr;
  if (const auto* iv = dynamic_cast<const gi::IvSolver*>(solver)) {
    nlohmann::json j = iv->stats();
    j["method"] = "iv";
    j["receiverTolerance"] = *iv->settings().receiverTolerance;
    j["unseenTolerance"] = iv->guidedByView() ? iv->settings().unseenTolerance : 1.0f;
    j["rigidOnce"] = gi::rigidOnceOn(iv->settings());
    return j;
  }
  if (const auto* ar = dynamic_cast<const gi::ArSolver*>(solver)) {
    nlohmann::json j = ar->stats();
    j["method"] = "ar";
    return j;
  }
  return {{"bytes", solver->allocatedBytes()}};
}

}  // namespace ivgi::cli

#include "engine/cli/report.h"

#include "engine/gi/iv/solver.h"

namespace ivgi::cli {

nlohmann::json solverJson(const gi::Solver* solver) {
  if (!solver) return nullptr;
  nlohmann::json j = {{"bytes", solver->allocatedBytes()}};
  if (const auto* iv = dynamic_cast<const gi::IvSolver*>(solver)) {
    const gi::IvStats s = iv->stats();
    j.update({{"method", "iv"},
              {"nodes", s.nodes},
              {"levels", s.levels},
              {"links", s.links},
              {"leafLinks", s.leafLinks},
              {"staticLinks", s.staticLinks},
              {"staticLeafLinks", s.staticLeafLinks},
              {"sharedMemoryBins", s.sharedBins},
              {"pruneBatches", s.pruneBatches},
              {"pruneGroupSize", s.pruneGroupSize},
              {"sendersWalked", s.sendersWalked},
              {"staticSendersWalked", s.staticSendersWalked},
              {"framesRedone", s.framesRedone},
              {"staticPasses", s.staticPasses}});
  }
  return j;
}

}  // namespace ivgi::cli

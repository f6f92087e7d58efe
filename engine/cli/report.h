#pragma once
// The solver's figures as the sidecar, bench and sweep report them (one function for all three).
#include <nlohmann/json.hpp>

#include "engine/gi/solver.h"

namespace ivgi::cli {

// The solver's counts, memory and work as JSON; null for no solver.
nlohmann::json solverJson(const gi::Solver* solver);

}  // namespace ivgi::cli

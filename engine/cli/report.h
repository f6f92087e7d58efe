#pragma once
// The solver's figures as the sidecar, bench and sweep report them (one function for all three).
#include <nlohmann/json.hpp>

#include <optional>

#include "engine/gi/ar/settings.h"
#include "engine/gi/direct_light.h"
#include "engine/gi/iv/settings.h"
#include "engine/gi/solver.h"

namespace ivgi::cli {

// The iv settings' bounces: the count given, or "auto" (until converged).
nlohmann::json bouncesJson(const gi::IvSettings& settings);
// "2", or "auto" (until converged).
std::string bouncesText(const gi::IvSettings& settings);

// A method's settings as render, bench and sweep record them: the method, and iv's (bins, ε,
// bounces and their tolerance, κ, the receivers' tolerance, the tessellation, where the direct light
// comes from: "bins", or "maps" with its samples and map side), or ar's (directions, ε, κ, iterations
// and their tolerance, scheme, the tessellation).
nlohmann::json settingsJson(const std::string& method, const gi::IvSettings& iv, uint32_t tessellation,
                            const gi::ArSettings& ar = {},
                            const std::optional<gi::DirectLightSettings>& directLight = std::nullopt);

// The solver's counts, memory and work as JSON; null for no solver.
nlohmann::json solverJson(const gi::Solver* solver);

}  // namespace ivgi::cli

#pragma once
// What a user chooses for the ar solver, with its defaults (defined here only), and the figures it
// reports.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/environment.h"

namespace ivgi::gi {

enum class ArScheme {
  Symmetric,   // radiance and antiradiance updated together each iteration (shadows a step behind)
  Asymmetric,  // a radiance step, then gpu::kAntiradianceSteps antiradiance steps
};

struct ArSettings {
  uint32_t dirs = 4;      // --dirs N: 6×N×N direction bins per node and surfel
  float epsilon = 0.02f;  // --eps: refine links while their form-factor estimate is above it
  float kappa = 1.0f;     // --kappa: refine while either side covers more than κ bins from the other
  // --iterations K: exactly K iterations; none: until an iteration changes the irradiance by less than
  // --iteration-tol of it.
  std::optional<uint32_t> iterations;
  float tolerance = 1e-3f;  // --iteration-tol
  ArScheme scheme = ArScheme::Symmetric;
  // --restart-every K: a frame whose number is a multiple of K starts its iteration from the
  // emission, every other from the solution of the frame before it (solved first where it was not
  // asked for: ArSolver::chainStart), so that a frame's image depends on its number alone. 1: every
  // frame from the emission.
  uint32_t restartEvery = 16;
  bool chained() const { return restartEvery > 1; }
  std::optional<scene::Environment> environment;  // --env; none: no environment light
  uint64_t memoryBudget = 0;                      // --max-memory, in bytes; 0: the device's heap
  // The links of a receiver's list one dispatch of the global pass walks; 0: gpu::kArGatherChunk.
  // Tests set few, so that lists take several dispatches (the frame is redone with more).
  uint32_t gatherChunkLinks = 0;
  // The most bins of a receiver's table the global pass sums in each invocation (a larger one is
  // summed in place, in device memory); 0: gpu::kArGatherTableHere. Tests set 1, so that the two
  // ways can be compared.
  uint32_t gatherTableHereMost = 0;
  // The least share of a step a diverging iteration is damped to (halving from a whole step) before
  // it is stopped at its best iteration. Damping holds an iteration whose changes alternate in sign
  // (each surface's antiradiance a step behind the light it cancels); one whose light grows on its
  // own is not held by any. Tests set 1 (no damping) to reach the stop.
  float leastDamping = 0.25f;
  // Tests: every frame is redone once, as a frame that ran out of room is, so that a frame redone can
  // be compared with one solved once.
  bool redoEachFrameOnce = false;
  // Tests: senders inside other objects are linked too. A moving object buries what it stands on only
  // while it stands there, so links made once keep what a full relink leaves out; linked, the two
  // agree, which tests of links made once compare.
  bool linkBuriedSenders = false;
};

// The most iterations a frame runs: a guard against typing errors and light that does not converge.
inline constexpr uint32_t kMaxIterations = 2000;

// The longest chain of frames --restart-every allows (a frame may have to solve as many before it).
inline constexpr uint32_t kMostRestartEvery = 100000;

// Throws SettingsError naming the option when a setting is out of its range.
void validate(const ArSettings& settings);
ArScheme parseScheme(const std::string& text);  // throws SettingsError
const char* schemeName(ArScheme scheme);

struct ArStats {
  uint32_t nodes = 0, levels = 0, links = 0;
  uint32_t staticLinks = 0;            // of the links, those between static objects (made once)
  uint32_t longestList = 0;            // the most links one receiver node has
  uint32_t gatherChunks = 0;           // the global pass's dispatches an iteration, each a chunk of every list
  uint64_t bytes = 0, tableBytes = 0;  // in all; of those, the directional tables
  uint32_t iterations = 0;             // the last frame's
  bool warm = false;                   // whether it started from the frame before's solution
  float residual = 0;                  // its last iteration's change of the irradiance, over the irradiance
  float negative = 0;                  // light cancelled past zero, over the irradiance
  bool diverged = false;               // the iteration was stopped where it diverged
  float damping = 1.0f;                // the share of a step the last frame's iteration took
  uint32_t framesRedone = 0;
  std::vector<float> residuals;  // per iteration of the last frame
};

}  // namespace ivgi::gi

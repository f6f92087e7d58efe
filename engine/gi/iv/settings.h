#pragma once
// What a user chooses for the iv solver, with its defaults (defined here only), and the figures it
// reports.
#include <cstdint>
#include <optional>

#include "engine/scene/environment.h"

namespace ivgi::gi {

struct IvSettings {
  uint32_t bins = 16;     // --bins N: 6×N×N direction bins
  float epsilon = 0.02f;  // --eps: refine links while their form-factor estimate is above it
  // --bounces K: exactly K indirect bounces (0: direct light only); none: until a bounce adds less
  // than --bounce-tol of the light still to come (estimated from the last two bounces).
  std::optional<uint32_t> bounces;
  float bounceTolerance = 1e-3f;  // --bounce-tol
  float kappa = 1.0f;             // --kappa: refine while a sender covers more than κ average bins
  // --receiver-tol: irradiance is solved at receivers chosen where a receiver's irradiance,
  // predicted from its neighbours, misses by more than this share of it; 0: at every surfel.
  // None: chosen by the device (receiverToleranceOn).
  std::optional<float> receiverTolerance;
  // --unseen-tol: the surfaces the image does not show (their light reaches it only after a bounce)
  // are judged at this many times --receiver-tol; 1: like those it shows.
  float unseenTolerance = 16.0f;
  // Whether the receivers may follow the image's view at all. Not where the camera moves over a still
  // scene: its solution, made once, serves every view.
  bool viewGuided = true;
  std::optional<scene::Environment> environment;  // --env; none: no environment light
  uint64_t memoryBudget = 0;  // --max-memory, in bytes: the most the solver may allocate; 0: the device's heap
  // The most workgroups one prune dispatch runs; 0: as many as the scene and the device allow. Fewer
  // prune in more dispatches (batches) with the same result; tests batch small scenes with it.
  uint32_t pruneGroups = 0;
  // Leaves a prune workgroup walks in one dispatch; 0: 8. Tests run many to spend lavapipe's loop
  // budget (common.glsl), which the solver must notice and redo.
  uint32_t pruneLeaves = 0;
  // --rigid: whether an object that moves rigidly has its links to itself made and pruned once, in
  // its rest pose, like those between static objects (each leaf the first time it is a receiver;
  // every one at the first frame where every surfel is); else every frame with the rest of its links
  // (at that frame's receivers). None: once (rigidOnceOn).
  std::optional<bool> rigidOnce;
  // Tests: the static set's leaf links keep no room to spare once a frame stands, so that the next
  // frame's new rigid receivers overflow it (and it grows keeping what it holds).
  bool exactStaticRoom = false;
  // Tests: senders inside other objects are linked too. A moving object buries what it stands on only
  // while it stands there, so links made once keep what a full relink leaves out; linked, the two
  // agree, which tests of links made once compare.
  bool linkBuriedSenders = false;
};

// The most bounces a frame runs, given or until converged: a guard against typing errors and
// against light that does not converge (an albedo of 1).
inline constexpr uint32_t kMaxBounces = 10000;

// --receiver-tol's default on a CPU device (lavapipe), where choosing fewer receivers saves work.
inline constexpr float kCpuReceiverTolerance = 0.4f;
// The tolerance a solver on such a device uses: --receiver-tol as given; else kCpuReceiverTolerance
// on a CPU and 0 (every surfel) on a GPU, whose width prunes every surfel at once in about the time
// the receivers' rounds, each waiting on the one before, take to choose and prune fewer.
float receiverToleranceOn(const IvSettings& settings, bool cpuDevice);

// Whether a solver with these settings prunes a rigid object's links to itself once: --rigid as
// given, else yes.
bool rigidOnceOn(const IvSettings& settings);

// Throws SettingsError naming the option when a setting is out of its range.
void validate(const IvSettings& settings);

struct IvStats {
  uint32_t nodes = 0, levels = 0, links = 0, leafLinks = 0;
  uint32_t staticLinks = 0, staticLeafLinks = 0;  // of those, made once between objects that cannot move
  uint64_t bytes = 0;
  uint64_t hostBytes = 0;  // of those, link arrays in host memory (where the device's could not hold them)
  bool sharedBins = true;
  uint32_t pruneBatches = 0;    // dispatches a prune takes (each of at most a few leaves a workgroup)
  uint32_t pruneGroupSize = 0;  // invocations a prune workgroup has (more when one ran out of loop rounds)
  // The prune's work: root-path senders its leaves walked, in the last relinked frame and in the
  // static pass (once; the frame then walks only the senders of the pairs with a moving side), and
  // of the frame's, those the static leaves walked (the moving leaves walked the rest), and of
  // those, the ones the leaves of rigid objects walked (rigidLeaves of them).
  uint64_t sendersWalked = 0, staticSendersWalked = 0, mergedSendersWalked = 0, rigidSendersWalked = 0;
  uint32_t rigidLeaves = 0;
  // Since the solver was made: frames redone because their links outgrew the room they had or a
  // prune workgroup its loop budget (the timings are the redone frame's), and static passes run (1
  // once the static links are whole).
  uint32_t framesRedone = 0, staticPasses = 0;
  // The last frame's bounces (gathers − 1), and the light its bounces were estimated to leave out,
  // as a share of the light (0 where they stopped at a count: not estimated then).
  uint32_t bounces = 0;
  float bounceRemaining = 0;
  // The last relinked frame's receivers (surfels whose irradiance is solved; the rest interpolate),
  // and of those the surfels no receiver reached, made receivers.
  uint32_t receivers = 0, receiverFills = 0;
};

}  // namespace ivgi::gi

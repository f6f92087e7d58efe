#pragma once
// The ivgi subcommands. Each returns the process exit status; bad input throws (scene::LoadError,
// SettingsError, vk::VulkanError, std::runtime_error) and main() turns it into one line on stderr.
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/gi/ar/solver.h"
#include "engine/gi/frame_renderer.h"
#include "engine/gi/iv/solver.h"
#include "engine/image/metrics.h"
#include "engine/reference/path_tracer.h"
#include "engine/scene/geometry.h"
#include "engine/scene/scene.h"

namespace ivgi::cli {

// The Vulkan device a command runs on: --device (a name substring, index or UUID; empty: IVGI_DEVICE,
// else the best), unless the program running the command line lent its own (run()): a program that
// runs many commands in one process (the tests) spares each the device's creation and the
// compilation of its pipelines.
struct DeviceChoice {
  std::string name;
  vk::Context* lent = nullptr;  // used when `name` is empty
};
// The device `choice` names: the lent one, or one opened now and closed with the last reference.
std::shared_ptr<vk::Context> openDevice(const DeviceChoice& choice);

struct SceneChoice {
  std::string scene;     // a .gltf/.glb path or a built-in name; empty: the animated Cornell box
  int cells = 8;         // tessellation of the built-in scenes
  bool glossy = false;   // the Cornell box's glossy variant
  scene::Limits limits;  // what a scene may declare (--max-triangles, --max-morph-deltas)
};
// The scene named by `choice`, loaded and checked.
scene::Scene loadScene(const SceneChoice& choice);
// The lighting method and its settings, shared by render, bench, sweep and info. The defaults are
// the settings structs' own.
struct SolverOptions {
  std::string method = "iv";  // iv, ar, none (emission only) or pt (render only)
  gi::IvSettings iv;          // --bins, --eps, --bounces, --kappa, --receiver-tol (--eps and --kappa: ar's too)
  gi::ArSettings ar;          // --dirs, --iterations, --iteration-tol
  std::string arScheme = "symmetric";  // --scheme
  std::string environment;             // --env: "R,G,B", an .exr, or none; empty: the scene's own light (see below)
  uint64_t maxMemoryMiB = 0;           // --max-memory: the solver's memory budget (0: the device's)
  uint32_t tessellation = 16;          // --tessellate: iv and ar sample surfaces at least this finely
  // --direct: where the emitters' direct light comes from: "bins" (the solver's own), "maps" (depth
  // maps, gi::DirectLight: --light-samples, --shadow-map, at the surfels) or "pixels" (the maps
  // looked up at the pixels too); empty: pixels for iv and ar where the maps suit the emitters,
  // else the solver's own (directLightSettings).
  std::string direct;
  gi::DirectLightSettings maps;
  // --rigid: "once" (an object that moves rigidly has its links to itself pruned once, in its rest
  // pose: gi::IvSettings::rigidOnce), "every-frame" or "auto".
  std::string rigid = "auto";
};
// The frame's direct light from depth maps, where --direct asks for it (checked: SettingsError) or,
// by default, where iv or ar renders emitters or punctual lights that the maps suit
// (gi::emissiveAreaShare, gi::emitterPowerShare).
std::optional<gi::DirectLightSettings> directLightSettings(const SolverOptions& options, const scene::Scene& scene,
                                                           const scene::Geometry& geometry);

// The tessellation `solver`'s method samples surfaces with (scene::buildGeometry): --tessellate for
// iv and ar, 0 (the mesh as modelled) for pt and none.
uint32_t sampledTessellation(const SolverOptions& solver);

// The scene's flattened geometry, as `solver`'s method samples it, the backs of its open surfaces
// that see only open space given faces where the environment withSceneLight() gives it lights
// them; throws LoadError when there is no triangle to render.
scene::Geometry renderableGeometry(const scene::Scene& scene, const SolverOptions& solver, const scene::Limits& limits);
// The loader's warnings (what the file holds that ivgi ignores), a line each on stderr; said once
// the scene is known to render, so that a refusal before it stays its one line.
void sayWarnings(const scene::Scene& scene);
// Whether the environment withSceneLight() gives lights open space: --env as given, or where it is
// not, the default sky of a scene whose drawn materials emit nothing and which has no light.
scene::OpenSpace openSpaceOf(const SolverOptions& solver, const scene::Scene& scene);
// A progress line on stderr for building a scene, shown once the build has taken two seconds.
scene::BuildProgress buildProgress();

// The light a scene without any gets: --env as given ("none": no environment); for a scene with no
// emitter and no punctual light, a uniform white sky, said once on stderr, as glTF viewers do.
SolverOptions withSceneLight(SolverOptions options, const scene::Scene& scene, const scene::Geometry& geometry);

// ar's settings from the options (--eps and --kappa are shared with iv; checked by the solver).
gi::ArSettings arSettings(const SolverOptions& options);
// The solver for `options`, or none for --method none; `animation` (-1: none) says which objects
// can move. The hierarchy depends only on the scene: pass one already built to reuse it.
std::unique_ptr<gi::Solver> makeSolver(const SolverOptions& options, const vk::Context& ctx, const scene::Scene& scene,
                                       const scene::Geometry& geometry, int animation,
                                       const gi::Hierarchy* hierarchy = nullptr);

// The path tracer's own options (--method pt).
struct PathOptions {
  uint32_t spp = 64;
  uint32_t seed = 0;
  unsigned threads = 0;  // 0: every core
  bool given = false;    // any of them was given on the command line
};
// The tracer's settings (checked: SettingsError).
reference::PathSettings pathSettings(const PathOptions& options, const SolverOptions& solver);

struct RenderOptions {
  SceneChoice source;
  SolverOptions solver;
  PathOptions pt;
  std::string frames;  // empty: the whole animation
  double fps = 24.0;
  std::string size = "640x360";
  uint32_t supersample = 1;
  std::string out = "out/frame_%04d";
  std::string formats = "exr,png";
  std::string tonemap = "aces";
  float exposure = 0.0f;
  std::string camera, animation, json;
  DeviceChoice device;
  bool resume = false;
  std::string shard;                   // "I/N" or "slurm"; empty: every frame
  std::optional<uint32_t> writeAhead;  // frames written while the next render; default by the device
};
int runRender(const RenderOptions& options);

// Gathers the sidecars of a (sharded) render with output `pattern` into one summary of the
// sequence; returns 1 when frames are missing.
struct ReportOptions {
  std::string pattern;
  std::string json;
};
int runReport(const ReportOptions& options);

struct InfoOptions {
  SceneChoice source;
  SolverOptions solver;
  bool memory = false;  // set when --method is given: report the solver's memory
  DeviceChoice device;  // where the solver's memory is measured
};
int runInfo(const InfoOptions& options);

struct SceneOptions {
  std::string name;
  std::string out;
  int cells = 8;
  float albedo = 0.5f, emission = 1.0f;
  bool still = false, blocks = false, glossy = false;
};
int runScene(const SceneOptions& options);

struct BenchOptions {
  SceneChoice source;
  SolverOptions solver;
  int frames = 20, warmup = 3;
  double fps = 24.0;
  std::string size = "320x240";
  uint32_t supersample = 1;  // N×N samples per pixel
  std::string json;
  DeviceChoice device;
  bool perProgram = false;  // also time every dispatch, by program
  // --equal-error: iv's time and relMSE against a converged pt reference of one frame, and the time
  // pt needs to reach that relMSE.
  bool equalError = false;
  std::string reference;  // an existing reference EXR; empty: render one with referenceSpp
  uint32_t referenceSpp = 4096;
  uint32_t maxSpp = 4096;  // pt stops doubling its spp here
  int frame = 0;           // the frame compared
  unsigned threads = 0;    // pt threads (0: every core)
};
// Renders warm-up + measured frames in memory and prints per-pass GPU times and the counts.
int runBench(const BenchOptions& options);
void checkFrameCounts(const BenchOptions& options);  // --frames and --warmup
int runEqualError(const BenchOptions& options);

int runDevices();

struct CompareOptions {
  std::string test, reference;  // two .exr files, two folders, or two patterns with a frame number
  std::string json, heatmap, ratio, mask;
  float exposure = 0.0f;  // stops, before the ACES tone map that FLIP sees
  // Limits; each absent one is not checked.
  std::optional<double> maxRelMse, maxFlip, maxPixelError;
  std::optional<double> maxTemporal;        // a sequence's temporal relMSE (its flicker against the reference's)
  std::optional<double> maxFailingPercent;  // with pixelTolerance on `layers`: the per-pixel rule
  float pixelTolerance = 0.02f;
  std::string layers = "rgb";  // comma-separated layer names, or all
  bool golden = false;         // the rule of ivgi's own golden tests on every layer
};
// Scores TEST against REF (every pair of frames of two sequences): relMSE, RMSE, PSNR, max error
// and FLIP, and the per-pixel rule where asked. Returns 0 when every limit holds for every frame, 1
// when one fails or a frame is missing on either side; throws (status 2) when a comparison cannot
// be made.
int runCompare(const CompareOptions& options);
nlohmann::json metricsJson(const image::ErrorMetrics& metrics);

struct SweepOptions {
  SceneChoice source;
  std::string reference;  // linear EXR of the same scene, frame and camera (e.g. render --method pt)
  // Comma-separated lists; --bounces takes counts and auto (until converged, at each --bounce-tol).
  std::string methods = "iv", bins = "16", eps = "0.02", bounces = "auto", bounceTolerances = "0.001", kappa = "1",
              receiverTolerances = "0.2";
  std::string dirs = "4";  // ar's direction resolutions
  uint32_t tessellation = SolverOptions{}.tessellation;
  std::string environment, camera, animation;
  DeviceChoice device;
  int frame = 0;
  double fps = 24.0;
  int repeats = 3, warmup = 1;
  uint32_t supersample = 1;       // N×N samples per pixel
  std::string metric = "relMSE";  // what the Pareto front and the plot use: relMSE or FLIP
  std::string out = "sweep";
};
// Measures each setting of the grid; writes OUT/sweep.csv, sweep.json and sweep.png.
int runSweep(const SweepOptions& options);

}  // namespace ivgi::cli

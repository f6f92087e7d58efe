#include "engine/cli/app.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "engine/cli/commands.h"
#include "engine/core/notes.h"

namespace ivgi::cli {

namespace {

void addSceneArgument(CLI::App* cmd, SceneChoice& choice) {
  cmd->add_option("scene", choice.scene,
                  "glTF file (.gltf/.glb) or built-in scene (cornell, furnace); default: the animated Cornell box");
  cmd->add_option("--cells", choice.cells, "tessellation of a built-in scene: cells along the Cornell box's side")
      ->capture_default_str();
  cmd->add_flag("--glossy", choice.glossy,
                "the built-in Cornell box with a polished floor, a metal tall block and a satin short block");
  cmd->add_option("--max-triangles", choice.limits.triangles,
                  "refuse a scene that draws more triangles than this, as modelled or tessellated")
      ->capture_default_str()
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 32));
  cmd->add_option("--max-texels", choice.limits.texels,
                  "refuse a scene with an image of more pixels than this, as its header declares, before decoding it")
      ->capture_default_str()
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 32));
  cmd->add_option("--max-morph-deltas", choice.limits.morphDeltas,
                  "refuse a scene whose morph targets × their vertices exceed this, as read or as drawn")
      ->capture_default_str()
      ->check(CLI::Range(uint64_t(1), uint64_t(1) << 32));
}

void addSolverOptions(CLI::App* cmd, SolverOptions& o) {
  cmd->add_option("--method", o.method,
                  "lighting: iv (implicit-visibility radiosity), ar (antiradiance), none (emission only); render "
                  "also: pt (Embree path-traced reference)")
      ->capture_default_str();
  cmd->add_option("--bins", o.iv.bins, "N: 6×N×N direction bins per receiver (1–64)")->capture_default_str();
  cmd->add_option("--eps", o.iv.epsilon, "refine links while their form-factor estimate exceeds this")
      ->capture_default_str();
  cmd->add_option("--bounces", o.iv.bounces,
                  "exactly this many indirect bounces (0: direct light only); default: until converged (--bounce-tol)");
  cmd->add_option("--bounce-tol", o.iv.bounceTolerance,
                  "bounces stop where the light, with the estimated tail of the bounces not run added, "
                  "moves by less than this share of it")
      ->capture_default_str();
  cmd->add_option("--kappa", o.iv.kappa, "split senders wider than this many average bins")->capture_default_str();
  cmd->add_option("--rigid", o.rigid,
                  "iv: an object that moves rigidly (turns and shifts, keeping its shape) has its links to itself "
                  "made and pruned once, in its rest pose, each surfel's the first time it is a receiver (once), or "
                  "every frame for that frame's receivers (every-frame); auto: once")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "once", "every-frame"}));
  cmd->add_option("--receiver-tol", o.iv.receiverTolerance,
                  "iv solves irradiance at receivers chosen where the lighting needs them and interpolates the rest, "
                  "within this tolerance (smaller: more receivers, slower); 0: at every surfel; default: 0.4 on a "
                  "CPU device (lavapipe), 0 on a GPU");
  cmd->add_option("--unseen-tol", o.iv.unseenTolerance,
                  "iv: surfaces the image does not show, whose light reaches it only after a bounce, get receivers "
                  "at this many times --receiver-tol (1: as those it shows; not where the camera moves over a still "
                  "scene, whose solution serves every view)")
      ->capture_default_str();
  cmd->add_option(
         "--tessellate", o.tessellation,
         "iv and ar sample surfaces at least this finely: triangle edges longer than 1/N of the scene's size are "
         "split (0: the mesh as modelled)")
      ->capture_default_str();
  cmd->add_option("--dirs", o.ar.dirs, "ar: N: 6×N×N direction bins per element (1–32)")->capture_default_str();
  cmd->add_option("--iterations", o.ar.iterations,
                  "ar: exactly this many iterations; default: until one changes the irradiance by less than "
                  "--iteration-tol");
  cmd->add_option("--iteration-tol", o.ar.tolerance, "ar: iterations stop once one changes the irradiance by less")
      ->capture_default_str();
  cmd->add_option("--scheme", o.arScheme,
                  "ar: symmetric (radiance and antiradiance together) or asymmetric (a radiance step, then 3 "
                  "antiradiance steps)")
      ->capture_default_str();
  cmd->add_option("--restart-every", o.ar.restartEvery,
                  "ar: frames numbered a multiple of K start their iteration from the emission, the frames between "
                  "from the solution of the frame before (solved first where not asked for): fewer iterations, and a "
                  "frame's image depends on its number alone; 1: every frame from the emission")
      ->capture_default_str();
  cmd->add_option("--direct", o.direct,
                  "where the emitters' direct light comes from: bins (the solver's own visibility), maps (depth "
                  "maps rasterized around points on the emitters, at the surfels) or pixels (the maps looked up at "
                  "the pixels too); iv and ar [default: pixels, or bins where emitters are over a tenth of the surface "
                  "and of the light]");
  cmd->add_option("--light-samples", o.maps.samples,
                  "--direct maps or pixels: points over the emitters, each with its depth maps")
      ->capture_default_str();
  cmd->add_option("--shadow-map", o.maps.resolution,
                  "--direct maps or pixels: a depth map's side in texels (six a point)")
      ->capture_default_str();
  cmd->add_option("--env-directions", o.maps.environmentDirections,
                  "--direct maps or pixels: directions toward the environment, each with a depth map over the "
                  "scene, that light the surfels and pixels (0: the solver's bins carry the environment)")
      ->capture_default_str();
  cmd->add_option("--max-memory", o.maxMemoryMiB, "MiB the solver may allocate at most (0: what the device holds)")
      ->capture_default_str();
  cmd->add_option("--env", o.environment, "environment light: R,G,B radiance or an equirectangular .exr");
}

}  // namespace

int run(const std::vector<std::string>& args, vk::Context* device) {
  forgetNotes();
  CLI::App app{"ivgi " IVGI_VERSION
               ": global illumination of animated glTF scenes with implicit visibility, on Vulkan compute"};
  app.require_subcommand(1);
  // Usage errors in the same one-line form as every other error.
  app.failure_message(
      [](const CLI::App*, const CLI::Error& e) { return "ivgi: error: " + std::string(e.what()) + " (see --help)\n"; });
  app.set_version_flag("--version", "ivgi " IVGI_VERSION);

  RenderOptions render;
  auto* r = app.add_subcommand("render", "render a scene's frames to EXR and PNG");
  addSceneArgument(r, render.source);
  addSolverOptions(r, render.solver);
  r->add_option("--frames", render.frames, "frames A, A-B or A-B:STEP (default: the whole animation)");
  r->add_option("--fps", render.fps, "frames per second: frame f shows time f / fps")->capture_default_str();
  r->add_option("--size", render.size, "image size WIDTHxHEIGHT")->capture_default_str();
  r->add_option("--supersample", render.supersample, "N: N×N samples per pixel")->capture_default_str();
  r->add_option("--out", render.out, "output pattern with a printf frame number; extension from --format")
      ->capture_default_str();
  r->add_option("--format", render.formats, "comma-separated: exr (linear, all channels), png (tone mapped)")
      ->capture_default_str();
  r->add_option("--tonemap", render.tonemap, "PNG tone mapping: aces or clamp")->capture_default_str();
  r->add_option("--exposure", render.exposure, "PNG exposure in stops")->capture_default_str();
  r->add_option("--camera", render.camera, "camera name or index (default: the first in the scene)");
  r->add_option("--animation", render.animation, "animation name or index, or none (default: the first)");
  r->add_option("--device", render.device.name,
                "Vulkan device name substring or index (default: IVGI_DEVICE, else the best)");
  r->add_option("--json", render.json, "sidecar JSON path (default: beside the frames)");
  r->add_flag("--resume", render.resume,
              "skip frames whose files all exist; remove the temporary files of runs that ended");
  r->add_option("--shard", render.shard,
                "render shard I of N (I/N, 0 <= I < N: every N-th requested frame from the I-th), or slurm: the job "
                "array task's");
  r->add_option("--write-ahead", render.writeAhead,
                "frames whose images are written while the next frames render (default: 3 on a GPU, 0 on a CPU "
                "device and for pt)")
      ->check(CLI::Range(0u, 16u));
  auto* spp = r->add_option("--spp", render.pt.spp, "pt: samples per pixel")->capture_default_str();
  auto* seed = r->add_option("--seed", render.pt.seed, "pt: random seed (another seed, independent noise)")
                   ->capture_default_str();
  auto* threads =
      r->add_option("--threads", render.pt.threads, "pt: CPU threads (0: every core)")->capture_default_str();

  InfoOptions info;
  auto* i =
      app.add_subcommand("info", "describe a scene: meshes, triangles, surfels, animations, cameras, lights, bounds");
  addSceneArgument(i, info.source);
  addSolverOptions(i, info.solver);
  i->get_option("--method")->description("with iv: also solve frame 0 and print the memory the solver allocates");

  SceneOptions scene;
  auto* s = app.add_subcommand("scene", "write a built-in scene as glTF");
  s->add_option("name", scene.name, "cornell or furnace")->required();
  s->add_option("--out", scene.out, "output file (.gltf or .glb)")->required();
  s->add_option("--cells", scene.cells, "tessellation: cells along the Cornell box's side, or per furnace face")
      ->capture_default_str();
  s->add_option("--albedo", scene.albedo, "furnace albedo")->capture_default_str();
  s->add_option("--emission", scene.emission, "furnace emitted radiance")->capture_default_str();
  s->add_flag("--static", scene.still, "Cornell box without its animation");
  s->add_flag("--glossy", scene.glossy,
              "Cornell box with a polished floor, a metal tall block and a satin short block");
  s->add_flag("--blocks", scene.blocks,
              "furnace: the Cornell box's room closed, with its blocks (--cells as the box's)");

  BenchOptions bench;
  auto* b =
      app.add_subcommand("bench", "time each pass over frames of a scene (GPU timestamps), print medians and p90");
  addSceneArgument(b, bench.source);
  addSolverOptions(b, bench.solver);
  b->add_option("--frames", bench.frames, "measured frames")->capture_default_str();
  b->add_option("--warmup", bench.warmup, "frames rendered first and not measured")->capture_default_str();
  b->add_option("--fps", bench.fps, "frames per second of the animation")->capture_default_str();
  b->add_option("--size", bench.size, "image size WIDTHxHEIGHT")->capture_default_str();
  b->add_option("--supersample", bench.supersample, "N: N×N samples per pixel")->capture_default_str();
  b->add_option("--device", bench.device.name, "Vulkan device name substring or index");
  b->add_option("--json", bench.json, "write the figures and per-frame times as JSON");
  b->add_flag("--per-program", bench.perProgram,
              "also time every dispatch (a timestamp before and after each) and print each program's share");
  b->add_flag("--equal-error", bench.equalError,
              "compare iv with pt at equal relMSE against a converged pt reference of one frame");
  b->add_option("--reference", bench.reference,
                "equal-error: reference EXR of --frame at --size (default: render one with pt)");
  b->add_option("--reference-spp", bench.referenceSpp, "equal-error: spp of the reference it renders")
      ->capture_default_str();
  b->add_option("--max-spp", bench.maxSpp, "equal-error: pt doubles its spp up to this")->capture_default_str();
  b->add_option("--frame", bench.frame, "equal-error: the frame compared")->capture_default_str();
  b->add_option("--threads", bench.threads, "equal-error: pt threads (0: every core)")->capture_default_str();

  CompareOptions compare;
  auto* c = app.add_subcommand("compare",
                               "score an image or a sequence against a reference (relMSE, RMSE, PSNR, max error, FLIP) "
                               "and gate on limits: exit 0 pass, 1 a limit fails, 2 cannot compare");
  c->add_option("test", compare.test, "linear OpenEXR, a folder of them, or a pattern such as out/f_%04d.exr")
      ->required();
  c->add_option("reference", compare.reference, "the same kind as test, e.g. from --method pt or committed goldens")
      ->required();
  c->add_option("--max-relmse", compare.maxRelMse, "fail where relMSE exceeds this");
  c->add_option("--max-flip", compare.maxFlip, "fail where mean FLIP exceeds this");
  c->add_option("--max-pixel-error", compare.maxPixelError, "fail where any channel of a pixel differs by more");
  c->add_option("--max-temporal", compare.maxTemporal,
                "sequences: fail where the relMSE of the frame-to-frame change against the reference's exceeds this");
  c->add_option(
       "--pixel-tol", compare.pixelTolerance,
       "per-pixel rule: a pixel fails beyond this fraction (rgb: of its own value; other layers: of their range)")
      ->capture_default_str();
  c->add_option("--max-failing", compare.maxFailingPercent,
                "per-pixel rule: fail where more than this % of pixels fail")
      ->transform([](std::string v) { return v.empty() || v.back() != '%' ? v : v.substr(0, v.size() - 1); });
  c->add_option("--layers", compare.layers,
                "per-pixel rule: layers rgb, A, albedo, N, Z, emission, roughness, metallic (comma-separated) or all")
      ->capture_default_str();
  c->add_flag("--golden", compare.golden,
              "ivgi's own golden rule: every layer, 2 % a pixel (depth 1 %), at most 0.2 %");
  c->add_option("--json", compare.json, "write the figures and the verdict of every frame as JSON");
  c->add_option("--heatmap", compare.heatmap,
                "the per-pixel FLIP error as a PNG (a sequence: a folder, failing frames)");
  c->add_option("--ratio", compare.ratio, "test/reference per pixel as a PNG (a sequence: a folder, failing frames)");
  c->add_option("--mask", compare.mask, "image whose non-zero pixels (first channel) are left out of the figures");
  c->add_option("--exposure", compare.exposure, "exposure in stops before the tone map FLIP sees")
      ->capture_default_str();

  SweepOptions sweep;
  auto* w = app.add_subcommand(
      "sweep",
      "time and score a grid of settings against a reference; CSV, JSON and a plot of the speed/accuracy front");
  addSceneArgument(w, sweep.source);
  w->add_option("--reference", sweep.reference,
                "reference EXR of the same frame, camera and size (e.g. render --method pt)")
      ->required();
  w->add_option("--method", sweep.methods, "methods, comma-separated: iv, ar, none")->capture_default_str();
  w->add_option("--dirs", sweep.dirs, "ar's N values (6xNxN directions), comma-separated")->capture_default_str();
  w->add_option("--bins", sweep.bins, "N values, comma-separated")->capture_default_str();
  w->add_option("--eps", sweep.eps, "refinement thresholds, comma-separated")->capture_default_str();
  w->add_option("--bounces", sweep.bounces, "bounce counts or auto (until converged), comma-separated")
      ->capture_default_str();
  w->add_option("--bounce-tol", sweep.bounceTolerances, "the tolerances of auto bounces, comma-separated")
      ->capture_default_str();
  w->add_option("--kappa", sweep.kappa, "sender sizes in bins, comma-separated")->capture_default_str();
  w->add_option("--receiver-tol", sweep.receiverTolerances,
                "receivers' tolerances, comma-separated (0: every surfel a receiver)")
      ->capture_default_str();
  w->add_option("--tessellate", sweep.tessellation, "surfaces sampled at least this finely (see render)")
      ->capture_default_str();
  w->add_option("--env", sweep.environment, "environment light: R,G,B radiance or an equirectangular .exr");
  w->add_option("--frame", sweep.frame, "the frame the reference shows")->capture_default_str();
  w->add_option("--fps", sweep.fps, "frames per second of the animation")->capture_default_str();
  w->add_option("--camera", sweep.camera, "camera name or index (default: the first in the scene)");
  w->add_option("--animation", sweep.animation, "animation name or index, or none (default: the first)");
  w->add_option("--supersample", sweep.supersample,
                "N: N×N samples per pixel (4 integrates each pixel nearly as a path tracer does)")
      ->capture_default_str();
  w->add_option("--repeats", sweep.repeats, "timed renders per setting (the median is reported)")
      ->capture_default_str();
  w->add_option("--warmup", sweep.warmup, "untimed renders per setting first")->capture_default_str();
  w->add_option("--metric", sweep.metric, "error of the Pareto front and the plot: relMSE or FLIP")
      ->capture_default_str()
      ->check(CLI::IsMember({"relMSE", "FLIP"}));
  w->add_option("--out", sweep.out, "output folder")->capture_default_str();
  w->add_option("--device", sweep.device.name, "Vulkan device name substring or index");

  ReportOptions report;
  auto* p = app.add_subcommand("report", "gather the sidecars of a render's shards into the sequence's summary");
  p->add_option("pattern", report.pattern, "the --out pattern the render (or its shards) wrote to")->required();
  p->add_option("--json", report.json, "write the summary and every frame's record as JSON");

  auto* d = app.add_subcommand("devices", "list Vulkan devices and whether ivgi can use them");

  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status != 0 && c->parsed() ? 2 : status;  // compare: a comparison that cannot be made is 2
  }
  render.device.lent = bench.device.lent = sweep.device.lent = info.device.lent = device;
  try {
    if (r->parsed()) {
      render.pt.given = spp->count() + seed->count() + threads->count() > 0;
      return runRender(render);
    }
    if (i->parsed()) {
      info.memory = i->get_option("--method")->count() > 0;
      return runInfo(info);
    }
    if (s->parsed()) return runScene(scene);
    if (d->parsed()) return runDevices();
    if (p->parsed()) return runReport(report);
    if (c->parsed()) return runCompare(compare);
    if (w->parsed()) return runSweep(sweep);
    if (b->parsed()) return runBench(bench);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ivgi: error: %s\n", e.what());
    return c->parsed() ? 2 : 1;
  }
  return 0;
}

}  // namespace ivgi::cli

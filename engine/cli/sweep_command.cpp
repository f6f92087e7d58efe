// ivgi sweep: for a grid of settings, the median GPU time of a frame, the memory, and the error
// against a reference image; CSV, JSON and a plot of error against time with the Pareto front.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/cli/commands.h"
#include "engine/cli/json_file.h"
#include "engine/cli/machine.h"
#include "engine/cli/options.h"
#include "engine/cli/progress.h"
#include "engine/cli/report.h"
#include "engine/cli/statistics.h"
#include "engine/cli/timeline.h"
#include "engine/gi/frame_renderer.h"
#include "engine/image/atomic_file.h"
#include "engine/scene/lights.h"
#include "plot_sweep_script.h"

namespace ivgi::cli {

namespace {

template <typename T>
std::vector<T> parseList(const std::string& option, const std::string& text) {
  std::vector<T> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    std::stringstream one(item);
    T v;
    if (!(one >> v) || !one.eof()) throw SettingsError(option + " '" + text + "': expected comma-separated numbers");
    out.push_back(v);
  }
  if (out.empty()) throw SettingsError(option + ": give at least one value");
  return out;
}

std::string label(const SolverOptions& o) {
  std::ostringstream s;
  if (o.method == "ar") {
    s << "ar D" << o.ar.dirs << " e" << o.iv.epsilon;
    if (o.iv.kappa != 1.0f) s << " k" << o.iv.kappa;
    return s.str();
  }
  if (o.method != "iv") return o.method;
  s << "N" << o.iv.bins << " e" << o.iv.epsilon;
  if (o.iv.bounces)
    s << " b" << *o.iv.bounces;
  else
    s << " tol" << o.iv.bounceTolerance;
  if (o.iv.kappa != 1.0f) s << " k" << o.iv.kappa;
  s << " r" << *o.iv.receiverTolerance;
  return s.str();
}

struct Row {
  SolverOptions settings;
  std::optional<gi::DirectLightSettings> direct;  // where the setting's direct light came from
  double ms = 0, msP90 = 0;
  uint64_t bytes = 0;
  image::ErrorMetrics error;
  nlohmann::json solver;
  bool pareto = false;
};

// The interpreter that runs the plotting script: IVGI_PYTHON, else Debian's, else the PATH's.
std::string python() {
  if (const char* p = std::getenv("IVGI_PYTHON")) return p;
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

void plot(const std::string& csv, const std::string& png, const std::string& metric) {
  namespace fs = std::filesystem;
  fs::path script = fs::path(png).parent_path() / ".plot_sweep.py";
  {
    std::ofstream out(script);
    out << kPlotSweepScript;
  }
  struct RemoveScript {  // on every path out, a failed plot included
    fs::path path;
    ~RemoveScript() {
      std::error_code ec;
      fs::remove(path, ec);
    }
  } removeScript{script};
  image::writeAtomically(png, [&](const std::string& temp) {
    // The script writes the PNG under the temporary name, so a failed plot leaves no file.
    std::string command =
        python() + " '" + script.string() + "' '" + csv + "' '" + temp + ".png' --metric " + metric + " 2>&1";
    std::string output;
    if (FILE* pipe = popen(command.c_str(), "r")) {
      char buf[512];
      while (fgets(buf, sizeof buf, pipe)) output += buf;
      int status = pclose(pipe);
      if (status == 0 && fs::exists(temp + ".png")) {
        fs::rename(temp + ".png", temp);
        return;
      }
    }
    fs::remove(temp + ".png");
    std::string last = output.substr(output.find_last_of('\n', output.size() >= 2 ? output.size() - 2 : 0) + 1);
    throw std::runtime_error(
        png + ": plotting failed (needs python3-matplotlib, which ci/install-deps.sh installs): " + last);
  });
}

}  // namespace

int runSweep(const SweepOptions& o) {
  if (o.repeats < 1 || o.repeats > 1000) throw SettingsError("--repeats must be 1 to 1000");
  if (o.warmup < 0 || o.warmup > 100) throw SettingsError("--warmup must be 0 to 100");
  if (o.frame < 0) throw SettingsError("--frame must be >= 0");
  auto methods = parseList<std::string>("--method", o.methods);
  auto bins = parseList<uint32_t>("--bins", o.bins);
  auto eps = parseList<float>("--eps", o.eps);
  // Bounce counts, or auto (until converged) at each of the tolerances.
  std::vector<std::optional<uint32_t>> bounces;
  for (const std::string& b : parseList<std::string>("--bounces", o.bounces))
    bounces.push_back(b == "auto" ? std::nullopt : std::optional<uint32_t>(parseList<uint32_t>("--bounces", b)[0]));
  auto tolerances = parseList<float>("--bounce-tol", o.bounceTolerances);
  auto kappas = parseList<float>("--kappa", o.kappa);
  auto receiverTolerances = parseList<float>("--receiver-tol", o.receiverTolerances);
  std::vector<SolverOptions> grid;
  for (const auto& m : methods) {
    if (m != "iv" && m != "ar" && m != "none")
      throw SettingsError("--method '" + m + "': the sweep measures iv, ar and none (pt is the reference)");
    if (m == "none") {
      grid.push_back({.method = "none"});
      continue;
    }
    if (m == "ar") {
      for (uint32_t d : parseList<uint32_t>("--dirs", o.dirs))
        for (float e : eps)
          for (float k : kappas)
            grid.push_back(
                {.method = m, .iv = {.epsilon = e, .kappa = k}, .ar = {.dirs = d}, .tessellation = o.tessellation});
      continue;
    }
    for (uint32_t n : bins)
      for (float e : eps)
        for (const auto& b : bounces)
          for (float t : b ? std::vector<float>{gi::IvSettings{}.bounceTolerance} : tolerances)
            for (float k : kappas)
              for (float r : receiverTolerances)
                grid.push_back({.method = m,
                                .iv = {.bins = n,
                                       .epsilon = e,
                                       .bounces = b,
                                       .bounceTolerance = t,
                                       .kappa = k,
                                       .receiverTolerance = r},
                                .environment = o.environment,
                                .tessellation = o.tessellation});
  }

  const image::RgbImage reference = image::readLinearRgb(o.reference);
  scene::Scene s = loadScene(o.source);
  scene::Geometry g = renderableGeometry(s, {.tessellation = o.tessellation}, o.source.limits);
  sayWarnings(s);
  const std::string environment = withSceneLight({.environment = o.environment}, s, g).environment;
  for (SolverOptions& setting : grid) setting.environment = environment;
  const Timeline tl = timeline(s, o.animation, o.fps);
  if (o.frame > tl.lastFrame)
    throw SettingsError("--frame " + std::to_string(o.frame) + ": the animation ends at frame " +
                        std::to_string(tl.lastFrame));
  // Its files are written once every setting has run: their folder is checked before the first.
  image::prepareToWrite((std::filesystem::path(o.out) / "sweep.csv").string());
  gi::ImageSettings image{reference.width, reference.height, o.supersample};
  const FrameCamera camera(s, g, tl, o.fps, o.camera, {o.frame}, float(image.width) / float(image.height));
  const auto pose = scene::evaluatePose(s, tl.animation, float(tl.time(o.frame, o.fps)));
  const auto inputs = g.frameInputs(s, pose);
  const auto lights = scene::worldLights(s, pose);

  const std::shared_ptr<vk::Context> device = openDevice(o.device);
  vk::Context& ctx = *device;
  // Every timed render solves the frame as a later frame of the animation does: refit, links and
  // pruning of what moves, bounces (what cannot move is linked by the warm-up render).
  std::vector<Row> rows;
  // The hierarchy depends on the scene alone: built once, shared by every setting.
  const gi::Hierarchy hierarchy = gi::restPoseHierarchy(s, g);
  Progress progress("sweep", grid.size(), "setting");
  for (const auto& settings : grid) {
    const auto direct = directLightSettings(settings, s, g);
    gi::FrameRenderer renderer(ctx, g, image, makeSolver(settings, ctx, s, g, tl.animation, &hierarchy), direct);
    std::vector<double> ms;
    gi::FrameResult last;
    for (int i = 0; i < o.warmup + o.repeats; ++i) {
      last = renderer.render(inputs, camera.at(pose), lights, true);
      double total = 0;
      for (const auto& p : last.passTimes) total += p.ms;
      if (i >= o.warmup) ms.push_back(total);
    }
    image::sanitize(last.channels);
    Row row{settings,
            direct,
            percentile(ms, 0.5),
            percentile(ms, 0.9),
            renderer.bytesAllocated(),
            {},
            solverJson(renderer.solver()),
            false};
    row.error = image::measureError(image::radianceOf(last.channels), reference);
    rows.push_back(row);
    progress.advance();
  }
  progress.finish();

  auto errorOf = [&](const Row& r) { return o.metric == "FLIP" ? r.error.flip : r.error.relMse; };
  for (auto& r : rows) {
    r.pareto = true;
    for (const auto& q : rows)
      if (q.ms <= r.ms && errorOf(q) <= errorOf(r) && (q.ms < r.ms || errorOf(q) < errorOf(r))) r.pareto = false;
  }

  namespace fs = std::filesystem;
  const std::string csvPath = (fs::path(o.out) / "sweep.csv").string(),
                    jsonPath = (fs::path(o.out) / "sweep.json").string(),
                    pngPath = (fs::path(o.out) / "sweep.png").string();
  std::ostringstream csv;
  csv << "scene,method,bins,eps,bounces,bounceTol,bouncesRun,kappa,receiverTol,receivers,dirs,iterationsRun,ms,msP90,"
         "bytes,relMSE,RMSE,PSNR,maxError,FLIP,pareto,label\n";
  nlohmann::json rowsJson = nlohmann::json::array();
  std::printf("%-22s %10s %10s %12s %10s %8s %s\n", "setting", "median ms", "MiB", "relMSE", "FLIP", "PSNR dB",
              "Pareto");
  for (const auto& r : rows) {
    const auto& st = r.settings;
    const auto run = r.solver.is_object() ? r.solver.value("bounces", 0u) : 0u;
    const auto receivers = r.solver.is_object() ? r.solver.value("receivers", 0u) : 0u;
    const auto iterations = r.solver.is_object() ? r.solver.value("iterations", 0u) : 0u;
    const bool ar = st.method == "ar";
    csv << '"' << s.source << "\"," << st.method << ',' << st.iv.bins << ',' << st.iv.epsilon << ','
        << bouncesText(st.iv) << ',' << st.iv.bounceTolerance << ',' << run << ',' << st.iv.kappa << ','
        << *st.iv.receiverTolerance << ',' << receivers << ',' << (ar ? st.ar.dirs : 0u) << ',' << iterations << ','
        << r.ms << ',' << r.msP90 << ',' << r.bytes << ',' << r.error.relMse << ',' << r.error.rmse << ','
        << r.error.psnr << ',' << r.error.maxError << ',' << r.error.flip << ',' << (r.pareto ? 1 : 0) << ",\""
        << label(st) << "\"\n";
    nlohmann::json j = settingsJson(st.method, st.iv, st.tessellation, arSettings(st), r.direct);
    j.update({{"medianMs", r.ms},
              {"p90Ms", r.msP90},
              {"bytes", r.bytes},
              {"error", metricsJson(r.error)},
              {"solver", r.solver},
              {"pareto", r.pareto},
              {"label", label(st)}});
    rowsJson.push_back(j);
    std::printf("%-22s %10.2f %10.1f %12.5g %10.4f %8.2f %s\n", label(st).c_str(), r.ms, double(r.bytes) / (1 << 20),
                r.error.relMse, r.error.flip, r.error.psnr, r.pareto ? "*" : "");
  }
  image::writeAtomically(csvPath, [&](const std::string& temp) {
    std::ofstream out(temp);
    out << csv.str();
    if (!out.flush()) throw std::runtime_error(csvPath + ": cannot write");
  });
  writeJson(jsonPath, {{"scene", s.source},
                       {"reference", o.reference},
                       {"frame", o.frame},
                       {"width", image.width},
                       {"height", image.height},
                       {"supersample", image.samples},
                       {"repeats", o.repeats},
                       {"warmup", o.warmup},
                       {"device", deviceJson(ctx)},
                       {"paretoMetric", o.metric},
                       {"settings", rowsJson}});
  plot(csvPath, pngPath, o.metric);
  std::printf("\ndevice: %s\nwrote %s, %s, %s\n", deviceLine(ctx).c_str(), csvPath.c_str(), jsonPath.c_str(),
              pngPath.c_str());
  return ctx.validationErrors() ? 3 : 0;
}

}  // namespace ivgi::cli

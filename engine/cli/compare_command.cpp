// ivgi compare: error figures of an image or a sequence against a reference, and a gate on them
// for CI (exit status 0: every limit holds, 1: a limit fails or a frame is missing, 2: the
// comparison cannot be made).
#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/cli/commands.h"
#include "engine/cli/frame_pairs.h"
#include "engine/cli/json_file.h"
#include "engine/cli/options.h"
#include "engine/image/atomic_file.h"
#include "engine/image/compare.h"
#include "engine/image/frame_image.h"
#include "engine/image/image_file.h"
#include "engine/image/metrics.h"
#include "engine/image/temporal.h"

namespace ivgi::cli {

namespace {

namespace fs = std::filesystem;

// One flag per pixel: non-zero where the mask image's first channel is non-zero.
std::vector<uint8_t> readMask(const std::string& path, const image::RgbImage& like) {
  const OIIO::ImageBuf buf = image::readFloatImage(path, "the mask");
  if (uint32_t(buf.spec().width) != like.width || uint32_t(buf.spec().height) != like.height)
    throw std::runtime_error(path + ": the mask is " + std::to_string(buf.spec().width) + "x" +
                             std::to_string(buf.spec().height) + ", the images " + std::to_string(like.width) + "x" +
                             std::to_string(like.height));
  std::vector<float> first(like.pixels.size());
  buf.get_pixels(OIIO::ROI(0, buf.spec().width, 0, buf.spec().height, 0, 1, 0, 1), OIIO::TypeDesc::FLOAT, first.data());
  std::vector<uint8_t> ignore(first.size());
  for (size_t i = 0; i < first.size(); ++i) ignore[i] = first[i] != 0.0f;
  return ignore;
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// "FIGURE VALUE above OPTION LIMIT (by P %)".
std::string above(const std::string& figure, double value, const std::string& option, double limit) {
  std::string by = limit > 0 ? " (by " + number(std::round(1000.0 * (value - limit) / limit) / 10.0) + " %)" : "";
  return figure + " " + number(value) + " above " + option + " " + number(limit) + by;
}

// The per-pixel rule the options ask for, if any.
std::vector<image::LayerTolerance> pixelRule(const CompareOptions& o) {
  if (o.golden) return image::goldenTolerances();
  if (!o.maxFailingPercent) return {};
  std::vector<std::string> layers;
  if (o.layers == "all")
    return image::pixelRule(image::layerNames(), o.pixelTolerance, float(*o.maxFailingPercent / 100));
  std::stringstream list(o.layers);
  for (std::string layer; std::getline(list, layer, ',');) layers.push_back(layer);
  return image::pixelRule(layers, o.pixelTolerance, float(*o.maxFailingPercent / 100));
}

void check(const CompareOptions& o) {
  image::validate(image::DisplaySettings{image::ToneMap::Aces, o.exposure});
  for (const auto& [option, value] : {std::pair{"--max-relmse", o.maxRelMse},
                                      {"--max-flip", o.maxFlip},
                                      {"--max-pixel-error", o.maxPixelError},
                                      {"--max-temporal", o.maxTemporal}})
    if (value && !(*value >= 0.0 && std::isfinite(*value)))
      throw SettingsError(std::string(option) + " must be finite and >= 0");
  if (o.maxFailingPercent && !(*o.maxFailingPercent >= 0.0 && *o.maxFailingPercent <= 100.0))
    throw SettingsError("--max-failing must lie in [0, 100] %");
  if (!(o.pixelTolerance >= 0.0f && std::isfinite(o.pixelTolerance)))
    throw SettingsError("--pixel-tol must be finite and >= 0");
  if (o.golden && o.maxFailingPercent)
    throw SettingsError("--golden sets the per-pixel rule itself; leave out --max-failing");
  if (o.layers != "all") {
    std::stringstream list(o.layers);
    for (std::string layer; std::getline(list, layer, ',');)
      if (std::find(image::layerNames().begin(), image::layerNames().end(), layer) == image::layerNames().end())
        throw SettingsError("--layers '" + o.layers +
                            "': layers are rgb, A, albedo, N, Z, emission, roughness, metallic, or all");
  }
}

struct FrameOutcome {
  enum class Status { Pass, Fail, Missing } status = Status::Pass;
  std::vector<std::string> failures;
  nlohmann::json json;
};

// Compares one pair; writes the FLIP heatmap and the ratio image where their paths are given (with
// `onlyWhenFailing`, for a failing frame only).
FrameOutcome comparePair(const FramePair& pair, const CompareOptions& o, const std::string& heatmap,
                         const std::string& ratio, bool onlyWhenFailing) {
  FrameOutcome out;
  out.json = {{"name", pair.name}, {"test", pair.test}, {"reference", pair.reference}};
  if (pair.test.empty() || pair.reference.empty()) {
    out.status = FrameOutcome::Status::Missing;
    out.failures.push_back("missing from " + (pair.test.empty() ? o.test : o.reference));
  } else {
    const image::RgbImage test = image::readLinearRgb(pair.test), ref = image::readLinearRgb(pair.reference);
    if (test.width != ref.width || test.height != ref.height)
      throw std::runtime_error(pair.test + ": " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                               ", but the reference " + pair.reference + " is " + std::to_string(ref.width) + "x" +
                               std::to_string(ref.height));
    const std::vector<uint8_t> ignore = o.mask.empty() ? std::vector<uint8_t>{} : readMask(o.mask, ref);
    std::vector<float> flip;
    const image::ErrorMetrics m = image::measureError(test, ref, ignore, {image::ToneMap::Aces, o.exposure}, &flip);
    out.json["metrics"] = metricsJson(m);
    if (o.maxRelMse && m.relMse > *o.maxRelMse)
      out.failures.push_back(above("relMSE", m.relMse, "--max-relmse", *o.maxRelMse));
    if (o.maxFlip && m.flip > *o.maxFlip) out.failures.push_back(above("FLIP", m.flip, "--max-flip", *o.maxFlip));
    if (o.maxPixelError && m.maxError > *o.maxPixelError)
      out.failures.push_back(above("largest error", m.maxError, "--max-pixel-error", *o.maxPixelError));
    nlohmann::json layers = nlohmann::json::array();
    for (const image::LayerDifference& d : image::compareLayers(pair.test, pair.reference, pixelRule(o))) {
      layers.push_back({{"layer", d.layer},
                        {"threshold", d.threshold},
                        {"maxError", d.maxError},
                        {"failingPercent", 100 * d.failingFraction},
                        {"passed", d.passed}});
      if (!d.passed) {
        const double failing = std::round(1e4 * d.failingFraction) / 100, allowed = 100.0 * d.allowedFraction;
        out.failures.push_back(d.layer + ": " + number(failing) + " % of pixels beyond " +
                               (o.golden ? "the golden rule" : "--pixel-tol " + number(o.pixelTolerance)) + ", above " +
                               (o.golden ? "its" : "--max-failing") + " " + number(allowed) + " % (by " +
                               number(std::round(100 * (failing - allowed)) / 100) + " points)");
      }
    }
    if (!layers.empty()) out.json["layers"] = layers;
    if (!out.failures.empty()) out.status = FrameOutcome::Status::Fail;
    if (!onlyWhenFailing || out.status == FrameOutcome::Status::Fail) {
      for (const std::string& file : {heatmap, ratio})
        if (!file.empty() && fs::path(file).has_parent_path()) fs::create_directories(fs::path(file).parent_path());
      if (!heatmap.empty()) {
        image::writeHeatmap(heatmap, flip, ref.width, ref.height);
        out.json["heatmap"] = heatmap;
      }
      if (!ratio.empty()) {
        image::writeRatioMap(ratio, test, ref);
        out.json["ratio"] = ratio;
      }
    }
  }
  const char* status[] = {"pass", "fail", "missing"};
  out.json["status"] = status[int(out.status)];
  out.json["failures"] = out.failures;
  return out;
}

// The sequences' flicker: over each pair of consecutive frames both sides hold, the test's change
// against the reference's, where the reference's surfaces stay put.
image::TemporalError temporalError(const std::vector<FramePair>& pairs) {
  image::TemporalError sum;
  for (size_t k = 1; k < pairs.size(); ++k) {
    const FramePair &a = pairs[k - 1], &b = pairs[k];
    if (a.test.empty() || a.reference.empty() || b.test.empty() || b.reference.empty()) continue;
    sum += image::temporalError(image::readLinearRgb(a.test), image::readLinearRgb(b.test),
                                image::readLinearRgb(a.reference), image::readLinearRgb(b.reference),
                                image::surfacesMoved(a.reference, b.reference));
  }
  return sum;
}

void printMetrics(const nlohmann::json& frame) {
  const auto& m = frame["metrics"];
  std::printf("relMSE  %.6g\nRMSE    %.6g\nPSNR    %.2f dB\nmax     %.6g\nFLIP    %.6g\npixels  %zu\n",
              m["relMSE"].get<double>(), m["RMSE"].get<double>(),
              m["PSNR"].is_null() ? INFINITY : m["PSNR"].get<double>(), m["maxError"].get<double>(),
              m["FLIP"].get<double>(), m["pixels"].get<size_t>());
  if (frame.contains("layers"))
    for (const auto& l : frame["layers"])
      std::printf("layer %-9s %.4g %% of pixels beyond %.4g (max error %.4g)\n", l["layer"].get<std::string>().c_str(),
                  l["failingPercent"].get<double>(), l["threshold"].get<double>(), l["maxError"].get<double>());
}

}  // namespace

nlohmann::json metricsJson(const image::ErrorMetrics& m) {
  return {{"relMSE", m.relMse},
          {"RMSE", m.rmse},
          {"PSNR", std::isfinite(m.psnr) ? nlohmann::json(m.psnr) : nlohmann::json(nullptr)},
          {"maxError", m.maxError},
          {"FLIP", m.flip},
          {"pixels", m.pixels}};
}

// A path tracer's pixel averages its paths over the pixel; an iv or ar pixel of one sample is the
// value at its centre, so along every edge the two differ by aliasing that no solver setting
// changes. Said once, from the first pair whose headers tell.
void noteSampling(const std::vector<FramePair>& pairs) {
  for (const FramePair& pair : pairs) {
    if (pair.test.empty() || pair.reference.empty()) continue;
    const image::Provenance test = image::readProvenance(pair.test), ref = image::readProvenance(pair.reference);
    if (test.method.empty() || ref.method.empty()) return;
    if (test.method != "pt" && test.samplesPerPixel == 1 && ref.method == "pt")
      std::fprintf(stderr,
                   "ivgi: note: the test takes one sample a pixel and the pt reference averages each pixel: "
                   "edges alias, which no solver setting changes; render the test with --supersample 4 to "
                   "measure the lighting alone\n");
    return;
  }
}

int runCompare(const CompareOptions& o) {
  check(o);
  const std::vector<FramePair> pairs = pairFrames(o.test, o.reference);
  if (!o.json.empty()) image::prepareToWrite(o.json);  // written once every frame is compared
  noteSampling(pairs);
  const bool sequence = !(fs::is_regular_file(o.test) && fs::is_regular_file(o.reference));
  // A sequence's images are of its failing frames only, in folders: --heatmap/--ratio, else beside the report.
  std::string heatmaps = o.heatmap, ratios = o.ratio;
  if (sequence && !o.json.empty()) {
    const std::string stem = (fs::path(o.json).parent_path() / fs::path(o.json).stem()).string();
    if (heatmaps.empty()) heatmaps = stem + "-heatmaps";
    if (ratios.empty()) ratios = stem + "-ratios";
  }
  nlohmann::json frames = nlohmann::json::array();
  int passed = 0, failed = 0, missing = 0;
  for (const FramePair& pair : pairs) {
    auto image = [&](const std::string& where) {
      return where.empty() || !sequence ? where
                                        : (fs::path(where) / (fs::path(pair.name).stem().string() + ".png")).string();
    };
    FrameOutcome f = comparePair(pair, o, image(heatmaps), image(ratios), sequence);
    passed += f.status == FrameOutcome::Status::Pass;
    failed += f.status == FrameOutcome::Status::Fail;
    missing += f.status == FrameOutcome::Status::Missing;
    if (!sequence) printMetrics(f.json);
    for (const std::string& failure : f.failures)
      std::printf("%s%s%s\n", sequence ? pair.name.c_str() : "", sequence ? ": FAIL " : "FAIL ", failure.c_str());
    frames.push_back(std::move(f.json));
  }
  nlohmann::json summary = {{"frames", pairs.size()}, {"pass", passed}, {"fail", failed}, {"missing", missing}};
  bool temporalFails = false;
  if (sequence) {
    std::printf("compare: %zu frames: %d pass, %d fail, %d missing\n", pairs.size(), passed, failed, missing);
    const image::TemporalError t = temporalError(pairs);
    if (t.pixels > 0) {
      const double share = double(t.count) / 3.0 / double(t.pixels);
      std::printf(
          "temporal: relMSE of the frame-to-frame change %.6g (%.1f %% of the pixels, where the reference's "
          "surfaces stay put)\n",
          t.relMse(), 100.0 * share);
      summary["temporal"] = {{"relMSE", t.relMse()}, {"share", share}};
      if (o.maxTemporal && t.relMse() > *o.maxTemporal) {
        temporalFails = true;
        std::printf("FAIL %s\n", above("temporal relMSE", t.relMse(), "--max-temporal", *o.maxTemporal).c_str());
      }
    }
  }
  const int status = failed + missing > 0 || temporalFails ? 1 : 0;
  if (!o.json.empty())
    writeJson(
        o.json,
        {{"test", o.test}, {"reference", o.reference}, {"summary", summary}, {"status", status}, {"frames", frames}});
  return status;
}

}  // namespace ivgi::cli

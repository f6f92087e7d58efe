#include <OpenImageIO/imagebuf.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "engine/cli/commands.h"
#include "engine/cli/json_file.h"
#include "engine/cli/options.h"
#include "engine/image/metrics.h"

namespace ivgi::cli {

namespace {

// One flag per pixel: non-zero where the mask image's first channel is non-zero.
std::vector<uint8_t> readMask(const std::string& path, const image::RgbImage& like) {
  OIIO::ImageBuf buf(path);
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    throw std::runtime_error(path + ": cannot read the mask: " + buf.geterror());
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

}  // namespace

nlohmann::json metricsJson(const image::ErrorMetrics& m) {
  return {{"relMSE", m.relMse},
          {"RMSE", m.rmse},
          {"PSNR", std::isfinite(m.psnr) ? nlohmann::json(m.psnr) : nlohmann::json(nullptr)},
          {"maxError", m.maxError},
          {"FLIP", m.flip},
          {"pixels", m.pixels}};
}

int runCompare(const CompareOptions& o) {
  const image::DisplaySettings display{image::ToneMap::Aces, o.exposure};
  image::validate(display);
  image::RgbImage test = image::readLinearRgb(o.test), ref = image::readLinearRgb(o.reference);
  if (test.width != ref.width || test.height != ref.height)
    throw std::runtime_error(o.test + ": " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                             ", but the reference " + o.reference + " is " + std::to_string(ref.width) + "x" +
                             std::to_string(ref.height));
  std::vector<uint8_t> ignore = o.mask.empty() ? std::vector<uint8_t>{} : readMask(o.mask, ref);
  std::vector<float> flip;
  image::ErrorMetrics m = image::measureError(test, ref, ignore, display, &flip);
  std::printf("relMSE  %.6g\nRMSE    %.6g\nPSNR    %.2f dB\nmax     %.6g\nFLIP    %.6g\npixels  %zu (%zu ignored)\n",
              m.relMse, m.rmse, m.psnr, m.maxError, m.flip, m.pixels, ref.pixels.size() - m.pixels);
  if (!o.heatmap.empty()) image::writeHeatmap(o.heatmap, flip, ref.width, ref.height);
  if (!o.json.empty()) {
    nlohmann::json j = metricsJson(m);
    j.update({{"test", o.test},
              {"reference", o.reference},
              {"mask", o.mask},
              {"exposure", o.exposure},
              {"tonemap", "aces"}});
    writeJson(o.json, j);
  }
  return 0;
}

}  // namespace ivgi::cli

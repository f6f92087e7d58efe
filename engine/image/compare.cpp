#include "engine/image/compare.h"

#include "engine/image/image_file.h"

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ivgi::image {

namespace OIIO = OIIO_NAMESPACE;

namespace {

std::vector<int> layerChannels(const OIIO::ImageSpec& spec, const std::string& layer, const std::string& file) {
  std::vector<std::string> names;
  if (layer.empty())
    names = {"R", "G", "B"};
  else if (layer == "A" || layer == "Z" || layer == "roughness" || layer == "metallic")
    names = {layer};
  else if (layer == "N")
    names = {"N.X", "N.Y", "N.Z"};
  else
    names = {layer + ".R", layer + ".G", layer + ".B"};
  std::vector<int> out;
  for (const auto& n : names) {
    int c = spec.channelindex(n);
    if (c < 0) throw std::runtime_error(file + ": no channel " + n);
    out.push_back(c);
  }
  return out;
}

}  // namespace

std::vector<LayerDifference> compareLayers(const std::string& testFile, const std::string& refFile,
                                           const std::vector<LayerTolerance>& tolerances) {
  OIIO::ImageBuf test = readFloatImage(testFile), ref = readFloatImage(refFile);
  const auto &ts = test.spec(), &rs = ref.spec();
  if (ts.width != rs.width || ts.height != rs.height)
    throw std::runtime_error(testFile + ": " + std::to_string(ts.width) + "x" + std::to_string(ts.height) +
                             " differs from the reference's " + std::to_string(rs.width) + "x" +
                             std::to_string(rs.height));
  const float* tp = static_cast<const float*>(test.localpixels());
  const float* rp = static_cast<const float*>(ref.localpixels());
  const size_t pixels = size_t(ts.width) * ts.height;
  std::vector<LayerDifference> out;
  for (const auto& tol : tolerances) {
    auto tc = layerChannels(ts, tol.layer, testFile), rc = layerChannels(rs, tol.layer, refFile);
    std::vector<float> magnitude(pixels, 0.0f);  // per reference pixel: its largest |value| over the layer's channels
    for (size_t p = 0; p < pixels; ++p)
      for (int c : rc) magnitude[p] = std::max(magnitude[p], std::abs(rp[p * rs.nchannels + c]));
    float largest = pixels ? *std::max_element(magnitude.begin(), magnitude.end()) : 0.0f;
    // Layers whose values lie in [0, 1] (or ±1): their tolerance is of that range however dark the image.
    bool colour = tol.layer != "Z";
    LayerDifference d;
    d.layer = tol.layer.empty() ? "RGB" : tol.layer;
    if (tol.perPixel && pixels > 0) {
      std::vector<float> sorted = magnitude;
      auto at = sorted.begin() + std::ptrdiff_t(std::min(pixels - 1, pixels * 99 / 100));
      std::nth_element(sorted.begin(), at, sorted.end());
      d.threshold = tol.relativeThreshold * std::max(0.05f * *at, 1e-30f);
    } else {
      d.threshold = tol.relativeThreshold * (colour ? std::max(largest, 1.0f) : std::max(largest, 1e-30f));
    }
    size_t failing = 0;
    for (size_t p = 0; p < pixels; ++p) {
      float worst = 0;
      for (size_t k = 0; k < tc.size(); ++k) {
        float a = tp[p * ts.nchannels + tc[k]], b = rp[p * rs.nchannels + rc[k]];
        if (!std::isfinite(a) || !std::isfinite(b))
          throw std::runtime_error((std::isfinite(a) ? refFile : testFile) + ": layer " + d.layer + " holds a NaN or " +
                                   "infinite value at pixel (" + std::to_string(p % ts.width) + ", " +
                                   std::to_string(p / ts.width) + ")");
        worst = std::max(worst, std::abs(a - b));
      }
      d.maxError = std::max(d.maxError, worst);
      if (worst > d.threshold + (tol.perPixel ? tol.relativeThreshold * magnitude[p] : 0.0f)) ++failing;
    }
    d.failingFraction = double(failing) / double(pixels);
    d.allowedFraction = tol.maxFailingFraction;
    d.passed = d.failingFraction <= tol.maxFailingFraction;
    out.push_back(d);
  }
  return out;
}

const std::vector<std::string>& layerNames() {
  static const std::vector<std::string> names = {"rgb", "A", "albedo", "N", "Z", "emission", "roughness", "metallic"};
  return names;
}

std::vector<LayerTolerance> pixelRule(const std::vector<std::string>& layers, float tolerance,
                                      float maxFailingFraction) {
  std::vector<LayerTolerance> out;
  for (const std::string& layer : layers)
    out.push_back({layer == "rgb" ? "" : layer, tolerance, maxFailingFraction, layer == "rgb"});
  return out;
}

std::vector<LayerTolerance> goldenTolerances() {
  // 2 % per pixel of the layer's range (about 5 of 255 display levels for albedo and normals) or, for
  // the radiance, of the pixel's own value; at most 0.2 % of the pixels beyond it: a moved object, a
  // shifted view or a 5 % change of a layer fails, while a handful of silhouette pixels may flip
  // between CPUs.
  return {{"", 0.02f, 0.002f, true},    {"A", 0.02f, 0.002f},       {"albedo", 0.02f, 0.002f},
          {"N", 0.02f, 0.002f},         {"Z", 0.01f, 0.002f},       {"emission", 0.02f, 0.002f},
          {"roughness", 0.02f, 0.002f}, {"metallic", 0.02f, 0.002f}};
}

}  // namespace ivgi::image

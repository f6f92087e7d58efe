#include "engine/image/metrics.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/image/colour.h"
#include "engine/image/image_file.h"

namespace ivgi::image {

namespace {

OIIO::ImageBuf toBuffer(const RgbImage& image) {
  OIIO::ImageBuf buf(OIIO::ImageSpec(int(image.width), int(image.height), 3, OIIO::TypeDesc::FLOAT));
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, image.pixels.data());
  return buf;
}

}  // namespace

RgbImage readLinearRgb(const std::string& path) {
  OIIO::TypeDesc format;
  const OIIO::ImageBuf buf = readFloatImage(path, "", &format);
  if (format != OIIO::TypeDesc::FLOAT && format != OIIO::TypeDesc::HALF)
    throw std::runtime_error(path +
                             ": not a floating-point image: compare reads linear OpenEXR radiance as ivgi writes it");
  const auto& names = buf.spec().channelnames;
  int rgb[3] = {-1, -1, -1};
  for (int c = 0; c < int(names.size()); ++c)
    for (int k = 0; k < 3; ++k)
      if (names[c] == std::string(1, "RGB"[k])) rgb[k] = c;
  if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) throw std::runtime_error(path + ": no R, G, B channels");
  RgbImage out{uint32_t(buf.spec().width), uint32_t(buf.spec().height), {}};
  out.pixels.resize(size_t(out.width) * out.height);
  std::vector<float> all(out.pixels.size() * buf.spec().nchannels);
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    const float* p = &all[i * buf.spec().nchannels];
    out.pixels[i] = {p[rgb[0]], p[rgb[1]], p[rgb[2]]};
    if (!std::isfinite(p[rgb[0]]) || !std::isfinite(p[rgb[1]]) || !std::isfinite(p[rgb[2]]))
      throw std::runtime_error(path + ": pixel (" + std::to_string(i % out.width) + ", " +
                               std::to_string(i / out.width) + ") is NaN or infinite");
  }
  return out;
}

RgbImage radianceOf(const FrameChannels& frame) {
  RgbImage out{frame.width, frame.height, {}};
  out.pixels.reserve(frame.radiance.size());
  for (const auto& r : frame.radiance) out.pixels.emplace_back(r);
  return out;
}

RgbImage displayed(const RgbImage& linear, const DisplaySettings& d) {
  RgbImage out = linear;
  const float scale = std::exp2(d.exposure);
  for (auto& p : out.pixels)
    for (int c = 0; c < 3; ++c) p[c] = linearToSrgb(toneMap(p[c] * scale, d.tonemap));
  return out;
}

ErrorMetrics measureError(const RgbImage& test, const RgbImage& ref, const std::vector<uint8_t>& ignore,
                          const DisplaySettings& display, std::vector<float>* flipMap) {
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument("the images differ in size: " + std::to_string(test.width) + "x" +
                                std::to_string(test.height) + " and " + std::to_string(ref.width) + "x" +
                                std::to_string(ref.height));
  if (!ignore.empty() && ignore.size() != ref.pixels.size())
    throw std::invalid_argument("the mask differs in size from the images");
  auto kept = [&](size_t i) { return ignore.empty() || !ignore[i]; };
  ErrorMetrics m;
  double rel = 0;
  RgbImage a = test, b = ref;  // ignored pixels zeroed in both, so that they add nothing to OIIO's sums
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    if (!kept(i)) {
      a.pixels[i] = b.pixels[i] = glm::vec3(0.0f);
      continue;
    }
    ++m.pixels;
    for (int c = 0; c < 3; ++c) {
      double d = double(test.pixels[i][c]) - ref.pixels[i][c];
      rel += d * d / (double(ref.pixels[i][c]) * ref.pixels[i][c] + 0.01);
    }
  }
  if (m.pixels == 0) throw std::invalid_argument("the mask leaves no pixel to compare");
  m.relMse = rel / (3.0 * double(m.pixels));
  // RMSE and the largest error from OpenImageIO, rescaled from all pixels to the kept ones.
  auto cmp = OIIO::ImageBufAlgo::compare(toBuffer(a), toBuffer(b), 0.0f, 0.0f);
  m.rmse = cmp.rms_error * std::sqrt(double(ref.pixels.size()) / double(m.pixels));
  m.maxError = cmp.maxerror;
  m.psnr = m.rmse > 0 ? 20.0 * std::log10(1.0 / m.rmse) : std::numeric_limits<double>::infinity();
  auto flip = flipErrorMap(displayed(test, display), displayed(ref, display));
  double sum = 0;
  for (size_t i = 0; i < flip.size(); ++i)
    if (kept(i)) sum += flip[i];
  m.flip = sum / double(m.pixels);
  if (flipMap) *flipMap = std::move(flip);
  return m;
}

void writeHeatmap(const std::string& path, const std::vector<float>& error, uint32_t width, uint32_t height) {
  // matplotlib's magma, sampled at 0, 1/8, …, 1.
  static const glm::vec3 magma[9] = {{0.001f, 0.000f, 0.014f}, {0.113f, 0.065f, 0.277f}, {0.317f, 0.072f, 0.485f},
                                     {0.513f, 0.148f, 0.508f}, {0.716f, 0.215f, 0.475f}, {0.904f, 0.320f, 0.388f},
                                     {0.987f, 0.536f, 0.382f}, {0.997f, 0.770f, 0.535f}, {0.987f, 0.991f, 0.750f}};
  std::vector<uint8_t> rgb(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    float t = std::clamp(std::isfinite(error[i]) ? error[i] : 1.0f, 0.0f, 1.0f) * 8.0f;
    int k = std::min(int(t), 7);
    glm::vec3 c = glm::mix(magma[k], magma[k + 1], t - float(k));
    for (int j = 0; j < 3; ++j) rgb[i * 3 + j] = uint8_t(std::lround(c[j] * 255.0f));
  }
  writeRgb8Png(path, width, height, rgb);
}

void writeRatioMap(const std::string& path, const RgbImage& test, const RgbImage& reference) {
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument("writeRatioMap: the images differ in size");
  const glm::vec3 darker(0.230f, 0.299f, 0.754f), same(0.865f, 0.865f, 0.865f), brighter(0.706f, 0.016f, 0.150f);
  auto luminance = [](glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
  std::vector<uint8_t> rgb(size_t(test.width) * test.height * 3, 0);
  for (size_t i = 0; i < test.pixels.size(); ++i) {
    const float t = luminance(test.pixels[i]), r = luminance(reference.pixels[i]);
    if (!(t > 0.0f) && !(r > 0.0f)) continue;  // both black: black
    // log-symmetric: a ratio of kRatioRange or more saturates, as does its inverse
    const float x =
        std::clamp(std::log(std::max(t, 1e-30f) / std::max(r, 1e-30f)) / std::log(kRatioRange), -1.0f, 1.0f);
    const glm::vec3 c = x < 0.0f ? glm::mix(same, darker, -x) : glm::mix(same, brighter, x);
    for (int j = 0; j < 3; ++j) rgb[i * 3 + j] = uint8_t(std::lround(c[j] * 255.0f));
  }
  writeRgb8Png(path, test.width, test.height, rgb);
}

}  // namespace ivgi::image

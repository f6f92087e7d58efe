#include "engine/image/frame_image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/core/errors.h"
#include "engine/image/atomic_file.h"
#include "engine/image/colour.h"

namespace ivgi::image {

namespace OIIO = OIIO_NAMESPACE;

size_t sanitize(FrameChannels& frame) {
  size_t replaced = 0;
  for (auto* channel : {&frame.radiance, &frame.albedo, &frame.normalDepth, &frame.emission, &frame.roughnessMetallic})
    for (auto& v : *channel)
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(v[c])) v[c] = 0.0f, ++replaced;
  return replaced;
}

void validate(const DisplaySettings& d) {
  if (!std::isfinite(d.exposure) || std::abs(d.exposure) > 64)
    throw SettingsError("--exposure must lie in [-64, 64] stops");
}

float toneMap(float x, ToneMap mode) {
  x = std::max(x, 0.0f);
  if (mode == ToneMap::Aces) x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);  // Narkowicz's ACES fit
  return std::clamp(x, 0.0f, 1.0f);
}

namespace {

void writeWith(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* data) {
  writeAtomically(path, [&](const std::string& temp) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": no image writer for this file type");
    if (!out->open(temp, spec) || !out->write_image(type, data) || !out->close())
      throw std::runtime_error(path + ": cannot write image: " + out->geterror());
  });
}

}  // namespace

Provenance readProvenance(const std::string& path) {
  Provenance p;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return p;
  const OIIO::ImageSpec& spec = in->spec();
  p.method = spec.get_string_attribute("ivgi:method");
  p.samplesPerPixel = uint32_t(std::max(spec.get_int_attribute("ivgi:samplesPerPixel", 0), 0));
  return p;
}

void writeExr(const std::string& path, const FrameChannels& f, const Provenance& provenance) {
  const char* names[] = {"R",   "G",   "B", "A",          "albedo.R",   "albedo.G",   "albedo.B",  "N.X",
                         "N.Y", "N.Z", "Z", "emission.R", "emission.G", "emission.B", "roughness", "metallic"};
  const int channels = 16;
  OIIO::ImageSpec spec(int(f.width), int(f.height), channels, OIIO::TypeDesc::FLOAT);
  spec.channelnames.assign(names, names + channels);
  spec.alpha_channel = 3;
  spec.z_channel = 10;
  spec.attribute("compression", "zip");
  // A fixed time stamp: the same render must give the same bytes (golden images, caching, diffs).
  spec.attribute("DateTime", "1970:01:01 00:00:00");
  spec.attribute("Software", "ivgi " IVGI_VERSION);
  if (!provenance.method.empty()) spec.attribute("ivgi:method", provenance.method);
  if (provenance.samplesPerPixel > 0) spec.attribute("ivgi:samplesPerPixel", int(provenance.samplesPerPixel));
  std::vector<float> pixels(size_t(f.width) * f.height * channels);
  for (size_t i = 0; i < size_t(f.width) * f.height; ++i) {
    float* p = &pixels[i * channels];
    const glm::vec4 &r = f.radiance[i], &a = f.albedo[i], &n = f.normalDepth[i], &e = f.emission[i];
    const glm::vec4 m = f.roughnessMetallic.empty() ? glm::vec4(0.0f) : f.roughnessMetallic[i];
    float row[] = {r.r, r.g, r.b, r.a, a.r, a.g, a.b, n.x, n.y, n.z, n.w, e.r, e.g, e.b, m.r, m.g};
    std::copy(row, row + channels, p);
  }
  writeWith(path, spec, OIIO::TypeDesc::FLOAT, pixels.data());
}

void writeRgb8Png(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb) {
  OIIO::ImageSpec spec(int(width), int(height), 3, OIIO::TypeDesc::UINT8);
  spec.attribute("Software", "ivgi " IVGI_VERSION);
  writeWith(path, spec, OIIO::TypeDesc::UINT8, rgb.data());
}

void writePng(const std::string& path, const FrameChannels& f, const DisplaySettings& d) {
  std::vector<uint8_t> pixels(size_t(f.width) * f.height * 3);
  const float scale = std::exp2(d.exposure);
  for (size_t i = 0; i < size_t(f.width) * f.height; ++i)
    for (int c = 0; c < 3; ++c) {
      float v = linearToSrgb(toneMap(f.radiance[i][c] * scale, d.tonemap));
      pixels[i * 3 + c] = uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
  writeRgb8Png(path, f.width, f.height, pixels);
}

}  // namespace ivgi::image

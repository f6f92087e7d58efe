#include "engine/image/temporal.h"

#include "engine/image/image_file.h"

#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <stdexcept>

namespace ivgi::image {

namespace {

// Coverage, depth and normal of an EXR as ivgi writes it: A, Z, N.X, N.Y, N.Z per pixel.
struct Surfaces {
  uint32_t width = 0, height = 0;
  std::vector<float> values;  // 5 a pixel
};

Surfaces readSurfaces(const std::string& path) {
  const OIIO::ImageBuf buf = readFloatImage(path);
  const auto& spec = buf.spec();
  std::vector<int> at;
  for (const char* name : {"A", "Z", "N.X", "N.Y", "N.Z"}) {
    const int c = spec.channelindex(name);
    if (c < 0) throw std::runtime_error(path + ": no " + name + " channel (the temporal measure needs ivgi's layers)");
    at.push_back(c);
  }
  Surfaces s{uint32_t(spec.width), uint32_t(spec.height), {}};
  std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
  s.values.reserve(size_t(spec.width) * spec.height * 5);
  for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i)
    for (int c : at) s.values.push_back(all[i * spec.nchannels + size_t(c)]);
  return s;
}

}  // namespace

std::vector<uint8_t> surfacesMoved(const std::string& before, const std::string& after) {
  const Surfaces a = readSurfaces(before), b = readSurfaces(after);
  if (a.width != b.width || a.height != b.height) throw std::runtime_error(after + ": not the size of " + before);
  const size_t pixels = size_t(a.width) * a.height;
  std::vector<uint8_t> moved(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) {
    const float* p = &a.values[5 * i];
    const float* q = &b.values[5 * i];
    const float normals = p[2] * q[2] + p[3] * q[3] + p[4] * q[4];
    moved[i] = p[0] != q[0] || p[1] <= 0.0f || q[1] <= 0.0f || std::abs(p[1] - q[1]) > 0.01f * std::max(p[1], q[1]) ||
               normals < 0.99f;
  }
  std::vector<uint8_t> dilated = moved;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x) {
      if (!moved[size_t(y) * a.width + x]) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = int(x) + dx, ny = int(y) + dy;
          if (nx >= 0 && ny >= 0 && nx < int(a.width) && ny < int(a.height)) dilated[size_t(ny) * a.width + nx] = 1;
        }
    }
  return dilated;
}

TemporalError temporalError(const RgbImage& test0, const RgbImage& test1, const RgbImage& ref0, const RgbImage& ref1,
                            const std::vector<uint8_t>& ignore) {
  const size_t n = ref1.pixels.size();
  if (test0.pixels.size() != n || test1.pixels.size() != n || ref0.pixels.size() != n || ignore.size() != n)
    throw std::invalid_argument("temporalError: the images differ in size");
  TemporalError e;
  e.pixels = n;
  for (size_t i = 0; i < n; ++i) {
    if (ignore[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = double(test1.pixels[i][c] - test0.pixels[i][c]) - double(ref1.pixels[i][c] - ref0.pixels[i][c]);
      const double r = ref1.pixels[i][c];
      e.sum += d * d / (r * r + 0.01);
      ++e.count;
    }
  }
  return e;
}

}  // namespace ivgi::image

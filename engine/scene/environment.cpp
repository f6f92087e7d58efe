#include "engine/scene/environment.h"

#include "engine/image/colour.h"
#include "engine/image/image_file.h"

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/core/errors.h"
#include "engine/scene/scene.h"
#include "shaders/interface.h"

namespace ivgi::scene {

namespace {

glm::vec3 parseColour(const std::string& spec) {
  std::stringstream ss(spec);
  glm::vec3 c;
  char comma1 = 0, comma2 = 0;
  if (!(ss >> c.r >> comma1 >> c.g >> comma2 >> c.b) || comma1 != ',' || comma2 != ',' || !ss.eof())
    throw SettingsError("--env '" + spec + "': expected R,G,B or an .exr file");
  if (!glm::all(glm::greaterThanEqual(c, glm::vec3(0.0f))) || !glm::all(glm::lessThan(c, glm::vec3(1e30f))))
    throw SettingsError("--env '" + spec + "': radiance must be at least 0 and below 1e30");
  return c;
}

}  // namespace

Environment Environment::parse(const std::string& spec) {
  Environment env;
  bool file = spec.size() > 4 && spec.substr(spec.size() - 4) == ".exr";
  if (!file) {
    env.constant_ = parseColour(spec);
    return env;
  }
  OIIO_NAMESPACE::ImageBuf image;
  try {
    image = image::readFloatImage(spec, "the environment");
  } catch (const std::runtime_error& e) {
    throw LoadError(e.what());
  }
  const auto& is = image.spec();
  if (is.nchannels < 3 || is.width < 1 || is.height < 1) throw LoadError(spec + ": the environment needs RGB channels");
  const float* px = static_cast<const float*>(image.localpixels());
  env.width_ = is.width, env.height_ = is.height;
  env.texels_.resize(size_t(is.width) * is.height);
  for (size_t i = 0; i < env.texels_.size(); ++i) {
    const float* p = px + i * is.nchannels;
    glm::vec3 c(p[0], p[1], p[2]);
    if (!glm::all(glm::lessThan(glm::abs(c), glm::vec3(1e30f))))
      throw LoadError(spec + ": the environment holds NaN or infinite values");
    env.texels_[i] = glm::max(c, glm::vec3(0.0f));
  }
  return env;
}

glm::vec3 Environment::radiance(glm::vec3 d) const {
  if (width_ == 0) return constant_;
  d = glm::normalize(d);
  float u = std::atan2(d.x, -d.z) / (2.0f * gpu::kPi) + 0.5f, v = std::acos(glm::clamp(d.y, -1.0f, 1.0f)) / gpu::kPi;
  int x = std::clamp(int(u * width_), 0, width_ - 1), y = std::clamp(int(v * height_), 0, height_ - 1);
  return texels_[size_t(y) * width_ + x];
}

std::vector<glm::vec4> Environment::bins(uint32_t n) const {
  std::vector<glm::vec4> out(6 * n * n);
  for (uint32_t b = 0; b < out.size(); ++b) {
    // Sub-directions on the bin's face cell, around its centre.
    glm::vec3 c = gpu::binDirection(b, n), sum(0.0f);
    uint32_t face = b / (n * n), axis = face / 2;
    float half = 1.0f / float(n);
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        glm::vec3 d = c;
        float du = ((i + 0.5f) / 4.0f - 0.5f) * 2.0f * half, dv = ((j + 0.5f) / 4.0f - 0.5f) * 2.0f * half;
        if (axis == 0)
          d.y += du, d.z += dv;
        else if (axis == 1)
          d.z += du, d.x += dv;
        else
          d.x += du, d.y += dv;
        sum += radiance(d);
      }
    out[b] = glm::vec4(sum / 16.0f, 0.0f);
  }
  return out;
}

std::vector<Environment::Direction> Environment::sampleDirections(uint32_t count) const {
  std::vector<Direction> out;
  constexpr double kGolden = 0.6180339887498949;
  using image::luminance;
  if (width_ == 0) {
    if (!(luminance(constant_) > 0) || count == 0) return out;
    // A Fibonacci sphere: heights evenly spaced, the azimuth turning by the golden angle.
    for (uint32_t i = 0; i < count; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / count, r = std::sqrt(std::max(0.0, 1.0 - z * z)),
                   phi = 2.0 * gpu::kPi * std::fmod(i * kGolden, 1.0);
      out.push_back(
          {glm::vec3(glm::dvec3(r * std::cos(phi), z, r * std::sin(phi))), constant_ * float(4.0 * gpu::kPi / count)});
    }
    return out;
  }
  // Each texel's power: luminance × its solid angle (2π/W · (cos θ0 − cos θ1) between its rows).
  std::vector<double> power(texels_.size()), solidAngle(texels_.size());
  double total = 0;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const size_t t = size_t(y) * width_ + x;
      solidAngle[t] = 2.0 * gpu::kPi / width_ *
                      (std::cos(double(y) / height_ * gpu::kPi) - std::cos(double(y + 1) / height_ * gpu::kPi));
      power[t] = luminance(texels_[t]) * solidAngle[t];
      total += power[t];
    }
  if (!(total > 0) || count == 0) return out;
  // Half the directions by power, half uniformly over the sphere: a sun that holds nearly all the
  // power would otherwise leave a surface facing away from it a handful of directions of the sky.
  constexpr double kByPower = 0.5;
  for (size_t t = 0; t < power.size(); ++t)
    power[t] = kByPower * power[t] / total + (1.0 - kByPower) * solidAngle[t] / (4.0 * gpu::kPi);
  total = 1.0;  // the mixed shares sum to one
  double before = 0;
  size_t t = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const double target = (i + 0.5) / count * total;
    while (t + 1 < power.size() && (power[t] <= 0 || before + power[t] < target)) before += power[t++];
    // Within the texel: across by where the target falls in its share, down by a golden-ratio step.
    const double across = std::clamp((target - before) / power[t], 0.0, 1.0),
                 down = std::fmod((i + 0.5) * kGolden, 1.0);
    const double u = (double(t % width_) + across) / width_, v = (double(t / width_) + down) / height_;
    const double phi = (u - 0.5) * 2.0 * gpu::kPi, theta = v * gpu::kPi;
    // radiance(): u = atan2(x, -z) / 2π + ½, v = acos(y) / π.
    const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
    // pdf per solid angle where the direction lies: spread evenly over the texel's u and v, its
    // share of the mixed power has the density (2π/W · π/H · sin θ) there.
    const double pdf = power[t] / (2.0 * gpu::kPi / width_ * gpu::kPi / height_ * std::max(std::sin(theta), 1e-9));
    out.push_back({glm::vec3(d), texels_[t] * float(1.0 / (count * pdf))});
  }
  return out;
}

}  // namespace ivgi::scene

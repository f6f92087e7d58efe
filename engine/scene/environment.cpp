#include "engine/scene/environment.h"

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
    throw SettingsError("--env '" + spec + "': radiance must be finite and >= 0");
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

}  // namespace ivgi::scene

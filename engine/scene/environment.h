#pragma once
// Environment light: radiance arriving from infinitely far away, a constant colour or an
// equirectangular EXR (+y up; u = 0.5 looks along -z). The GPU solvers read it per direction bin,
// the path tracer per direction.
#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace ivgi::scene {

class Environment {
 public:
  // "R,G,B" or a path to an .exr; throws SettingsError (--env) or LoadError naming the problem.
  static Environment parse(const std::string& spec);

  glm::vec3 radiance(glm::vec3 direction) const;  // nearest texel; any length of direction
  // Per bin of the 6·N² table: the mean radiance over 4×4 directions inside it.
  std::vector<glm::vec4> bins(uint32_t n) const;

  // `count` directions toward the sky chosen by power (a constant sky uniformly over the sphere, a
  // map half by luminance × solid angle and half uniformly), stratified: the i-th where the running sum crosses (i +
  // ½)/count, so that every k-th of them is spread over the whole sky too. Each carries radiance / (count × pdf): the
  // irradiance it stands for at normal incidence. Empty where the sky is black.
  struct Direction {
    glm::vec3 towardSky, irradiance;
  };
  std::vector<Direction> sampleDirections(uint32_t count) const;

 private:
  glm::vec3 constant_{0.0f};
  int width_ = 0, height_ = 0;  // 0: constant
  std::vector<glm::vec3> texels_;
};

}  // namespace ivgi::scene

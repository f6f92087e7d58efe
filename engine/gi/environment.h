#pragma once
// Environment light for the bins: radiance per direction bin, from a constant colour or an
// equirectangular EXR (+y up; u = 0.5 looks along -z).
#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace ivgi::gi {

// "R,G,B" or a path to an .exr; throws std::runtime_error naming the problem. Each bin holds the
// mean radiance over 4×4 directions inside it.
std::vector<glm::vec4> environmentBins(const std::string& spec, uint32_t n);

}  // namespace ivgi::gi

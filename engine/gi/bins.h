#pragma once
// Host tables of the cube-map direction bins (docs/design.md §5), computed here because GLSL's atan
// is not exact enough for solid angles.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include <optional>

#include "engine/scene/environment.h"

namespace ivgi::gi {

// Per bin of 6·n²: ∫ ω dω over the bin (so that n·∫ω dω is the bin's cosine-weighted solid angle for any
// normal n that sees the whole bin), and Ω. Computed once a process for each n (a million atan2 at 16).
const std::vector<glm::vec4>& binVectorTable(uint32_t n);

// The solid angle of an average bin of 6·n²: 4π/(6n²) (link creation's κ counts in it).
float meanBinSolidAngle(uint32_t n);

// The environment's radiance per bin, or one zero for none (a buffer is never empty).
std::vector<glm::vec4> environmentTable(const std::optional<scene::Environment>& environment, uint32_t n);

}  // namespace ivgi::gi

#pragma once
// The sRGB transfer curve: textures are decoded with it, PNGs and FLIP's display images encoded.
// And the luminance of linear RGB, by which lights are weighed.
#include <glm/glm.hpp>

#include <cmath>

namespace ivgi::image {

inline float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
inline float linearToSrgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

// Rec. 709 / sRGB primaries' luminance.
inline double luminance(glm::dvec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace ivgi::image

#pragma once
// Host tables of the cube-map direction bins (docs/design.md §5), computed here because GLSL's atan
// is not exact enough for solid angles.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include <optional>

#include "engine/scene/environment.h"
#include "engine/scene/geometry.h"

namespace ivgi::gi {

// The frame a solver's bins lie in: ar's tables are fixed in the world; each of iv's receivers bins
// in a frame of its own whose z is its normal (binFrame), so that its horizon runs along the side
// faces' middle: between two rows of bins for even n, through the middle row for odd n.
enum class BinFrame { World, Normal };
// Per bin of 6·n²: ∫ ω dω over the bin (so that n·∫ω dω is the bin's cosine-weighted solid angle for any
// normal n that sees the whole bin), and Ω. In the normal's frame, a bin the horizon cuts counts for
// its part above it alone (odd n): weighed whole, its halves' cosines cancel, and the light of the
// band above the horizon (a tenth of the hemisphere's cosine at n = 3) would be lost. Computed once a
// process for each n and frame (a million atan2 at 16).
const std::vector<glm::vec4>& binVectorTable(uint32_t n, BinFrame frame);

// The solid angle of an average bin of 6·n²: 4π/(6n²) (link creation's κ counts in it).
float meanBinSolidAngle(uint32_t n);

// The least spread (per-axis angular variance, brdf.h's widenedLobe) of the directions a method's
// bins tell apart, n a side, and the roughness whose lobe spreads that far. iv's bins keep one
// sender each: a bin spreads as a disk of its solid angle, Ω/(4π). ar's tables are written and read
// between bins (binTaps): a sender spreads as a tent a bin wide either way (w²/6, w² = Ω) and as
// the bin itself (w²/12), Ω/4 in all.
float senderBinSpread(uint32_t n);
float tableBinSpread(uint32_t n);
inline float roughnessOfSpread(float spread) { return std::sqrt(std::sqrt(spread)); }
// Says on stderr, once a command (noteOnce), where some glossy surface is smoother than `spread` resolves: its lobe's
// reflections of the indirect light are drawn at that roughness (`method`: "iv"; `option`: what
// resolves finer, "--bins 16").
void noteUnresolvedRoughness(const scene::Geometry& g, float spread, const char* method, const std::string& option);

// Per object (its surfels by `objectOfSurfel`, its instance `objectInstance`): the axes its surfaces
// follow at rest (`world`: the vertices there), as rows (binFrame's x, y, z): z the direction for
// which Σ area·(n·z)⁴ is largest among the world's axes and the normals of its largest surfels, x the
// orientation, modulo a right angle about z, that most of the normals across z (by area) and of the
// edges of its faces along z's plane (by length) take (the most weighted degree, then the mean about
// it). A receiver's bins tilt from its object's axis
// nearest its normal (common.glsl's tiltedTangent), so that the faces of a room or a part modelled
// askew to the world's axes lie along their bins as they would along the world's, neighbours on a
// curved surface bin alike, and the bins turn with the object.
std::vector<glm::mat3> objectAxes(const scene::Geometry& g, const std::vector<scene::WorldVertex>& world,
                                  const std::vector<scene::Surfel>& surfels,
                                  const std::vector<uint32_t>& objectOfSurfel,
                                  const std::vector<uint32_t>& objectInstance);

// The environment's radiance per bin, or one zero for none (a buffer is never empty).
std::vector<glm::vec4> environmentTable(const std::optional<scene::Environment>& environment, uint32_t n);

}  // namespace ivgi::gi

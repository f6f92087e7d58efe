#pragma once
// Still surfels by a concave crease (docs/design.md §2.4, *Creases*): where two surfaces meet at an
// angle, facing each other, a surfel within a few of its radii of the other surface sees it fill
// half its hemisphere from close by, and its light falls toward the crease faster than its receivers,
// a few cells away, can follow. Such a surfel of a still object takes its still senders' light from
// its own static links each bounce (shaders/iv/gather_creases.comp), its receivers' for the rest.
#include <cstdint>
#include <vector>

#include "shaders/interface.h"

namespace ivgi::gi {

// How near another surface, in the surfel's disk radii, a surfel counts as by a crease: its own
// row along the crease and the next.
inline constexpr float kCreaseReach = 2.0f;

// The surfels among `surfels` (at rest) that are `still` and lie within kCreaseReach of their radius
// of another still surfel that meets theirs at a concave crease: normals more than 45° apart, each in
// front of the other's plane. In order.
std::vector<uint32_t> creaseSurfels(const std::vector<gpu::Surfel>& surfels, const std::vector<bool>& still);

}  // namespace ivgi::gi

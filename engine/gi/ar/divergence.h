#pragma once
// When ar's iteration counts as diverging, and the words that say why (docs/design.md §2.2).
#include <cstddef>
#include <optional>
#include <span>
#include <string>

namespace ivgi::gi {

// Over a frame's iterations so far, each one's change of the irradiance and its light cancelled
// past zero (both as shares of the light), the last `fresh` of them just judged: why the
// iteration diverges, as "light cancelled past zero 18.8 times the light at iteration 2"; none
// where it does not. Undamped (damping 1), light cancelled past half the light diverges from the
// third iteration; damped, the light may settle with some cancelled past zero (a damped step is
// slower, not off), but a change still above the light after 8 iterations, or one that did not
// fall by a quarter over 16, is light the damping does not hold. At any damping, a change not
// finite, or one above the light and ten times the smallest after 8 iterations.
std::optional<std::string> divergence(std::span<const float> changes, std::span<const float> negatives, size_t fresh,
                                      float damping);

}  // namespace ivgi::gi

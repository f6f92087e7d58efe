#include "engine/cli/timeline.h"

#include <cmath>

namespace ivgi::cli {

Timeline timeline(const scene::Scene& s, const std::string& choice, double fps) {
  Timeline t;
  if (choice == "none") return t;
  if (!choice.empty()) {
    auto a = s.findAnimation(choice);
    if (!a) throw scene::LoadError(s.source + ": no animation named '" + choice + "' (" + std::to_string(s.animations.size()) + " animations; see `ivgi info`)");
    t.animation = *a;
  } else if (!s.animations.empty()) {
    t.animation = 0;
  }
  if (t.animation >= 0) {
    const auto& a = s.animations[t.animation];
    t.start = a.start;
    t.lastFrame = int(std::floor((a.end - a.start) * fps + 1e-4));
  }
  return t;
}

}  // namespace ivgi::cli

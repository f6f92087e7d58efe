#include "engine/cli/timeline.h"

#include <algorithm>
#include <cmath>

#include "engine/core/errors.h"
#include "engine/scene/animation.h"

namespace ivgi::cli {

namespace {

// "no camera named or numbered 'x' (3 cameras, numbered 0 to 2; see `ivgi info`)": the option takes either.
std::string noneSuch(const std::string& what, const std::string& choice, size_t count) {
  const std::string numbered = count ? ", numbered 0 to " + std::to_string(count - 1) : "";
  return "no " + what + " named or numbered '" + choice + "' (" + std::to_string(count) + " " + what +
         (count == 1 ? "" : "s") + numbered + "; see `ivgi info`)";
}

}  // namespace

Timeline timeline(const scene::Scene& s, const std::string& choice, double fps) {
  if (!(fps > 0.0 && fps <= 1000.0)) throw SettingsError("--fps must lie in (0, 1000]");
  Timeline t;
  if (choice == "none") return t;
  if (!choice.empty()) {
    auto a = s.findAnimation(choice);
    if (!a) throw scene::LoadError(s.source + ": " + noneSuch("animation", choice, s.animations.size()));
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

FrameCamera::FrameCamera(const scene::Scene& s, const scene::Geometry& g, const Timeline& tl, double fps,
                         const std::string& camera, const std::vector<int>& frames, float aspect)
    : scene_(s) {
  if (!camera.empty()) {
    auto c = s.findCameraNode(camera);
    if (!c) throw scene::LoadError(s.source + ": " + noneSuch("camera", camera, s.cameraNodes().size()));
    node_ = *c;
  } else if (auto cams = s.cameraNodes(); !cams.empty()) {
    node_ = cams.front();
  }
  if (node_ >= 0) return;
  scene::Bounds all;
  size_t stride = std::max<size_t>(1, frames.size() / 16);
  for (size_t i = 0; i < frames.size(); i += stride) {
    auto pose = scene::evaluatePose(s, tl.animation, float(tl.time(frames[i], fps)));
    auto b = scene::worldBounds(scene::animateOnHost(g, g.frameInputs(s, pose)));
    all.add(b.min), all.add(b.max);
  }
  framing_ = scene::framingCamera(all, aspect);
}

scene::CameraView FrameCamera::at(const scene::Pose& pose) const {
  return node_ >= 0 ? scene::cameraView(scene_, pose, node_) : framing_;
}

std::string FrameCamera::name() const { return node_ >= 0 ? scene_.nodes[node_].name : "default framing"; }

}  // namespace ivgi::cli

#pragma once
// What a lighting method gives the frame (docs/design.md §8): after the surfel pass it
// records its passes, which leave the irradiance at every surfel for the resolve pass. The frame
// renderer owns one: iv (iv/solver.h) and ar (ar/solver.h).
#include <cstdint>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/timer.h"
#include "shaders/interface.h"

namespace ivgi::gi {

class Solver {
 public:
  virtual ~Solver() = default;

  // The first frame of the chain `frame` belongs to: a solver whose solve of a frame starts from the
  // solution of the frame before it needs the frames from there to frame − 1 solved, in order, just
  // before it (a frame's image then depends on its number alone). By default every frame stands alone.
  virtual int chainStart(int frame) const { return frame; }
  // The number of the frame about to be recorded (negative: none, a frame that chains to nothing).
  virtual void beginFrame(int /*frame*/) {}
  // The frame's punctual lights in world space.
  virtual void setLights(const std::vector<gpu::PunctualLight>& lights) = 0;
  // The frame's node world matrices (scene::FrameInputs::matrices), before record().
  virtual void setObjectMatrices(const std::vector<glm::mat4>& /*matrices*/) {}
  // Takes the emitters' direct light per surfel from the frame's depth maps (gi::DirectLight) and
  // from then on solves with it; false where the solver cannot. `surfelDirect` and `surfelArrival`
  // (the light's mean direction, DirectLight::surfelArrival) stay valid and are rewritten each frame
  // before record(); given before the first frame.
  virtual bool useDirectLight(const vk::Buffer& /*surfelDirect*/, const vk::Buffer& /*surfelArrival*/,
                              bool /*withEnvironment*/) {
    return false;
  }
  // Records the solver's passes, each timed. `geometryMoved`: the surfels or the lights changed
  // since the last frame (or this is the first), so whatever depends on them must be made again.
  // Where nothing moved, the last frame's solution is what solving again would give: the solvers
  // record nothing and it stands.
  virtual void record(VkCommandBuffer cmd, vk::PassTimer& timer, const vk::Buffer& surfels, bool geometryMoved) = 0;
  // Whether the solve this frame would take the image's view into account (guidedByView) and whether
  // record() will solve again (`geometryMoved` as record() takes it). Where both hold, the renderer
  // marks what the image shows (gpu's kShown bits) in `shown` before record() and the solve reads it,
  // with the camera (a gpu::Camera) the image is drawn from.
  virtual bool guidedByView() const { return false; }
  virtual bool solvesFrame(bool /*geometryMoved*/) const { return false; }
  virtual void useView(const vk::Buffer& /*shown*/, const vk::Buffer& /*camera*/) {}
  // Whether record() left the solve to recordMorePasses() (the image is resolved after it).
  virtual bool solvePending() const { return false; }
  // After the frame completed: whether it must be recorded again (the solver has made more room),
  // and, when it stands, a chance to give back what it left unused.
  virtual bool frameMustBeRedone() = 0;
  virtual void frameStands() {}
  // After the frame completed: whether the solver has more to record before the irradiance is final
  // (bounces that have not converged yet), and the recording of it; the frame renderer submits it
  // and resolves the image again.
  virtual bool wantsMorePasses() const { return false; }
  virtual void recordMorePasses(VkCommandBuffer, vk::PassTimer&) {}
  // What the sidecar records of the solver per frame (e.g. its bounces).
  virtual std::vector<std::pair<std::string, double>> frameFigures() const { return {}; }
  // Whether the solver reflects the indirect light through the glossy surfels' lobes
  // (recordReflections); where it does not, the resolve reflects it as if it arrived evenly.
  virtual bool reflectsLobes() const { return false; }
  // Once the irradiance is final: per surfel into `lobes` (rgb, w unused), the radiance each glossy
  // surfel's specular lobe reflects toward `eye` (gpu::cameraEye) of the light of the other
  // surfaces (not the emitters' direct light, which the depth maps give per pixel); zero at the
  // others. Only at the surfels `shown` marks kShownFit (gpu's kShown bits, per surfel): the image
  // reads no others.
  virtual void recordReflections(VkCommandBuffer, vk::PassTimer&, glm::vec4 /*eye*/, const vk::Buffer& /*shown*/,
                                 const vk::Buffer& /*lobes*/) {}
  // Irradiance per surfel (rgba32f, w unused), read by the resolve pass.
  virtual const vk::Buffer& irradiance() const = 0;
  // Per surfel (uint): 1 where it lies inside another object this frame (gi::Refit), else 0.
  virtual const vk::Buffer& surfelBuried() const = 0;
  // Device memory the solver holds.
  virtual uint64_t allocatedBytes() const = 0;
};

}  // namespace ivgi::gi

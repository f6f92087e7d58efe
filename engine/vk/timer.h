#pragma once
// Per-pass GPU times: a timestamp at the top of the pipe before a pass and one at the bottom after
// it, 64-bit, converted with the device's timestampPeriod.
#include <vulkan/vulkan.h>

#include <string>
#include <utility>
#include <vector>

#include "engine/vk/context.h"

namespace ivgi::vk {

struct PassTime {
  std::string pass;
  double ms = 0;
  uint32_t count = 1;  // times it was recorded (summed in ms)
};

class PassTimer {
 public:
  PassTimer(const Context& ctx, uint32_t maxPasses = 1024);
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  // At the start of a frame's command buffer. `keepEarlier`: the frame is recorded again (redone),
  // and the passes timed since the last reset, completed, are kept and summed into results(): the
  // frame cost every run of it.
  void reset(VkCommandBuffer cmd, bool keepEarlier = false);
  void begin(VkCommandBuffer cmd, std::string pass);
  void end(VkCommandBuffer cmd);
  // How many more passes this frame can time.
  uint32_t room() const { return maxPasses_ - uint32_t(names_.size()); }
  // After the command buffers completed: the time of each pass, in recording order; a pass recorded
  // more than once since reset() (in later command buffers of the frame) is summed.
  std::vector<PassTime> results() const;

 private:
  const Context& ctx_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t maxPasses_;
  std::vector<std::string> names_;
  std::vector<PassTime> kept_;  // the frame's earlier runs (reset's keepEarlier)
};

}  // namespace ivgi::vk

#include "engine/vk/timer.h"

#include <algorithm>

namespace ivgi::vk {

PassTimer::PassTimer(const Context& ctx, uint32_t maxPasses) : ctx_(ctx), maxPasses_(maxPasses) {
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = 2 * maxPasses;
  check(vkCreateQueryPool(ctx.device(), &qi, nullptr, &pool_), "vkCreateQueryPool");
}

PassTimer::~PassTimer() { vkDestroyQueryPool(ctx_.device(), pool_, nullptr); }

void PassTimer::reset(VkCommandBuffer cmd, bool keepEarlier) {
  kept_ = keepEarlier ? results() : std::vector<PassTime>{};
  vkCmdResetQueryPool(cmd, pool_, 0, 2 * maxPasses_);
  names_.clear();
}

void PassTimer::begin(VkCommandBuffer cmd, std::string pass) {
  if (names_.size() >= maxPasses_) throw VulkanError("too many timed passes in one frame");
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, uint32_t(2 * names_.size()));
  names_.push_back(std::move(pass));
}

void PassTimer::end(VkCommandBuffer cmd) {
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, uint32_t(2 * names_.size() - 1));
}

std::vector<PassTime> PassTimer::results() const {
  std::vector<PassTime> out = kept_;
  if (names_.empty()) return out;
  std::vector<uint64_t> ticks(2 * names_.size());
  check(vkGetQueryPoolResults(ctx_.device(), pool_, 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t),
                              ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  uint64_t mask = ctx_.timestampValidBits() >= 64 ? ~0ull : ((1ull << ctx_.timestampValidBits()) - 1);
  for (size_t i = 0; i < names_.size(); ++i) {
    const double ms = double((ticks[2 * i + 1] - ticks[2 * i]) & mask) * ctx_.timestampPeriodNs() * 1e-6;
    auto same = std::find_if(out.begin(), out.end(), [&](const PassTime& p) { return p.pass == names_[i]; });
    if (same == out.end())
      out.push_back({names_[i], ms, 1});
    else
      same->ms += ms, ++same->count;  // a pass recorded again (in a later submission or run of the frame)
  }
  return out;
}

}  // namespace ivgi::vk

#pragma once
// A compute program: one embedded SPIR-V shader whose descriptor layout (storage buffers and
// imageBuffers, in binding order, with their formats) and push-constant size are read from the
// SPIR-V itself. Buffers go in by push descriptors (an imageBuffer as a texel view of the buffer),
// so a dispatch is one call naming its buffers.
#include <vulkan/vulkan.h>

#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/context.h"

namespace ivgi::vk {

struct Groups {
  uint32_t x = 1, y = 1, z = 1;
};

class Program {
 public:
  // The product's shader `shaderName` (shaders/NAME.comp), or the given SPIR-V; `constants` are the
  // values of specialization constants 0, 1, … (32-bit each; a bool is 0 or 1).
  explicit Program(const Context& ctx, const std::string& shaderName, const std::vector<uint32_t>& constants = {});
  Program(const Context& ctx, const std::string& name, std::span<const uint32_t> code, const std::vector<uint32_t>& constants = {});
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  const std::string& name() const { return name_; }
  uint32_t localSizeX() const { return localSize_[0]; }
  uint32_t bindingCount() const { return bindingCount_; }
  uint32_t pushConstantBytes() const { return pushBytes_; }

  // Binds `buffers` to bindings 0..n-1, pushes the constants, dispatches `groups`.
  void dispatch(VkCommandBuffer cmd, Groups groups, std::initializer_list<const Buffer*> buffers,
                const void* push = nullptr, uint32_t pushBytes = 0) const;
  template <class Push>
  void dispatch(VkCommandBuffer cmd, Groups groups, std::initializer_list<const Buffer*> buffers, const Push& push) const {
    dispatch(cmd, groups, buffers, &push, sizeof(Push));
  }
  // Dispatch with the group counts at `offset` in `args` (a VkDispatchIndirectCommand).
  template <class Push>
  void dispatchIndirect(VkCommandBuffer cmd, const Buffer& args, VkDeviceSize offset, std::initializer_list<const Buffer*> buffers,
                        const Push& push) const {
    bind(cmd, buffers, &push, sizeof(Push));
    vkCmdDispatchIndirect(cmd, args.handle(), offset);
  }
  // One invocation per item (items laid out over x and y so that no dimension exceeds the device
  // limit; shaders read their item with itemIndex() from common.glsl and test it against the count).
  template <class Push>
  void dispatchItems(VkCommandBuffer cmd, uint64_t items, std::initializer_list<const Buffer*> buffers, const Push& push) const {
    dispatch(cmd, groupsFor(items, localSize_[0]), buffers, &push, sizeof(Push));
  }
  // Workgroups for `count` items of `perGroup` each, laid out over x then y.
  Groups groupsFor(uint64_t count, uint32_t perGroup) const;

 private:
  void bind(VkCommandBuffer cmd, std::initializer_list<const Buffer*> buffers, const void* push, uint32_t pushBytes) const;

  const Context& ctx_;
  std::string name_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  uint32_t bindingCount_ = 0;
  // Per binding: an imageBuffer's view format and texel bytes, or UNDEFINED for a storage buffer.
  std::vector<std::pair<VkFormat, VkDeviceSize>> texels_;
  uint32_t pushBytes_ = 0;
  uint32_t localSize_[3] = {1, 1, 1};
};

// Makes the writes of earlier passes (shader and transfer) visible to later passes.
void barrier(VkCommandBuffer cmd);

}  // namespace ivgi::vk

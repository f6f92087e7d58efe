#pragma once
// A compute program: one SPIR-V shader whose descriptor layout (storage buffers and imageBuffers,
// with their formats), binding names, specialization constants and push-constant size are read
// from the SPIR-V itself. Buffers are bound by the names the shader gives them and go in by push
// descriptors (an imageBuffer as a texel view of the buffer; an array of imageBuffers as views of
// one buffer, shaders/common/parted_texels.glsl), so a dispatch is one call naming its buffers, or
// naming a pool of them that the shader's own names pick from; no binding number is written twice.
// Every dispatch ends with a barrier (buffer.h): what it wrote is what the next command reads.
#include <vulkan/vulkan.h>

#include <future>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/vk/buffer.h"
#include "engine/vk/context.h"

namespace ivgi::vk {

struct Groups {
  uint32_t x = 1, y = 1, z = 1;
};

// A buffer bound to the shader's binding of that name: an imageBuffer's variable name, or a
// storage block's instance name (for an anonymous instance, its block name with the first letter
// lowered: `buffer GlobalBins { … }` is "globalBins").
struct Binding {
  std::string_view name;
  const Buffer& buffer;
};

// The buffers a dispatch binds, by name: listed (each must match a binding of the program), or a
// pool whose entries a program takes where its shader names them, with listed ones in front.
class Bindings {
 public:
  Bindings(std::initializer_list<Binding> listed) { add(listed, true); }
  static Bindings pool(std::initializer_list<Binding> entries) {
    Bindings b;
    b.add(entries, false);
    return b;
  }
  // These bindings with `listed` in front of them.
  Bindings with(std::initializer_list<Binding> listed) const {
    Bindings b;
    b.add(listed, true);
    b.entries_.insert(b.entries_.end(), entries_.begin(), entries_.end());
    return b;
  }
  // These bindings, then those of `more` (a pool of pools).
  Bindings plus(const Bindings& more) const {
    Bindings b = *this;
    b.entries_.insert(b.entries_.end(), more.entries_.begin(), more.entries_.end());
    return b;
  }

 private:
  friend class Program;
  struct Entry {
    std::string_view name;
    const Buffer* buffer;
    bool listed;
  };
  Bindings() = default;
  void add(std::initializer_list<Binding> entries, bool listed) {
    for (const Binding& b : entries) entries_.push_back({b.name, &b.buffer, listed});
  }
  std::vector<Entry> entries_;
};

// Values of the shader's specialization constants, by name; the workgroup size set by
// local_size_x_id has no name and is `localSizeX` (0: the shader's default). `texelPartBits`
// (parted_texels.glsl) is set from the device, not here.
struct Specialization {
  std::initializer_list<std::pair<std::string_view, uint32_t>> constants = {};
  uint32_t localSizeX = 0;
};

class Program {
 public:
  Program(const Context& ctx, std::string name, std::span<const uint32_t> code,
          const Specialization& specialization = {});
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  const std::string& name() const { return name_; }
  uint32_t localSizeX() const { return compiled_->localSize[0]; }
  uint32_t pushConstantBytes() const { return compiled_->pushBytes; }

  // Binds every binding of the shader by its name, pushes the constants, dispatches `groups`, and
  // records the barrier after it.
  template <class Push>
  void dispatch(VkCommandBuffer cmd, Groups groups, const Bindings& bindings, const Push& push) const {
    const bool timed = bind(cmd, bindings, &push, sizeof(Push));
    vkCmdDispatch(cmd, groups.x, groups.y, groups.z);
    finish(cmd, timed);
  }
  void dispatch(VkCommandBuffer cmd, Groups groups, const Bindings& bindings) const;
  // Dispatch with the group counts at `offset` in `args` (a VkDispatchIndirectCommand).
  template <class Push>
  void dispatchIndirect(VkCommandBuffer cmd, const Buffer& args, VkDeviceSize offset, const Bindings& bindings,
                        const Push& push) const {
    const bool timed = bind(cmd, bindings, &push, sizeof(Push));
    vkCmdDispatchIndirect(cmd, args.handle(), offset);
    finish(cmd, timed);
  }
  void dispatchIndirect(VkCommandBuffer cmd, const Buffer& args, VkDeviceSize offset, const Bindings& bindings) const {
    const bool timed = bind(cmd, bindings, nullptr, 0);
    vkCmdDispatchIndirect(cmd, args.handle(), offset);
    finish(cmd, timed);
  }
  // One invocation per item (items laid out over x and y so that no dimension exceeds the device
  // limit; shaders read their item with itemIndex() from common.glsl and test it against the count).
  template <class Push>
  void dispatchItems(VkCommandBuffer cmd, uint64_t items, const Bindings& bindings, const Push& push) const {
    dispatch(cmd, groupsFor(items, compiled_->localSize[0]), bindings, push);
  }
  // Workgroups for `count` items of `perGroup` each, laid out over x then y.
  Groups groupsFor(uint64_t count, uint32_t perGroup) const;

 private:
  // Binds, pushes and, where the context times dispatches (and has room), starts timing this one:
  // whether it did.
  bool bind(VkCommandBuffer cmd, const Bindings& bindings, const void* push, uint32_t pushBytes) const;
  // Ends the dispatch's timing where bind() started it, then records the barrier after it.
  void finish(VkCommandBuffer cmd, bool timed) const;

  // Per binding (numbered 0..n-1): its name, and an imageBuffer's view format and texel bytes
  // (UNDEFINED for a storage buffer).
  struct Slot {
    std::string name;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkDeviceSize texelBytes = 0;
    uint32_t parts = 1;  // an imageBuffer array: that many views of one buffer
  };
  // The pipeline compiled from the shader and specialization, with what reflection found: shared by
  // every Program of them on one context (Context::shared). The pipeline is compiled on a worker
  // thread (the driver's compiler is most of a run's start-up), `ready` once it is; the first
  // dispatch waits for it.
  struct Compiled {
    VkDevice device = VK_NULL_HANDLE;
    VkShaderModule module = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    std::shared_future<void> ready;  // rethrows the compilation's error
    std::vector<Slot> slots;
    uint32_t texelViews = 1;  // the views of an imageBuffer array the shader reads (parted_texels.glsl)
    uint32_t pushBytes = 0;
    uint32_t localSize[3] = {1, 1, 1};
    ~Compiled();
  };
  std::shared_ptr<Compiled> compile(std::span<const uint32_t> code, const Specialization& specialization) const;

  const Context& ctx_;
  std::string name_;
  std::shared_ptr<const Compiled> compiled_;
  // The views of `buffer` that `slot` binds: the whole buffer, or for an array view p from texel
  // p << texelPartBits (views past the buffer's end repeat the first: bound, never read).
  void addTexelViews(const Buffer& buffer, const Slot& slot, std::vector<VkBufferView>& views) const;
};

}  // namespace ivgi::vk

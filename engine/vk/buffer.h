#pragma once
// A VkBuffer with its own memory. Device buffers hold what passes exchange; host buffers are mapped
// and carry per-frame inputs up and results down.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>
#include <utility>
#include <vector>

#include "engine/vk/context.h"

namespace ivgi::vk {

enum class Memory { Device, Host };

// The bytes of the buffers that name it, counted as they are made and freed: what an owner has
// allocated, without a list of its buffers, and of those in host memory (Memory::Host).
class Allocations {
 public:
  uint64_t bytes() const { return bytes_; }
  uint64_t hostBytes() const { return hostBytes_; }
  uint64_t deviceBytes() const { return bytes_ - hostBytes_; }

 private:
  friend class Buffer;
  uint64_t bytes_ = 0, hostBytes_ = 0;
};

class Buffer {
 public:
  static constexpr VkDeviceSize kMinBytes = 16;  // the least a buffer takes (an empty array gets a stand-in)
  Buffer() = default;
  Buffer(const Context& ctx, VkDeviceSize bytes, Memory memory, Allocations* allocations = nullptr);
  ~Buffer() { release(); }
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  Memory memory() const { return memoryKind_; }
  bool mapped() const { return mapped_ != nullptr; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

  // Copies bytes in (mapped: memcpy; device: through a staging buffer and one submission).
  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  template <class T>
  void upload(std::span<const T> items) {
    upload(items.data(), items.size_bytes());
  }
  template <class T>
  void upload(const std::vector<T>& items) {
    upload(items.data(), items.size() * sizeof(T));
  }

  void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  // A texel view of the buffer from `offset` (made on first use, kept with the buffer): shaders read
  // it as an imageBuffer, which lavapipe loads with vector gathers instead of one lane at a time.
  VkBufferView texelView(VkFormat format, VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE) const;
  template <class T>
  std::vector<T> read(size_t count) const {
    std::vector<T> out(count);
    download(out.data(), count * sizeof(T));
    return out;
  }

 private:
  void release();
  const Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  Memory memoryKind_ = Memory::Device;
  void* mapped_ = nullptr;
  Allocations* allocations_ = nullptr;
  struct View {
    VkFormat format;
    VkDeviceSize offset, range;
    VkBufferView view;
  };
  mutable std::vector<View> views_;
};

// A device buffer for `count` items of T (at least one: a buffer is never empty), not filled.
template <class T>
Buffer deviceArray(const Context& ctx, size_t count, Allocations& allocations) {
  return Buffer(ctx, std::max<size_t>(count, 1) * sizeof(T), Memory::Device, &allocations);
}

// Creates a buffer sized for `items` (at least one element) and fills it.
template <class T>
Buffer makeBuffer(const Context& ctx, const std::vector<T>& items, Memory memory = Memory::Device,
                  Allocations* allocations = nullptr) {
  Buffer b(ctx, std::max<size_t>(items.size(), 1) * sizeof(T), memory, allocations);
  if (!items.empty()) b.upload(items);
  return b;
}

// Makes the writes of earlier commands (shader and transfer) visible to later ones and to the host.
// Dispatches (program.h) and the transfers below record it themselves.
void barrier(VkCommandBuffer cmd);

// Transfers recorded into a command buffer, each ending, as a dispatch does, with the barrier after
// it (program.h): a copy of the whole of `from` to the start of `to`, or of one region; `size`
// bytes from `offset` filled with a 32-bit value; bytes written from the host's memory (at most
// 65,536, recorded into the command buffer).
void copyBuffer(VkCommandBuffer cmd, const Buffer& from, const Buffer& to);
void copyRegion(VkCommandBuffer cmd, const Buffer& from, const Buffer& to, const VkBufferCopy& region);
void copyRegions(VkCommandBuffer cmd, const Buffer& from, const Buffer& to, std::span<const VkBufferCopy> regions);
void fillBuffer(VkCommandBuffer cmd, const Buffer& buffer, uint32_t value, VkDeviceSize offset = 0,
                VkDeviceSize size = VK_WHOLE_SIZE);
void updateBuffer(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize bytes, const void* data);

}  // namespace ivgi::vk

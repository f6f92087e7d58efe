#include "engine/vk/buffer.h"

#include <algorithm>

namespace ivgi::vk {

Buffer::Buffer(const Context& ctx, VkDeviceSize bytes, Memory memory, Allocations* allocations)
    : ctx_(&ctx), size_(std::max(bytes, kMinBytes)), memoryKind_(memory) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size_;
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
             VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex =
      memory == Memory::Host
          ? ctx.findMemoryType(req.memoryTypeBits,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0)
          : ctx.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  check(vkAllocateMemory(ctx.device(), &ai, nullptr, &memory_), "vkAllocateMemory");
  check(vkBindBufferMemory(ctx.device(), buffer_, memory_, 0), "vkBindBufferMemory");
  VkMemoryPropertyFlags flags = 0;
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &mp);
  flags = mp.memoryTypes[ai.memoryTypeIndex].propertyFlags;
  if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
    check(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  if (const std::optional<uint32_t> word = ctx.freshMemoryFill()) {
    if (mapped_)
      std::fill_n(static_cast<uint32_t*>(mapped_), size_ / sizeof(uint32_t), *word);
    else
      ctx.submitAndWait([&](VkCommandBuffer cmd) { fillBuffer(cmd, *this, *word); });
  }
  allocations_ = allocations;
  if (allocations_) allocations_->bytes_ += size_, allocations_->hostBytes_ += memory == Memory::Host ? size_ : 0;
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = o.ctx_, buffer_ = o.buffer_, memory_ = o.memory_, size_ = o.size_, memoryKind_ = o.memoryKind_;
    mapped_ = o.mapped_;
    allocations_ = o.allocations_, views_ = std::move(o.views_);
    o.buffer_ = VK_NULL_HANDLE, o.memory_ = VK_NULL_HANDLE, o.mapped_ = nullptr, o.size_ = 0, o.allocations_ = nullptr;
    o.views_.clear();
  }
  return *this;
}

void Buffer::release() {
  if (!ctx_) return;
  for (const View& v : views_) vkDestroyBufferView(ctx_->device(), v.view, nullptr);
  views_.clear();
  if (buffer_) vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
  if (memory_) vkFreeMemory(ctx_->device(), memory_, nullptr);  // unmaps implicitly
  if (allocations_ && buffer_)
    allocations_->bytes_ -= size_, allocations_->hostBytes_ -= memoryKind_ == Memory::Host ? size_ : 0;
  buffer_ = VK_NULL_HANDLE, memory_ = VK_NULL_HANDLE, mapped_ = nullptr, allocations_ = nullptr;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw VulkanError("buffer upload out of range");
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Buffer staging(*ctx_, bytes, Memory::Host);
  staging.upload(data, bytes);
  ctx_->submitAndWait([&](VkCommandBuffer cmd) {
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer_, 1, &region);
  });
}

VkBufferView Buffer::texelView(VkFormat format, VkDeviceSize offset, VkDeviceSize range) const {
  for (const View& v : views_)
    if (v.format == format && v.offset == offset && v.range == range) return v.view;
  VkBufferViewCreateInfo vi{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  vi.buffer = buffer_;
  vi.format = format;
  vi.offset = offset;
  vi.range = range;
  VkBufferView view = VK_NULL_HANDLE;
  check(vkCreateBufferView(ctx_->device(), &vi, nullptr, &view), "vkCreateBufferView");
  views_.push_back({format, offset, range, view});
  return view;
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw VulkanError("buffer download out of range");
  if (mapped_) {
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Buffer staging(*ctx_, bytes, Memory::Host);
  ctx_->submitAndWait([&](VkCommandBuffer cmd) {
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.handle(), 1, &region);
  });
  staging.download(data, bytes);
}

void barrier(VkCommandBuffer cmd) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
}

void copyBuffer(VkCommandBuffer cmd, const Buffer& from, const Buffer& to) {
  copyRegion(cmd, from, to, {0, 0, from.size()});
}

void copyRegion(VkCommandBuffer cmd, const Buffer& from, const Buffer& to, const VkBufferCopy& region) {
  copyRegions(cmd, from, to, {&region, 1});
}

void copyRegions(VkCommandBuffer cmd, const Buffer& from, const Buffer& to, std::span<const VkBufferCopy> regions) {
  if (regions.empty()) return;
  vkCmdCopyBuffer(cmd, from.handle(), to.handle(), uint32_t(regions.size()), regions.data());
  barrier(cmd);
}

void fillBuffer(VkCommandBuffer cmd, const Buffer& buffer, uint32_t value, VkDeviceSize offset, VkDeviceSize size) {
  vkCmdFillBuffer(cmd, buffer.handle(), offset, size, value);
  barrier(cmd);
}

void updateBuffer(VkCommandBuffer cmd, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize bytes,
                  const void* data) {
  vkCmdUpdateBuffer(cmd, buffer.handle(), offset, bytes, data);
  barrier(cmd);
}

}  // namespace ivgi::vk

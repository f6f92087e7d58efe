#pragma once
// The device layer: instance, physical-device choice, logical device with the features ivgi needs,
// one compute queue, and one-shot command submission. Everything above it records compute passes.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ivgi::vk {

// Thrown for any Vulkan failure; the message names the call and the result code.
struct VulkanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void check(VkResult result, const char* what);

struct DeviceInfo {
  uint32_t index = 0;
  std::string name;
  std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
  std::string driverName;
  std::string driverInfo;
  uint32_t apiVersion = 0;
  std::string uuid;     // lower-case hex, 8-4-4-4-12 (on NVIDIA, nvidia-smi's GPU UUID without "GPU-")
  std::string missing;  // empty when the device has every feature ivgi needs
};

struct ContextOptions {
  std::string device;       // name substring, index or UUID; empty = IVGI_DEVICE, then automatic choice
  bool validation = false;  // also switched on by IVGI_VALIDATION=1
  // Texels a view of a parted array holds, as a power of two; 0: the most the device allows (tests
  // make it small, so that small scenes fill several views).
  uint32_t texelPartBits = 0;
  // Passes take their way for a device whose subgroups are smaller than their workgroups
  // (subgroupHolds() false), so that tests check that way on any device.
  bool spanSubgroups = false;
};

class PassTimer;

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Every Vulkan device the loader reports, with what each lacks.
  static std::vector<DeviceInfo> listDevices();

  VkDevice device() const { return device_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  // The largest single allocation, and so the largest buffer (VkPhysicalDeviceMaintenance3Properties).
  VkDeviceSize maxAllocationBytes() const { return maxAllocationBytes_; }
  // An array bound as several texel views (shaders/common/parted_texels.glsl) has 2^texelPartBits() texels
  // a view: maxTexelBufferElements rounded down to a power of two, or less where options ask.
  uint32_t texelPartBits() const { return texelPartBits_; }
  // The size of the heap that device-local buffers come from: what the device says it can hold.
  VkDeviceSize deviceHeapBytes() const;
  // What a solver may allocate in device memory: `budget` (--max-memory) where set, else the heap.
  VkDeviceSize deviceBudget(uint64_t budget) const { return budget ? budget : deviceHeapBytes(); }
  // The size of the heap that host-visible buffers (Memory::Host) come from, which the device reads
  // across its bus; on a CPU device or an integrated GPU the same heap as the device's.
  VkDeviceSize hostHeapBytes() const;
  bool hostHeapIsDeviceHeap() const;
  double timestampPeriodNs() const { return properties_.limits.timestampPeriod; }
  uint32_t timestampValidBits() const { return timestampValidBits_; }
  // Invocations a subgroup runs together (8 on lavapipe, 32 on NVIDIA).
  uint32_t subgroupSize() const { return subgroupSize_; }
  // Whether a workgroup of `invocations` lies in one subgroup, so that subgroup operations reach all
  // of it (shaders' groupInOneSubgroup).
  bool subgroupHolds(uint32_t invocations) const { return !spanSubgroups_ && subgroupSize_ >= invocations; }
  // 64-bit atomics on workgroup-shared memory (else passes keep such data in buffers).
  bool sharedInt64Atomics() const { return sharedInt64Atomics_; }

  // Records with `record` into a fresh command buffer, submits it and waits for completion.
  void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags wanted, VkMemoryPropertyFlags avoid) const;

  // Number of validation-layer errors reported so far (0 when validation is off).
  uint32_t validationErrors() const { return validationErrors_; }
  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }

  PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;

  // While set, every program's dispatch is timed on its own into `timer`, under its program's name
  // (bench --per-program); nullptr: none is.
  void timeDispatches(PassTimer* timer) const { dispatchTimer_ = timer; }
  PassTimer* dispatchTimer() const { return dispatchTimer_; }

  // For tests: while set, every buffer made holds `word` in each 32-bit word before anything is
  // written to it, so that a result that reads memory nothing wrote shows as a difference between
  // two fills (the driver's fresh memory holds whatever it last held); nullopt: left as it comes.
  void fillFreshMemory(std::optional<uint32_t> word) const { freshMemoryFill_ = word; }
  std::optional<uint32_t> freshMemoryFill() const { return freshMemoryFill_; }

  // What was made once under `key` for this device, made by `make` the first time it is asked for
  // and kept as long as the context: the compiled pipelines that every Program of one shader and
  // specialization shares (a pipeline costs its compilation; a device compiles it once).
  std::shared_ptr<const void> shared(const std::string& key,
                                     const std::function<std::shared_ptr<const void>()>& make) const;

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  uint32_t timestampValidBits_ = 0;
  uint32_t subgroupSize_ = 1;
  bool spanSubgroups_ = false;
  bool sharedInt64Atomics_ = false;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkDeviceSize maxAllocationBytes_ = 0;
  uint32_t texelPartBits_ = 0;
  VkPhysicalDeviceMemoryProperties memory_{};
  DeviceInfo info_;
  mutable uint32_t validationErrors_ = 0;
  mutable PassTimer* dispatchTimer_ = nullptr;
  mutable std::optional<uint32_t> freshMemoryFill_;
  mutable std::mutex sharedLock_;
  mutable std::map<std::string, std::shared_ptr<const void>> shared_;  // shared(); emptied before the device goes

  static VkBool32 VKAPI_PTR onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                      VkDebugUtilsMessageTypeFlagsEXT types,
                                      const VkDebugUtilsMessengerCallbackDataEXT* data, void* self);
};

}  // namespace ivgi::vk

#include "engine/vk/context.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace ivgi::vk {

namespace {

const char* resultName(VkResult r) {
  switch (r) {
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER (no Vulkan driver found)";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    default: return "VkResult error";
  }
}

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

std::string typeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

// Preference order of the issue: discrete GPU, then integrated, then anything else, lavapipe last.
int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

bool hasExtension(VkPhysicalDevice pd, const char* name) {
  uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  return std::any_of(exts.begin(), exts.end(), [&](auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::optional<uint32_t> computeQueueFamily(VkPhysicalDevice pd, uint32_t* timestampBits) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  for (uint32_t i = 0; i < n; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      if (timestampBits) *timestampBits = families[i].timestampValidBits;
      return i;
    }
  return std::nullopt;
}

DeviceInfo describe(VkPhysicalDevice pd, uint32_t index) {
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceIDProperties id{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES, &subgroup};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &id};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(pd, &props);
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 feats{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
  if (props.properties.apiVersion >= VK_API_VERSION_1_2) vkGetPhysicalDeviceFeatures2(pd, &feats);

  DeviceInfo d;
  d.index = index;
  d.name = props.properties.deviceName;
  d.type = typeName(props.properties.deviceType);
  d.driverName = driver.driverName;
  d.driverInfo = driver.driverInfo;
  d.apiVersion = props.properties.apiVersion;
  // As nvidia-smi and CUDA print it: 8-4-4-4-12 hex digits.
  for (uint32_t i = 0; i < VK_UUID_SIZE; ++i) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02x", id.deviceUUID[i]);
    d.uuid += (i == 4 || i == 6 || i == 8 || i == 10 ? "-" : "") + std::string(hex);
  }
  std::vector<std::string> missing;
  uint32_t tsBits = 0;
  if (props.properties.apiVersion < VK_API_VERSION_1_2) missing.push_back("Vulkan 1.2");
  if (!f12.shaderBufferInt64Atomics) missing.push_back("64-bit buffer atomics (shaderBufferInt64Atomics)");
  if (!feats.features.shaderInt64) missing.push_back("shaderInt64");
  if (!hasExtension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) missing.push_back("VK_KHR_push_descriptor");
  if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
      !(subgroup.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT))
    missing.push_back("subgroup ballot in compute shaders");
  if (!computeQueueFamily(pd, &tsBits))
    missing.push_back("a compute queue");
  else if (tsBits == 0 || props.properties.limits.timestampPeriod <= 0)
    missing.push_back("timestamps on the compute queue");
  for (size_t i = 0; i < missing.size(); ++i) d.missing += (i ? ", " : "") + missing[i];
  return d;
}

VkInstance createInstance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "ivgi";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  if (validation) {
    layers.push_back("VK_LAYER_KHRONOS_validation");
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(extensions.size());
  ci.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r == VK_ERROR_LAYER_NOT_PRESENT)
    throw VulkanError(
        "validation requested but VK_LAYER_KHRONOS_validation is not installed (package vulkan-validationlayers)");
  check(r, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> pds(n);
  check(vkEnumeratePhysicalDevices(instance, &n, pds.data()), "vkEnumeratePhysicalDevices");
  return pds;
}

// Picks the device named by `want` (index, UUID with or without nvidia-smi's "GPU-", or a
// case-insensitive name substring), else the best suitable.
uint32_t chooseDevice(const std::vector<VkPhysicalDevice>& pds, const std::vector<DeviceInfo>& infos,
                      const std::string& want) {
  if (pds.empty()) throw VulkanError("no Vulkan device found (install mesa-vulkan-drivers for lavapipe)");
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  };
  if (!want.empty()) {
    std::optional<uint32_t> pick;
    if (std::all_of(want.begin(), want.end(), ::isdigit)) {
      uint32_t i = uint32_t(std::stoul(want));
      if (i >= pds.size())
        throw VulkanError("device index " + want + " out of range: " + std::to_string(pds.size()) +
                          " device(s) (see `ivgi devices`)");
      pick = i;
    } else {
      const std::string uuid = lower(want).rfind("gpu-", 0) == 0 ? lower(want).substr(4) : lower(want);
      for (uint32_t i = 0; i < infos.size() && !pick; ++i)
        if (infos[i].uuid == uuid) pick = i;
      for (uint32_t i = 0; i < infos.size() && !pick; ++i)
        if (lower(infos[i].name).find(lower(want)) != std::string::npos) pick = i;
      if (!pick) throw VulkanError("no Vulkan device matches '" + want + "' (see `ivgi devices`)");
    }
    if (!infos[*pick].missing.empty())
      throw VulkanError("device '" + infos[*pick].name + "' lacks required features: " + infos[*pick].missing);
    return *pick;
  }
  std::optional<uint32_t> best;
  int bestRank = 1 << 30;
  for (uint32_t i = 0; i < pds.size(); ++i) {
    if (!infos[i].missing.empty()) continue;
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pds[i], &p);
    int rank = typeRank(p.deviceType);
    if (rank < bestRank) bestRank = rank, best = i;
  }
  if (!best) {
    std::string why;
    for (auto& d : infos) why += " '" + d.name + "' lacks " + d.missing + ";";
    throw VulkanError("no Vulkan device has the features ivgi needs:" + why);
  }
  return *best;
}

}  // namespace

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw VulkanError(std::string(what) + " failed: " + resultName(result));
}

std::vector<DeviceInfo> Context::listDevices() {
  VkInstance instance = createInstance(false);
  std::vector<DeviceInfo> out;
  auto pds = physicalDevices(instance);
  for (uint32_t i = 0; i < pds.size(); ++i) out.push_back(describe(pds[i], i));
  vkDestroyInstance(instance, nullptr);
  return out;
}

Context::Context(const ContextOptions& options) {
  bool validation = options.validation || envFlag("IVGI_VALIDATION");
  instance_ = createInstance(validation);
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = &Context::onMessage;
    mi.pUserData = this;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    check(create(instance_, &mi, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }

  auto pds = physicalDevices(instance_);
  std::vector<DeviceInfo> infos;
  for (uint32_t i = 0; i < pds.size(); ++i) infos.push_back(describe(pds[i], i));
  std::string want = options.device;
  if (want.empty())
    if (const char* env = std::getenv("IVGI_DEVICE")) want = env;
  uint32_t chosen = chooseDevice(pds, infos, want);
  physical_ = pds[chosen];
  info_ = infos[chosen];
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES,
                                                      &subgroup};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &maintenance3};
  vkGetPhysicalDeviceProperties2(physical_, &properties2);
  properties_ = properties2.properties;
  maxAllocationBytes_ = maintenance3.maxMemoryAllocationSize;
  texelPartBits_ = std::min<uint32_t>(std::bit_width(properties_.limits.maxTexelBufferElements) - 1, 31);
  if (options.texelPartBits)  // views start 16-byte aligned
    texelPartBits_ = std::clamp<uint32_t>(options.texelPartBits, 4, texelPartBits_);
  subgroupSize_ = std::max(subgroup.subgroupSize, 1u);
  spanSubgroups_ = options.spanSubgroups;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  queueFamily_ = *computeQueueFamily(physical_, &timestampValidBits_);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qi.queueFamilyIndex = queueFamily_;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkPhysicalDeviceVulkan12Features supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &supported};
  vkGetPhysicalDeviceFeatures2(physical_, &query);
  sharedInt64Atomics_ = supported.shaderSharedInt64Atomics;
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  f12.shaderBufferInt64Atomics = VK_TRUE;
  f12.shaderSharedInt64Atomics = supported.shaderSharedInt64Atomics;
  f12.hostQueryReset = VK_TRUE;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
  features.features.shaderInt64 = VK_TRUE;
  const char* extensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = 1;
  di.ppEnabledExtensionNames = extensions;
  check(vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  cmdPushDescriptorSet =
      reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));

  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = queueFamily_;
  check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(device_, &fi, nullptr, &fence_), "vkCreateFence");
}

std::shared_ptr<const void> Context::shared(const std::string& key,
                                            const std::function<std::shared_ptr<const void>()>& make) const {
  const std::lock_guard<std::mutex> lock(sharedLock_);
  auto it = shared_.find(key);
  if (it == shared_.end()) it = shared_.emplace(key, make()).first;
  return it->second;
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    shared_.clear();
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  try {
    record(cmd);
  } catch (...) {  // a pass refused its bindings: nothing was submitted
    vkFreeCommandBuffers(device_, pool_, 1, &cmd);
    throw;
  }
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkQueueSubmit(queue_, 1, &si, fence_), "vkQueueSubmit");
  check(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  check(vkResetFences(device_, 1, &fence_), "vkResetFences");
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
}

VkDeviceSize Context::deviceHeapBytes() const {
  uint32_t type = findMemoryType(~0u, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  return memory_.memoryHeaps[memory_.memoryTypes[type].heapIndex].size;
}

namespace {
constexpr VkMemoryPropertyFlags kHostMemory =
    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
}

VkDeviceSize Context::hostHeapBytes() const {
  return memory_.memoryHeaps[memory_.memoryTypes[findMemoryType(~0u, kHostMemory, 0)].heapIndex].size;
}

bool Context::hostHeapIsDeviceHeap() const {
  const uint32_t device = findMemoryType(~0u, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  return memory_.memoryTypes[device].heapIndex == memory_.memoryTypes[findMemoryType(~0u, kHostMemory, 0)].heapIndex;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags wanted, VkMemoryPropertyFlags avoid) const {
  // First a type with everything wanted and nothing avoided, then one with what is wanted.
  for (int pass = 0; pass < 2; ++pass)
    for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
      VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
      if ((typeBits & (1u << i)) && (f & wanted) == wanted && (pass == 1 || (f & avoid) == 0)) return i;
    }
  throw VulkanError("no suitable Vulkan memory type");
}

VkBool32 Context::onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                            const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    ++static_cast<Context*>(self)->validationErrors_;
    std::fprintf(stderr, "ivgi: validation error: %s\n", data->pMessage);
  } else {
    std::fprintf(stderr, "ivgi: validation warning: %s\n", data->pMessage);
  }
  return VK_FALSE;
}

}  // namespace ivgi::vk

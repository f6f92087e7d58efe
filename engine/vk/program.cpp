#include "engine/vk/program.h"

#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <cctype>
#include <semaphore>
#include <span>
#include <thread>
#include <vector>

#include "engine/vk/timer.h"

namespace ivgi::vk {

namespace {

// A turn of the worker threads that compile pipelines: as many at once as the host has cores (each
// compilation holds a compiler's memory).
class CompilerTurn {
 public:
  CompilerTurn() { turns().acquire(); }
  ~CompilerTurn() { turns().release(); }
  CompilerTurn(const CompilerTurn&) = delete;
  CompilerTurn& operator=(const CompilerTurn&) = delete;

 private:
  static std::counting_semaphore<>& turns() {
    static std::counting_semaphore<> t(std::max<std::ptrdiff_t>(1, std::thread::hardware_concurrency()));
    return t;
  }
};

// The view format of an imageBuffer's declared format, and the bytes of one texel.
struct TexelFormat {
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkDeviceSize bytes = 0;
};

TexelFormat texelFormat(SpvImageFormat f) {
  switch (f) {
    case SpvImageFormatRgba32f: return {VK_FORMAT_R32G32B32A32_SFLOAT, 16};
    case SpvImageFormatRgba32ui: return {VK_FORMAT_R32G32B32A32_UINT, 16};
    case SpvImageFormatRg32f: return {VK_FORMAT_R32G32_SFLOAT, 8};
    case SpvImageFormatRg32ui: return {VK_FORMAT_R32G32_UINT, 8};
    case SpvImageFormatR32f: return {VK_FORMAT_R32_SFLOAT, 4};
    case SpvImageFormatR32ui: return {VK_FORMAT_R32_UINT, 4};
    default: return {};
  }
}

// One descriptor of set 0: a storage buffer, or a storage texel buffer (imageBuffer) of a format.
struct ReflectedBinding {
  uint32_t binding = 0;
  std::string name;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  TexelFormat texel;
  uint32_t parts = 1;  // an array of imageBuffers: views of one buffer (parted_texels.glsl)
};

struct Reflection {
  std::vector<ReflectedBinding> bindings;
  struct Constant {
    std::string name;
    uint32_t id, value;  // the shader's own value
  };
  std::vector<Constant> constants;  // the named specialization constants
  uint32_t pushBytes = 0;
  uint32_t localSize[3] = {1, 1, 1};
  // Per dimension, the specialization constant that sets the local size (local_size_x_id), or none.
  static constexpr uint32_t kLiteral = ~0u;
  uint32_t localSizeConstant[3] = {kLiteral, kLiteral, kLiteral};
};

// A storage block's binding name: its instance name, else its block name with the first letter lowered.
std::string blockBindingName(spvc_compiler compiler, const spvc_reflected_resource& res) {
  std::string name = spvc_compiler_get_name(compiler, res.id);
  if (name.empty()) name = res.name;
  if (!name.empty()) name[0] = char(std::tolower(static_cast<unsigned char>(name[0])));
  return name;
}

Reflection reflect(std::span<const uint32_t> code, const std::string& name) {
  Reflection r;
  spvc_context sc = nullptr;
  spvc_context_create(&sc);
  auto fail = [&](const std::string& what) {
    std::string msg = "shader " + name + ": " + what;
    if (const char* last = spvc_context_get_last_error_string(sc); last && *last) msg += std::string(": ") + last;
    spvc_context_destroy(sc);
    throw VulkanError(msg);
  };
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_resources resources = nullptr;
  if (spvc_context_parse_spirv(sc, code.data(), code.size(), &ir) != SPVC_SUCCESS) fail("parse");
  if (spvc_context_create_compiler(sc, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) !=
      SPVC_SUCCESS)
    fail("reflect");
  if (spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS) fail("resources");

  const spvc_reflected_resource* list = nullptr;
  size_t count = 0;
  auto setZeroBinding = [&](const spvc_reflected_resource& res) {
    if (spvc_compiler_get_decoration(compiler, res.id, SpvDecorationDescriptorSet) != 0) fail("only set 0 is used");
    return spvc_compiler_get_decoration(compiler, res.id, SpvDecorationBinding);
  };
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_STORAGE_BUFFER, &list, &count);
  for (size_t i = 0; i < count; ++i)
    r.bindings.push_back({setZeroBinding(list[i]), blockBindingName(compiler, list[i])});
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_STORAGE_IMAGE, &list, &count);
  for (size_t i = 0; i < count; ++i) {
    spvc_type type = spvc_compiler_get_type_handle(compiler, list[i].type_id);
    TexelFormat texel = texelFormat(spvc_type_get_image_storage_format(type));
    if (spvc_type_get_image_dimension(type) != SpvDimBuffer || texel.format == VK_FORMAT_UNDEFINED)
      fail("images must be imageBuffers of a 32-bit float or uint format");
    uint32_t parts = 1;
    if (unsigned dims = spvc_type_get_num_array_dimensions(type); dims > 0) {
      if (dims > 1 || !spvc_type_array_dimension_is_literal(type, 0))
        fail("an array of imageBuffers must have one literal size");
      parts = spvc_type_get_array_dimension(type, 0);
    }
    r.bindings.push_back(
        {setZeroBinding(list[i]), list[i].name, VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, texel, parts});
  }
  std::sort(r.bindings.begin(), r.bindings.end(),
            [](const ReflectedBinding& a, const ReflectedBinding& b) { return a.binding < b.binding; });
  for (size_t i = 0; i < r.bindings.size(); ++i) {
    if (r.bindings[i].binding != i) fail("bindings must be numbered 0..n-1");
    for (size_t j = 0; j < i; ++j)
      if (r.bindings[j].name == r.bindings[i].name) fail("two bindings are named '" + r.bindings[i].name + "'");
  }
  for (auto type :
       {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, SPVC_RESOURCE_TYPE_SEPARATE_IMAGE}) {
    spvc_resources_get_resource_list_for_type(resources, type, &list, &count);
    if (count) fail("only storage buffers and imageBuffers are supported as resources");
  }
  spvc_resources_get_resource_list_for_type(resources, SPVC_RESOURCE_TYPE_PUSH_CONSTANT, &list, &count);
  if (count) {
    size_t bytes = 0;
    spvc_compiler_get_declared_struct_size(compiler, spvc_compiler_get_type_handle(compiler, list[0].base_type_id),
                                           &bytes);
    r.pushBytes = uint32_t(bytes);
  }
  const spvc_specialization_constant* constants = nullptr;
  spvc_compiler_get_specialization_constants(compiler, &constants, &count);
  for (size_t i = 0; i < count; ++i)
    if (const char* constantName = spvc_compiler_get_name(compiler, constants[i].id); constantName && *constantName)
      r.constants.push_back(
          {constantName, constants[i].constant_id,
           spvc_constant_get_scalar_u32(spvc_compiler_get_constant_handle(compiler, constants[i].id), 0, 0)});
  for (uint32_t d = 0; d < 3; ++d)
    r.localSize[d] =
        std::max(1u, spvc_compiler_get_execution_mode_argument_by_index(compiler, SpvExecutionModeLocalSize, d));
  spvc_specialization_constant sizeConstants[3] = {};
  spvc_compiler_get_work_group_size_specialization_constants(compiler, &sizeConstants[0], &sizeConstants[1],
                                                             &sizeConstants[2]);
  for (uint32_t d = 0; d < 3; ++d)
    if (sizeConstants[d].id != 0) {
      r.localSizeConstant[d] = sizeConstants[d].constant_id;
      r.localSize[d] = std::max(
          1u, spvc_constant_get_scalar_u32(spvc_compiler_get_constant_handle(compiler, sizeConstants[d].id), 0, 0));
    }
  spvc_context_destroy(sc);
  return r;
}

}  // namespace

Program::Program(const Context& ctx, std::string name, std::span<const uint32_t> code,
                 const Specialization& specialization)
    : ctx_(ctx), name_(std::move(name)) {
  // One compilation per shader code and specialization for the context (the device's own values,
  // texelPartBits, cpuDevice and groupInOneSubgroup, are the same for every program of it).
  std::string key = name_ + "@" + std::to_string(reinterpret_cast<uintptr_t>(code.data())) + "+" +
                    std::to_string(code.size()) + " x" + std::to_string(specialization.localSizeX);
  for (const auto& [constant, value] : specialization.constants)
    key += " " + std::string(constant) + "=" + std::to_string(value);
  compiled_ = std::static_pointer_cast<const Compiled>(
      ctx.shared(key, [&] { return std::shared_ptr<const void>(compile(code, specialization)); }));
}

std::shared_ptr<Program::Compiled> Program::compile(std::span<const uint32_t> code,
                                                    const Specialization& specialization) const {
  const Context& ctx = ctx_;
  auto c = std::make_shared<Compiled>();
  c->device = ctx.device();
  Reflection r = reflect(code, name_);
  for (const ReflectedBinding& b : r.bindings) c->slots.push_back({b.name, b.texel.format, b.texel.bytes, b.parts});
  c->pushBytes = r.pushBytes;
  std::copy(r.localSize, r.localSize + 3, c->localSize);
  if (c->pushBytes > ctx.limits().maxPushConstantsSize)
    throw VulkanError("shader " + name_ + " needs more push-constant bytes than the device allows");

  // Specialization: each named constant by its id, and the workgroup size.
  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  auto specialize = [&](uint32_t id, uint32_t value) {
    entries.push_back({id, uint32_t(4 * values.size()), 4});
    values.push_back(value);
  };
  auto constant = [&](std::string_view name) {
    auto it = std::find_if(r.constants.begin(), r.constants.end(), [&](const auto& c) { return c.name == name; });
    return it == r.constants.end() ? nullptr : &*it;
  };
  for (const auto& [name, value] : specialization.constants) {
    Reflection::Constant* k = constant(name);
    if (!k) throw VulkanError("shader " + name_ + " has no specialization constant named '" + std::string(name) + "'");
    if (std::any_of(entries.begin(), entries.end(), [&](const auto& e) { return e.constantID == k->id; }))
      throw VulkanError("shader " + name_ + ": specialization constant '" + std::string(name) + "' given twice");
    specialize(k->id, value);
    k->value = value;
  }
  // parted_texels.glsl: the views' size is the device's; how many the pass reads, its own.
  if (const Reflection::Constant* k = constant("texelPartBits")) specialize(k->id, ctx.texelPartBits());
  if (const Reflection::Constant* k = constant("texelViews")) c->texelViews = k->value;
  // climb.glsl: whether its atomics need fences around them.
  if (const Reflection::Constant* k = constant("cpuDevice")) specialize(k->id, ctx.info().type == "cpu" ? 1u : 0u);
  if (specialization.localSizeX) {
    if (r.localSizeConstant[0] == Reflection::kLiteral)
      throw VulkanError("shader " + name_ + " sets its workgroup size itself (no local_size_x_id)");
    specialize(r.localSizeConstant[0], specialization.localSizeX);
    c->localSize[0] = specialization.localSizeX;
  }
  // common.glsl: whether subgroup operations reach the whole workgroup.
  if (const Reflection::Constant* k = constant("groupInOneSubgroup"))
    specialize(k->id, ctx.subgroupHolds(c->localSize[0] * c->localSize[1] * c->localSize[2]) ? 1u : 0u);

  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = code.size_bytes();
  mi.pCode = code.data();
  check(vkCreateShaderModule(ctx.device(), &mi, nullptr, &c->module), "vkCreateShaderModule");

  std::vector<VkDescriptorSetLayoutBinding> bindings(c->slots.size());
  for (uint32_t i = 0; i < bindings.size(); ++i)
    bindings[i] = {i, r.bindings[i].type, r.bindings[i].parts, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  li.bindingCount = uint32_t(bindings.size());
  li.pBindings = bindings.data();
  check(vkCreateDescriptorSetLayout(ctx.device(), &li, nullptr, &c->setLayout), "vkCreateDescriptorSetLayout");

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, c->pushBytes};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &c->setLayout;
  pli.pushConstantRangeCount = c->pushBytes ? 1 : 0;
  pli.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(ctx.device(), &pli, nullptr, &c->layout), "vkCreatePipelineLayout");

  // The task writes c->pipeline alone, and ~Compiled waits for it, so `c` outlives it.
  c->ready = std::async(std::launch::async, [c = c.get(), entries = std::move(entries), values = std::move(values)] {
               const CompilerTurn turn;
               VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
               ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
               ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
               ci.stage.module = c->module;
               ci.stage.pName = "main";
               VkSpecializationInfo info{uint32_t(entries.size()), entries.data(), values.size() * 4, values.data()};
               if (!entries.empty()) ci.stage.pSpecializationInfo = &info;
               ci.layout = c->layout;
               check(vkCreateComputePipelines(c->device, VK_NULL_HANDLE, 1, &ci, nullptr, &c->pipeline),
                     "vkCreateComputePipelines");
             }).share();
  return c;
}

Program::Compiled::~Compiled() {
  if (ready.valid()) ready.wait();
  vkDestroyPipeline(device, pipeline, nullptr);
  vkDestroyPipelineLayout(device, layout, nullptr);
  vkDestroyDescriptorSetLayout(device, setLayout, nullptr);
  vkDestroyShaderModule(device, module, nullptr);
}

Program::~Program() = default;

Groups Program::groupsFor(uint64_t count, uint32_t perGroup) const {
  uint64_t groups = std::max<uint64_t>(1, (count + perGroup - 1) / perGroup);
  uint64_t maxX = ctx_.limits().maxComputeWorkGroupCount[0];
  uint64_t y = (groups + maxX - 1) / maxX;
  if (y > ctx_.limits().maxComputeWorkGroupCount[1])
    throw VulkanError("pass " + name_ + ": " + std::to_string(count) + " items exceed the device's dispatch limits");
  return {uint32_t(std::min(groups, maxX)), uint32_t(y), 1};
}

void Program::dispatch(VkCommandBuffer cmd, Groups groups, const Bindings& bindings) const {
  const bool timed = bind(cmd, bindings, nullptr, 0);
  vkCmdDispatch(cmd, groups.x, groups.y, groups.z);
  finish(cmd, timed);
}

void Program::finish(VkCommandBuffer cmd, bool timed) const {
  if (timed) ctx_.dispatchTimer()->end(cmd);
  barrier(cmd);
}

bool Program::bind(VkCommandBuffer cmd, const Bindings& bindings, const void* push, uint32_t pushBytes) const {
  if (pushBytes != compiled_->pushBytes)
    throw VulkanError("pass " + name_ + " takes " + std::to_string(compiled_->pushBytes) +
                      " push-constant bytes, given " + std::to_string(pushBytes));
  const uint32_t n = uint32_t(compiled_->slots.size());
  std::vector<const Buffer*> bound(n, nullptr);
  std::vector<bool> listed(n, false);
  for (const Bindings::Entry& e : bindings.entries_) {
    auto it =
        std::find_if(compiled_->slots.begin(), compiled_->slots.end(), [&](const Slot& s) { return s.name == e.name; });
    if (it == compiled_->slots.end()) {
      if (e.listed) throw VulkanError("pass " + name_ + " has no binding named '" + std::string(e.name) + "'");
      continue;  // a pool's buffer this shader does not read
    }
    const size_t i = size_t(it - compiled_->slots.begin());
    if (e.listed && listed[i]) throw VulkanError("pass " + name_ + ": '" + std::string(e.name) + "' is bound twice");
    if (!bound[i]) bound[i] = e.buffer, listed[i] = e.listed;  // listed ones come first
  }
  std::vector<VkDescriptorBufferInfo> infos(n);
  uint32_t viewCount = 0;
  for (const Slot& slot : compiled_->slots) viewCount += slot.parts;
  std::vector<VkBufferView> views;
  views.reserve(viewCount);  // the writes point into it
  std::vector<VkWriteDescriptorSet> writes(n, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET});
  for (uint32_t i = 0; i < n; ++i) {
    const Buffer* b = bound[i];
    const Slot& slot = compiled_->slots[i];
    if (!b) throw VulkanError("pass " + name_ + ": no buffer given for its binding '" + slot.name + "'");
    VkWriteDescriptorSet& w = writes[i];
    w.dstBinding = i;
    w.descriptorCount = 1;
    if (slot.format != VK_FORMAT_UNDEFINED) {
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
      w.descriptorCount = slot.parts;
      w.pTexelBufferView = views.data() + views.size();
      addTexelViews(*b, slot, views);
    } else {
      if (b->size() > ctx_.limits().maxStorageBufferRange)
        throw VulkanError("pass " + name_ + ": '" + slot.name + "' of " + std::to_string(b->size()) +
                          " bytes exceeds the device's maxStorageBufferRange of " +
                          std::to_string(ctx_.limits().maxStorageBufferRange));
      infos[i] = {b->handle(), 0, VK_WHOLE_SIZE};
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      w.pBufferInfo = &infos[i];
    }
  }
  compiled_->ready.get();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compiled_->pipeline);
  if (n) ctx_.cmdPushDescriptorSet(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compiled_->layout, 0, n, writes.data());
  if (compiled_->pushBytes)
    vkCmdPushConstants(cmd, compiled_->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, compiled_->pushBytes, push);
  PassTimer* timer = ctx_.dispatchTimer();
  if (!timer || timer->room() == 0) return false;
  timer->begin(cmd, name_);
  return true;
}

void Program::addTexelViews(const Buffer& buffer, const Slot& slot, std::vector<VkBufferView>& views) const {
  const uint64_t texels = buffer.size() / slot.texelBytes;
  const uint64_t perView = slot.parts > 1 ? uint64_t(1) << ctx_.texelPartBits() : ctx_.limits().maxTexelBufferElements;
  const uint32_t read = slot.parts > 1 ? std::min(compiled_->texelViews, slot.parts) : 1;
  if (texels > perView * read)
    throw VulkanError("pass " + name_ + ": '" + slot.name + "' of " + std::to_string(buffer.size()) +
                      " bytes exceeds the " + std::to_string(read) + " view(s) of " + std::to_string(perView) +
                      " texels it reads");
  if (slot.parts == 1) {
    views.push_back(buffer.texelView(slot.format));
    return;
  }
  const VkDeviceSize partBytes = perView * slot.texelBytes;
  for (uint32_t p = 0; p < slot.parts; ++p) {
    const VkDeviceSize offset = p * partBytes;
    views.push_back(offset < buffer.size()
                        ? buffer.texelView(slot.format, offset, std::min(partBytes, buffer.size() - offset))
                        : views[views.size() - p]);
  }
}

}  // namespace ivgi::vk

// SPDX-License-Identifier: MIT
#include "vulkan_compute.hpp"

#include <fp_mode.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#ifndef VPLKIT_VULKAN_SPIRV_DIR
#error "VPLKIT_VULKAN_SPIRV_DIR must name the folder of the compiled kernels"
#endif

namespace vplkit::vk_test {
namespace {

const char* const validation_layer = "VK_LAYER_KHRONOS_validation";

std::string result_name(VkResult r) {
  switch (r) {
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    default: return "VkResult " + std::to_string(int(r));
  }
}

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw vk_error(std::string("vulkan: ") + what + " failed: " + result_name(r));
}

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT types,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  std::string text = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
  text += (types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT)    ? " [validation] "
          : (types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) ? " [performance] "
                                                                      : " [general] ";
  text += data && data->pMessage ? data->pMessage : "(no text)";
  std::fprintf(stderr, "vulkan %s\n", text.c_str());
  static_cast<validation_log*>(user)->messages.push_back(text);
  return VK_FALSE;  // the call goes on; the test fails on the recorded message
}

std::string version_text(std::uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

const char* device_type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

int device_rank(VkPhysicalDeviceType t) {  // lower is preferred
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

}  // namespace

// ---- context ------------------------------------------------------------------------------------

context::context(validation_log& log) : log_(&log) {
  // IEEE mode: lavapipe's threads inherit the mode of the thread that creates them, and the
  // C++ reference may be running with FTZ|DAZ (fp_mode.hpp).
  vplkit_test::ieee_scope ieee;
  try {
    create_instance();
    pick_device();
    create_device();
  } catch (...) {
    release();
    throw;
  }
}

context::~context() { release(); }

void context::release() noexcept {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
    command_pool_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    if (messenger_) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy) destroy(instance_, messenger_, nullptr);
      messenger_ = VK_NULL_HANDLE;
    }
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

void context::create_instance() {
  std::uint32_t count = 0;
  check(vkEnumerateInstanceLayerProperties(&count, nullptr), "vkEnumerateInstanceLayerProperties");
  std::vector<VkLayerProperties> layers(count);
  check(vkEnumerateInstanceLayerProperties(&count, layers.data()), "vkEnumerateInstanceLayerProperties");
  const auto layer = std::find_if(layers.begin(), layers.end(), [](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, validation_layer) == 0;
  });
  if (layer == layers.end())
    throw vk_error(std::string("vulkan: the layer ") + validation_layer +
                   " is not installed (Debian: apt-get install vulkan-validationlayers; scripts/install-deps.sh "
                   "installs it)");
  std::uint32_t ext_count = 0;
  check(vkEnumerateInstanceExtensionProperties(validation_layer, &ext_count, nullptr),
        "vkEnumerateInstanceExtensionProperties");
  std::vector<VkExtensionProperties> layer_exts(ext_count);
  check(vkEnumerateInstanceExtensionProperties(validation_layer, &ext_count, layer_exts.data()),
        "vkEnumerateInstanceExtensionProperties");
  auto layer_has = [&](const char* name) {
    return std::any_of(layer_exts.begin(), layer_exts.end(),
                       [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
  };
  if (!layer_has(VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
    throw vk_error("vulkan: the validation layer offers no VK_EXT_debug_utils");
  std::vector<const char*> extensions = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  const bool sync = layer_has(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  if (sync) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);

  VkDebugUtilsMessengerCreateInfoEXT messenger{};
  messenger.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  messenger.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = on_message;
  messenger.pUserData = log_;
  // Synchronization validation: a missing barrier between two dispatches is a hazard it reports.
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{};
  features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
  features.pNext = &messenger;  // also reports on vkCreateInstance / vkDestroyInstance
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;

  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "vplkit vulkan tests";
  app.apiVersion = VK_API_VERSION_1_1;  // the kernels are SPIR-V 1.3 (glslangValidator --target-env vulkan1.1)
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pNext = sync ? static_cast<const void*>(&features) : static_cast<const void*>(&messenger);
  info.pApplicationInfo = &app;
  info.enabledLayerCount = 1;
  info.ppEnabledLayerNames = &validation_layer;
  info.enabledExtensionCount = std::uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  const VkResult created = vkCreateInstance(&info, nullptr, &instance_);
  if (created == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw vk_error("vulkan: vkCreateInstance found no Vulkan 1.1 driver (Debian: apt-get install "
                   "mesa-vulkan-drivers gives lavapipe, a CPU implementation)");
  check(created, "vkCreateInstance");
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
  if (!create) throw vk_error("vulkan: vkCreateDebugUtilsMessengerEXT not found");
  check(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  description_ = std::string("; validation layer ") + version_text(layer->specVersion) +
                 (sync ? " with synchronization validation" : "");
}

void context::pick_device() {
  std::uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance_, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  if (count) check(vkEnumeratePhysicalDevices(instance_, &count, devices.data()), "vkEnumeratePhysicalDevices");
  const char* wanted = std::getenv("VPLKIT_VULKAN_DEVICE");
  std::string seen;
  int best_rank = 1 << 30;
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    seen += std::string(seen.empty() ? "" : ", ") + p.deviceName;
    std::uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> families(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, families.data());
    std::uint32_t family = qn;
    for (std::uint32_t i = 0; i < qn && family == qn; ++i)
      if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) family = i;
    if (family == qn || p.apiVersion < VK_API_VERSION_1_1) continue;
    if (wanted && *wanted && std::string(p.deviceName).find(wanted) == std::string::npos) continue;
    const int rank = device_rank(p.deviceType);
    if (rank >= best_rank) continue;
    best_rank = rank;
    physical_ = d;
    queue_family_ = family;
  }
  if (!physical_) {
    std::string msg = "vulkan: no Vulkan 1.1 device with a compute queue";
    if (wanted && *wanted) msg += std::string(" named like VPLKIT_VULKAN_DEVICE='") + wanted + "'";
    msg += " (devices: " + (seen.empty() ? std::string("none") : seen) +
           "; Debian: apt-get install mesa-vulkan-drivers gives lavapipe, a CPU implementation)";
    throw vk_error(msg);
  }
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(physical_, &p);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  VkPhysicalDeviceFeatures f;
  vkGetPhysicalDeviceFeatures(physical_, &f);
  float64_ = f.shaderFloat64 == VK_TRUE;
  description_ = std::string(p.deviceName) + " (" + device_type_name(p.deviceType) + "), Vulkan " +
                 version_text(p.apiVersion) + ", shaderFloat64 " + (float64_ ? "yes" : "no") + description_;
}

void context::create_device() {
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{};
  queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = float64_ ? VK_TRUE : VK_FALSE;  // cdf_build.comp accumulates in double
  VkDeviceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.pEnabledFeatures = &features;
  check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  VkCommandPoolCreateInfo pool{};
  pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool.queueFamilyIndex = queue_family_;
  check(vkCreateCommandPool(device_, &pool, nullptr, &command_pool_), "vkCreateCommandPool");
}

std::uint32_t context::host_memory_type(std::uint32_t type_bits) const {
  const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
  throw vk_error("vulkan: no host-visible, coherent memory type for a buffer");
}

// ---- buffer -------------------------------------------------------------------------------------

buffer::buffer(context& ctx, std::size_t bytes, int fill_byte) : device_(ctx.device()), bytes_(bytes) {
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = std::max<std::size_t>(bytes, 16);  // Vulkan has no empty buffers
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device_, &info, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer_, &req);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  try {
    alloc.memoryTypeIndex = ctx.host_memory_type(req.memoryTypeBits);
    check(vkAllocateMemory(device_, &alloc, nullptr, &memory_), "vkAllocateMemory");
    check(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
    check(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  } catch (...) {
    release();
    throw;
  }
  std::memset(mapped_, fill_byte, info.size);
}

buffer::buffer(buffer&& o) noexcept
    : device_(o.device_), buffer_(o.buffer_), memory_(o.memory_), mapped_(o.mapped_), bytes_(o.bytes_) {
  o.buffer_ = VK_NULL_HANDLE;
  o.memory_ = VK_NULL_HANDLE;
  o.mapped_ = nullptr;
}

buffer::~buffer() { release(); }

void buffer::release() noexcept {
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);  // unmaps
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

// ---- kernel -------------------------------------------------------------------------------------

kernel::kernel(context& ctx, const std::string& name, std::vector<slot> slots)
    : device_(ctx.device()), name_(name), slots_(std::move(slots)) {
  vplkit_test::ieee_scope ieee;
  const std::string path = std::string(VPLKIT_VULKAN_SPIRV_DIR) + "/" + name + ".spv";
  std::ifstream file(path, std::ios::binary);
  if (!file) throw vk_error("vulkan: cannot read " + path);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (bytes.empty() || bytes.size() % 4 != 0) throw vk_error("vulkan: " + path + " is not SPIR-V");
  std::vector<std::uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), bytes.size());
  try {
    VkShaderModuleCreateInfo module{};
    module.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    module.codeSize = bytes.size();
    module.pCode = words.data();
    check(vkCreateShaderModule(device_, &module, nullptr, &module_), ("vkCreateShaderModule(" + name + ")").c_str());

    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (const slot& s : slots_) {
      VkDescriptorSetLayoutBinding b{};
      b.binding = s.binding;
      b.descriptorType =
          s.kind == slot_kind::uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      b.descriptorCount = 1;
      b.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
      bindings.push_back(b);
    }
    VkDescriptorSetLayoutCreateInfo set{};
    set.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set.bindingCount = std::uint32_t(bindings.size());
    set.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(device_, &set, nullptr, &set_layout_),
          ("vkCreateDescriptorSetLayout(" + name + ")").c_str());
    VkPipelineLayoutCreateInfo layout{};
    layout.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout.setLayoutCount = 1;
    layout.pSetLayouts = &set_layout_;
    check(vkCreatePipelineLayout(device_, &layout, nullptr, &layout_), ("vkCreatePipelineLayout(" + name + ")").c_str());
    VkComputePipelineCreateInfo pipeline{};
    pipeline.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    pipeline.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipeline.stage.module = module_;
    pipeline.stage.pName = "main";
    pipeline.layout = layout_;
    check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_),
          ("vkCreateComputePipelines(" + name + ")").c_str());
  } catch (...) {
    release();
    throw;
  }
}

kernel::~kernel() { release(); }

void kernel::release() noexcept {
  if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  if (module_) vkDestroyShaderModule(device_, module_, nullptr);
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}

// ---- dispatch -----------------------------------------------------------------------------------

void run(context& ctx, const std::vector<dispatch_step>& steps) {
  vplkit_test::ieee_scope ieee;
  const VkDevice dev = ctx.device();
  std::uint32_t storage = 0, uniform = 0;
  for (const dispatch_step& s : steps) {
    if (s.buffers.size() != s.k->slots().size())
      throw vk_error("vulkan: " + s.k->name() + " has " + std::to_string(s.k->slots().size()) + " slots, " +
                     std::to_string(s.buffers.size()) + " buffers given");
    for (const slot& sl : s.k->slots()) (sl.kind == slot_kind::uniform ? uniform : storage) += 1;
  }
  std::vector<VkDescriptorPoolSize> sizes;
  if (storage) sizes.push_back({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, storage});
  if (uniform) sizes.push_back({VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniform});
  VkDescriptorPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  pool_info.maxSets = std::uint32_t(steps.size());
  pool_info.poolSizeCount = std::uint32_t(sizes.size());
  pool_info.pPoolSizes = sizes.data();
  VkDescriptorPool pool = VK_NULL_HANDLE;
  check(vkCreateDescriptorPool(dev, &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  try {
    std::vector<VkDescriptorSet> sets(steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const VkDescriptorSetLayout layout = steps[i].k->set_layout();
      VkDescriptorSetAllocateInfo alloc{};
      alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
      alloc.descriptorPool = pool;
      alloc.descriptorSetCount = 1;
      alloc.pSetLayouts = &layout;
      check(vkAllocateDescriptorSets(dev, &alloc, &sets[i]), "vkAllocateDescriptorSets");
      std::vector<VkDescriptorBufferInfo> infos(steps[i].buffers.size());
      std::vector<VkWriteDescriptorSet> writes;
      for (std::size_t b = 0; b < steps[i].buffers.size(); ++b) {
        const bound& bb = steps[i].buffers[b];
        const auto& slots = steps[i].k->slots();
        const auto sl = std::find_if(slots.begin(), slots.end(), [&](const slot& s) { return s.binding == bb.binding; });
        if (sl == slots.end())
          throw vk_error("vulkan: " + steps[i].k->name() + " has no slot at binding " + std::to_string(bb.binding));
        infos[b] = {bb.buf->handle(), 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w{};
        w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w.dstSet = sets[i];
        w.dstBinding = bb.binding;
        w.descriptorCount = 1;
        w.descriptorType =
            sl->kind == slot_kind::uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &infos[b];
        writes.push_back(w);
      }
      vkUpdateDescriptorSets(dev, std::uint32_t(writes.size()), writes.data(), 0, nullptr);
    }

    VkCommandBufferAllocateInfo cmd_info{};
    cmd_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    cmd_info.commandPool = ctx.command_pool();
    cmd_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cmd_info.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(dev, &cmd_info, &cmd), "vkAllocateCommandBuffers");
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const dispatch_step& s = steps[i];
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s.k->pipeline());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, s.k->layout(), 0, 1, &sets[i], 0, nullptr);
      vkCmdDispatch(cmd, s.x, s.y, s.z);
      // The next step reads and writes what this one wrote; the host reads after the last.
      const bool last = i + 1 == steps.size();
      VkMemoryBarrier barrier{};
      barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
      barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT;
      barrier.dstAccessMask = last ? VK_ACCESS_HOST_READ_BIT : VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           last ? VK_PIPELINE_STAGE_HOST_BIT : VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0,
                           nullptr, 0, nullptr);
    }
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    check(vkCreateFence(dev, &fence_info, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(ctx.queue(), 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(dev, 1, &fence, VK_TRUE, 120ull * 1000 * 1000 * 1000), "vkWaitForFences (120 s)");
  } catch (...) {
    vkDeviceWaitIdle(dev);
    if (fence) vkDestroyFence(dev, fence, nullptr);
    if (cmd) vkFreeCommandBuffers(dev, ctx.command_pool(), 1, &cmd);
    vkDestroyDescriptorPool(dev, pool, nullptr);
    throw;
  }
  vkDestroyFence(dev, fence, nullptr);
  vkFreeCommandBuffers(dev, ctx.command_pool(), 1, &cmd);
  vkDestroyDescriptorPool(dev, pool, nullptr);
}

}  // namespace vplkit::vk_test

// SPDX-License-Identifier: MIT
#pragma once
// A small Vulkan compute harness for the Vulkan runtime tests (not part of the library; plain
// Vulkan C API, no window). What a host of the GLSL pack does on Vulkan, and no more:
//  - one instance with VK_LAYER_KHRONOS_validation (and its synchronization validation) and a
//    debug-utils messenger that records every message of severity warning or error;
//  - one device with a compute queue (VPLKIT_VULKAN_DEVICE=<part of the name> picks one; else a
//    GPU before a CPU implementation such as lavapipe), shaderFloat64 enabled where offered;
//  - host-visible, coherent buffers (storage and uniform);
//  - kernels from SPIR-V files, with the descriptor set layout (set 0) the host declares, i.e. the
//    bindings of the kernel's parameter header: the validation layer checks them against the
//    shader's own;
//  - dispatch sequences in one command buffer, a compute-to-compute barrier between steps.
// Missing pieces (no loader, no layer, no device) throw vk_error naming the Debian package.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplkit::vk_test {

class vk_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every message of severity warning or error, as "<severity> [<type>] <text>".
struct validation_log {
  std::vector<std::string> messages;
};

class context {
 public:
  explicit context(validation_log& log);
  ~context();
  context(const context&) = delete;
  context& operator=(const context&) = delete;

  // "<device name> (<type>), Vulkan <api>, driver <version>; validation layer <version> (+ sync)"
  const std::string& describe() const { return description_; }
  bool has_float64() const { return float64_; }

  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return command_pool_; }
  std::uint32_t host_memory_type(std::uint32_t type_bits) const;

 private:
  void create_instance();
  void pick_device();
  void create_device();
  void release() noexcept;

  validation_log* log_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDevice device_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  bool float64_ = false;
  std::string description_;
};

// A host-visible, coherent buffer, mapped for its whole life; usable as storage or uniform buffer.
class buffer {
 public:
  buffer(context& ctx, std::size_t bytes, int fill_byte);
  ~buffer();
  buffer(buffer&& other) noexcept;
  buffer& operator=(buffer&&) = delete;
  buffer(const buffer&) = delete;
  buffer& operator=(const buffer&) = delete;

  static buffer from_bytes(context& ctx, const void* data, std::size_t bytes) {
    buffer b(ctx, bytes, 0);
    if (bytes) std::memcpy(b.mapped_, data, bytes);
    return b;
  }
  template <class T>
  static buffer from_vector(context& ctx, const std::vector<T>& v) {
    return from_bytes(ctx, v.data(), v.size() * sizeof(T));
  }
  template <class T>
  std::vector<T> read() const {
    std::vector<T> out(bytes_ / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), mapped_, out.size() * sizeof(T));
    return out;
  }
  void write_bytes(const void* data, std::size_t bytes) { std::memcpy(mapped_, data, bytes); }

  VkBuffer handle() const { return buffer_; }
  std::size_t size() const { return bytes_; }

 private:
  void release() noexcept;

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  std::size_t bytes_ = 0;
};

// One descriptor of a kernel's set 0.
enum class slot_kind { storage, uniform };
struct slot {
  std::uint32_t binding;
  slot_kind kind;
};

// A compute pipeline from <VPLKIT_VULKAN_SPIRV_DIR>/<name>.spv with the given set-0 layout.
class kernel {
 public:
  kernel(context& ctx, const std::string& name, std::vector<slot> slots);
  ~kernel();
  kernel(const kernel&) = delete;
  kernel& operator=(const kernel&) = delete;

  const std::string& name() const { return name_; }
  const std::vector<slot>& slots() const { return slots_; }
  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkDescriptorSetLayout set_layout() const { return set_layout_; }

 private:
  void release() noexcept;

  VkDevice device_ = VK_NULL_HANDLE;
  std::string name_;
  std::vector<slot> slots_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

struct bound {
  std::uint32_t binding;
  const buffer* buf;
};

struct dispatch_step {
  const kernel* k;
  std::vector<bound> buffers;  // one per slot of the kernel
  std::uint32_t x = 1, y = 1, z = 1;
};

// Records the steps into one command buffer (a compute-to-compute memory barrier between steps, a
// compute-to-host one at the end), submits it and waits.
void run(context& ctx, const std::vector<dispatch_step>& steps);

inline void run(context& ctx, const kernel& k, std::vector<bound> buffers, std::uint32_t x, std::uint32_t y = 1,
                std::uint32_t z = 1) {
  run(ctx, {dispatch_step{&k, std::move(buffers), x, y, z}});
}

inline std::uint32_t groups_for(std::size_t n, std::uint32_t local_size) {
  return std::uint32_t((n + local_size - 1) / local_size);
}

}  // namespace vplkit::vk_test

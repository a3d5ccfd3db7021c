// The headless Vulkan context: instance, the chosen physical device, one queue that does
// graphics and compute, a command pool. No window system anywhere.
#pragma once

#include "gpu/check.h"

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <typeinfo>
#include <vector>

namespace hdof::gpu {

struct ContextOptions {
  // Empty: prefer a discrete GPU, then an integrated one, then anything else (lavapipe).
  // A number picks the device by index; other text picks the first device whose name contains it.
  std::string device;
  bool verbose = false;  // print the devices considered and the one chosen to stderr
  bool validation = HDOF_VALIDATION_DEFAULT;  // use VK_LAYER_KHRONOS_validation when installed
};

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  std::string deviceName() const { return properties_.deviceName; }
  float timestampPeriodNs() const { return properties_.limits.timestampPeriod; }
  bool timestampsSupported() const { return timestampsSupported_; }
  // Reads texels as they are (nearest, clamped): how every pass samples the images of a frame.
  VkSampler nearestSampler() const { return nearestSampler_; }
  // Compiled pipelines, kept for the process: each session's pipelines after the first come from
  // it rather than from the driver's compiler.
  VkPipelineCache pipelineCache() const { return pipelineCache_; }

  // An object that never changes once made, made at the first request for its key and shared by
  // every later one until the context goes: the pipelines and layouts that every session's passes
  // have in common, so that a new session compiles nothing. make() returns the object.
  template <typename T, typename Make>
  std::shared_ptr<const T> shared(const std::string& key, Make&& make) const {
    std::string typedKey = std::string(typeid(T).name()) + '|' + key;
    {
      std::lock_guard lock(sharedMutex_);
      if (auto found = shared_.find(typedKey); found != shared_.end())
        return std::static_pointer_cast<const T>(found->second);
    }
    std::shared_ptr<const void> made = std::make_shared<const T>(make());
    std::lock_guard lock(sharedMutex_);
    return std::static_pointer_cast<const T>(shared_.emplace(typedKey, made).first->second);
  }
  // How many shared objects have been made.
  size_t sharedObjects() const {
    std::lock_guard lock(sharedMutex_);
    return shared_.size();
  }

  // Records commands into a fresh command buffer, submits it and waits for it to finish.
  void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

  // Allocates a primary command buffer from the context's pool (freed with the pool).
  VkCommandBuffer allocateCommandBuffer() const;
  void submit(VkCommandBuffer commandBuffer, VkFence fence) const;

  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred = 0) const;

  // Gives an object a name that validation messages and GPU debuggers show.
  void setName(VkObjectType type, uint64_t handle, const std::string& name) const;

  PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;

 private:
  // Destroys the debug messenger and the instance (also on the constructor's error paths).
  void releaseInstance();

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  VkSampler nearestSampler_ = VK_NULL_HANDLE;
  VkPipelineCache pipelineCache_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memoryProperties_{};
  bool timestampsSupported_ = false;
  PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
  mutable std::mutex sharedMutex_;
  mutable std::map<std::string, std::shared_ptr<const void>> shared_;
};

}  // namespace hdof::gpu

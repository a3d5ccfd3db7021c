// Vulkan error handling: every call that returns a VkResult goes through VK_CHECK, which throws
// VulkanError carrying the result and its name, in release builds too.
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace hdof {

struct VulkanError : std::runtime_error {
  VulkanError(VkResult result, const std::string& what);
  VkResult result;
};

// No usable Vulkan implementation or device: the message says what to install or choose.
struct NoVulkanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The device asked for (--device) does not exist or cannot run hdof: a usage error.
struct DeviceChoiceError : NoVulkanError {
  using NoVulkanError::NoVulkanError;
};

const char* resultName(VkResult result);
[[noreturn]] void throwVulkanError(VkResult result, const char* call, const char* file, int line);

}  // namespace hdof

#define VK_CHECK(call)                                                                           \
  do {                                                                                           \
    VkResult vkCheckResult_ = (call);                                                            \
    if (vkCheckResult_ < 0) ::hdof::throwVulkanError(vkCheckResult_, #call, __FILE__, __LINE__); \
  } while (0)

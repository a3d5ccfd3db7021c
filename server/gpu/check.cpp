#include "gpu/check.h"

#include <cstring>

namespace hdof {

VulkanError::VulkanError(VkResult r, const std::string& what)
    : std::runtime_error(what), result(r) {}

const char* resultName(VkResult result) {
#define HDOF_RESULT_NAME(r) \
  case r:                   \
    return #r;
  switch (result) {
    HDOF_RESULT_NAME(VK_SUCCESS)
    HDOF_RESULT_NAME(VK_NOT_READY)
    HDOF_RESULT_NAME(VK_TIMEOUT)
    HDOF_RESULT_NAME(VK_INCOMPLETE)
    HDOF_RESULT_NAME(VK_ERROR_OUT_OF_HOST_MEMORY)
    HDOF_RESULT_NAME(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    HDOF_RESULT_NAME(VK_ERROR_INITIALIZATION_FAILED)
    HDOF_RESULT_NAME(VK_ERROR_DEVICE_LOST)
    HDOF_RESULT_NAME(VK_ERROR_MEMORY_MAP_FAILED)
    HDOF_RESULT_NAME(VK_ERROR_LAYER_NOT_PRESENT)
    HDOF_RESULT_NAME(VK_ERROR_EXTENSION_NOT_PRESENT)
    HDOF_RESULT_NAME(VK_ERROR_FEATURE_NOT_PRESENT)
    HDOF_RESULT_NAME(VK_ERROR_INCOMPATIBLE_DRIVER)
    HDOF_RESULT_NAME(VK_ERROR_TOO_MANY_OBJECTS)
    HDOF_RESULT_NAME(VK_ERROR_FORMAT_NOT_SUPPORTED)
    HDOF_RESULT_NAME(VK_ERROR_FRAGMENTED_POOL)
    HDOF_RESULT_NAME(VK_ERROR_OUT_OF_POOL_MEMORY)
    HDOF_RESULT_NAME(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    HDOF_RESULT_NAME(VK_ERROR_FRAGMENTATION)
    HDOF_RESULT_NAME(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    HDOF_RESULT_NAME(VK_ERROR_UNKNOWN)
    default:
      return "VK_ERROR_(unnamed)";
  }
#undef HDOF_RESULT_NAME
}

void throwVulkanError(VkResult result, const char* call, const char* file, int line) {
  const char* base = std::strrchr(file, '/');
  std::string where = std::string(base ? base + 1 : file) + ":" + std::to_string(line);
  throw VulkanError(result, std::string("Vulkan call failed with ") + resultName(result) + " (" +
                                call + " at " + where + ")");
}

}  // namespace hdof

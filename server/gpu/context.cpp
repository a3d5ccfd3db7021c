#include "gpu/context.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace hdof::gpu {
namespace {

const char* const kRequiredDeviceExtensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};

struct Candidate {
  VkPhysicalDevice device;
  VkPhysicalDeviceProperties properties;
  uint32_t queueFamily = 0;
  std::string rejection;  // empty: usable
};

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

const char* typeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, name) == 0;
  });
}

bool hasInstanceExtension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void*) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
    std::fprintf(stderr, "vulkan: %s\n", data->pMessage);
  return VK_FALSE;
}

// Says why a device cannot run hdof, or returns an empty string.
std::string checkDevice(VkPhysicalDevice device, const VkPhysicalDeviceProperties& properties,
                        uint32_t& queueFamily) {
  if (properties.apiVersion < VK_API_VERSION_1_2) return "supports only Vulkan 1.0/1.1, needs 1.2";
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  bool found = false;
  for (uint32_t i = 0; i < count && !found; ++i) {
    if ((families[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
        (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
      queueFamily = i;
      found = true;
    }
  }
  if (!found) return "has no queue that does both graphics and compute";

  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  for (const char* required : kRequiredDeviceExtensions) {
    bool present = std::any_of(extensions.begin(), extensions.end(), [&](auto& e) {
      return std::strcmp(e.extensionName, required) == 0;
    });
    if (!present) return std::string("lacks the extension ") + required;
  }

  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  vkGetPhysicalDeviceFeatures2(device, &features);
  if (!features.features.shaderStorageImageWriteWithoutFormat)
    return "lacks the shaderStorageImageWriteWithoutFormat feature";

  // The ray mask's compaction and the selective trace share work across a subgroup.
  VkPhysicalDeviceSubgroupProperties subgroup{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
                                          &subgroup};
  vkGetPhysicalDeviceProperties2(device, &properties2);
  constexpr VkSubgroupFeatureFlags kSubgroupOperations =
      VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT |
      VK_SUBGROUP_FEATURE_SHUFFLE_BIT | VK_SUBGROUP_FEATURE_SHUFFLE_RELATIVE_BIT;
  if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
      (subgroup.supportedOperations & kSubgroupOperations) != kSubgroupOperations)
    return "lacks subgroup ballot, arithmetic or shuffle operations in compute shaders";

  // A still view's raster takes 4 samples per pixel where the resolve knows them to lie.
  const VkPhysicalDeviceLimits& limits = properties2.properties.limits;
  if (!limits.standardSampleLocations || !(limits.framebufferColorSampleCounts & 4) ||
      !(limits.framebufferDepthSampleCounts & 4) || !(limits.sampledImageColorSampleCounts & 4))
    return "lacks 4x multisampling at the standard sample locations";
  return "";
}

}  // namespace

Context::Context(const ContextOptions& options) {
  uint32_t loaderVersion = 0;
  if (vkEnumerateInstanceVersion(&loaderVersion) != VK_SUCCESS ||
      loaderVersion < VK_API_VERSION_1_2)
    throw NoVulkanError(
        "no Vulkan 1.2 loader found: install a Vulkan driver (on Debian: apt-get install "
        "libvulkan1 mesa-vulkan-drivers)");

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "hdof";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  bool debugUtils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  bool validation = options.validation && hasLayer("VK_LAYER_KHRONOS_validation");
  if (validation) layers.push_back("VK_LAYER_KHRONOS_validation");
  VkInstanceCreateInfo instanceInfo{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instanceInfo.pApplicationInfo = &app;
  instanceInfo.enabledLayerCount = static_cast<uint32_t>(layers.size());
  instanceInfo.ppEnabledLayerNames = layers.data();
  instanceInfo.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  instanceInfo.ppEnabledExtensionNames = extensions.data();
  VkResult created = vkCreateInstance(&instanceInfo, nullptr, &instance_);
  if (created == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw NoVulkanError(
        "no Vulkan driver found: install one (on Debian: apt-get install mesa-vulkan-drivers for "
        "the lavapipe software device, or your GPU vendor's driver)");
  VK_CHECK(created);

  if (validation) {
    auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT info{
        VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    info.pfnUserCallback = onValidationMessage;
    if (createMessenger) VK_CHECK(createMessenger(instance_, &info, nullptr, &messenger_));
  }
  if (debugUtils)
    setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));

  uint32_t count = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &count, devices.data()));
  if (devices.empty()) {
    releaseInstance();
    throw NoVulkanError(
        "no Vulkan device found: install a driver (on Debian: apt-get install "
        "mesa-vulkan-drivers)");
  }
  std::vector<Candidate> candidates;
  for (VkPhysicalDevice d : devices) {
    Candidate c{d, {}};
    vkGetPhysicalDeviceProperties(d, &c.properties);
    c.rejection = checkDevice(d, c.properties, c.queueFamily);
    candidates.push_back(c);
  }
  if (options.verbose)
    for (size_t i = 0; i < candidates.size(); ++i)
      std::fprintf(stderr, "device %zu: %s (%s)%s%s\n", i, candidates[i].properties.deviceName,
                   typeName(candidates[i].properties.deviceType),
                   candidates[i].rejection.empty() ? "" : ": unusable, ",
                   candidates[i].rejection.c_str());

  const Candidate* chosen = nullptr;
  if (!options.device.empty()) {
    bool isIndex = std::all_of(options.device.begin(), options.device.end(), ::isdigit);
    for (size_t i = 0; i < candidates.size() && !chosen; ++i) {
      bool match = isIndex
                       ? std::to_string(i) == options.device
                       : std::string(candidates[i].properties.deviceName).find(options.device) !=
                             std::string::npos;
      if (match) chosen = &candidates[i];
    }
    if (!chosen) {
      std::string names;
      for (size_t i = 0; i < candidates.size(); ++i)
        names += (i ? ", " : "") + std::to_string(i) + ": " + candidates[i].properties.deviceName;
      releaseInstance();
      throw DeviceChoiceError("no Vulkan device matches '" + options.device +
                              "' (devices: " + names + ")");
    }
    if (!chosen->rejection.empty()) {
      std::string message = std::string("device ") + chosen->properties.deviceName + " " +
                            chosen->rejection + "; pick another with --device";
      releaseInstance();
      throw DeviceChoiceError(message);
    }
  } else {
    for (const Candidate& c : candidates)
      if (c.rejection.empty() &&
          (!chosen || typeRank(c.properties.deviceType) < typeRank(chosen->properties.deviceType)))
        chosen = &c;
    if (!chosen) {
      std::string message =
          "no usable Vulkan device: " + std::string(candidates[0].properties.deviceName) + " " +
          candidates[0].rejection + " (on Debian: apt-get install mesa-vulkan-drivers)";
      releaseInstance();
      throw NoVulkanError(message);
    }
  }
  physicalDevice_ = chosen->device;
  properties_ = chosen->properties;
  queueFamily_ = chosen->queueFamily;
  vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);
  if (options.verbose)
    std::fprintf(stderr, "using device: %s (%s, Vulkan %u.%u)\n", properties_.deviceName,
                 typeName(properties_.deviceType), VK_API_VERSION_MAJOR(properties_.apiVersion),
                 VK_API_VERSION_MINOR(properties_.apiVersion));

  uint32_t familyCount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &familyCount, nullptr);
  std::vector<VkQueueFamilyProperties> families(familyCount);
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &familyCount, families.data());
  timestampsSupported_ =
      families[queueFamily_].timestampValidBits > 0 && properties_.limits.timestampPeriod > 0.0f;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.features.shaderStorageImageWriteWithoutFormat = VK_TRUE;
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  deviceInfo.enabledExtensionCount = std::size(kRequiredDeviceExtensions);
  deviceInfo.ppEnabledExtensionNames = kRequiredDeviceExtensions;
  VK_CHECK(vkCreateDevice(physicalDevice_, &deviceInfo, nullptr, &device_));
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  cmdPushDescriptorSet = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
      vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = queueFamily_;
  VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_));

  VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
  samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
      VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VK_CHECK(vkCreateSampler(device_, &samplerInfo, nullptr, &nearestSampler_));
  VkPipelineCacheCreateInfo cacheInfo{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  VK_CHECK(vkCreatePipelineCache(device_, &cacheInfo, nullptr, &pipelineCache_));
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    shared_.clear();
    vkDestroyPipelineCache(device_, pipelineCache_, nullptr);
    vkDestroySampler(device_, nearestSampler_, nullptr);
    vkDestroyCommandPool(device_, commandPool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  releaseInstance();
}

void Context::releaseInstance() {
  if (messenger_) {
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroyMessenger) destroyMessenger(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
}

VkCommandBuffer Context::allocateCommandBuffer() const {
  VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  info.commandPool = commandPool_;
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateCommandBuffers(device_, &info, &commandBuffer));
  return commandBuffer;
}

void Context::submit(VkCommandBuffer commandBuffer, VkFence fence) const {
  VkSubmitInfo submitInfo{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submitInfo.commandBufferCount = 1;
  submitInfo.pCommandBuffers = &commandBuffer;
  VK_CHECK(vkQueueSubmit(queue_, 1, &submitInfo, fence));
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const {
  VkCommandBuffer commandBuffer = allocateCommandBuffer();
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(commandBuffer, &begin));
  record(commandBuffer);
  VK_CHECK(vkEndCommandBuffer(commandBuffer));
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFence(device_, &fenceInfo, nullptr, &fence));
  submit(commandBuffer, fence);
  VkResult waited = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, commandPool_, 1, &commandBuffer);
  VK_CHECK(waited);
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred) const {
  uint32_t fallback = UINT32_MAX;
  for (uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
    if (!(typeBits & (1u << i))) continue;
    VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (fallback == UINT32_MAX) fallback = i;
  }
  if (fallback == UINT32_MAX)
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "no suitable memory type");
  return fallback;
}

void Context::setName(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!setObjectName_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  setObjectName_(device_, &info);
}

}  // namespace hdof::gpu

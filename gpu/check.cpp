#include "gpu/check.h"

namespace stsv {

std::string toString(VkResult result) {
    switch (result) {
#define STSV_CASE(x)                                                                                         \
    case x:                                                                                                  \
        return #x;
        STSV_CASE(VK_SUCCESS)
        STSV_CASE(VK_NOT_READY)
        STSV_CASE(VK_TIMEOUT)
        STSV_CASE(VK_EVENT_SET)
        STSV_CASE(VK_EVENT_RESET)
        STSV_CASE(VK_INCOMPLETE)
        STSV_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        STSV_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        STSV_CASE(VK_ERROR_INITIALIZATION_FAILED)
        STSV_CASE(VK_ERROR_DEVICE_LOST)
        STSV_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        STSV_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        STSV_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        STSV_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        STSV_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        STSV_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        STSV_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        STSV_CASE(VK_ERROR_FRAGMENTED_POOL)
        STSV_CASE(VK_ERROR_UNKNOWN)
        STSV_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        STSV_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        STSV_CASE(VK_ERROR_FRAGMENTATION)
        STSV_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        STSV_CASE(VK_PIPELINE_COMPILE_REQUIRED)
        STSV_CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef STSV_CASE
    default:
        return "VkResult(" + std::to_string(static_cast<int>(result)) + ")";
    }
}

VulkanError::VulkanError(VkResult result, const std::string& expression, const char* file, int line)
    : Error("Vulkan call failed with " + toString(result) + ": " + expression + " at " + file + ":" +
            std::to_string(line)),
      m_result(result), m_expression(expression) {}

} // namespace stsv

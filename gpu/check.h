// Vulkan error checking (DESIGN §7, STYLE §6): every failing call becomes a VulkanError that
// names the VkResult, the expression and the place.
#pragma once

#include "core/error.h"

#include "gpu/vulkan.h"

#include <string>

namespace stsv {

/// A Vulkan call returned an error code.
class VulkanError : public Error {
  public:
    VulkanError(VkResult result, const std::string& expression, const char* file, int line);

    VkResult result() const { return m_result; }
    const std::string& expression() const { return m_expression; }

  private:
    VkResult m_result;
    std::string m_expression;
};

/// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.; the number for codes this build does not know.
std::string toString(VkResult result);

} // namespace stsv

/// Evaluates a VkResult expression and throws VulkanError unless it is VK_SUCCESS.
/// (Non-error status codes such as VK_INCOMPLETE or VK_NOT_READY are errors here; call sites
/// that expect them test the result themselves.)
#define STSV_VK_CHECK(expr)                                                                                  \
    do {                                                                                                     \
        const VkResult stsvVkResult_ = (expr);                                                               \
        if (stsvVkResult_ != VK_SUCCESS)                                                                     \
            throw ::stsv::VulkanError(stsvVkResult_, #expr, __FILE__, __LINE__);                             \
    } while (false)

// The Vulkan API as stsv calls it: the headers without prototypes, and one function pointer per
// entry point, filled from the Vulkan loader (libvulkan.so.1) the first time a device or the
// device list is asked for (loadVulkan). Nothing links the loader, so the program starts and
// `--backend cpu` renders on a machine without one. Include this instead of <vulkan/vulkan.h>.
#pragma once

// Prototypes would turn a call into a jump to the pointer's own address.
#if defined(VULKAN_CORE_H_) && !defined(VK_NO_PROTOTYPES)
#error "<vulkan/vulkan.h> was included with prototypes before gpu/vulkan.h"
#endif
#ifndef VK_NO_PROTOTYPES
#define VK_NO_PROTOTYPES
#endif
#include <vulkan/vulkan.h>

/// Every Vulkan 1.3 core entry point stsv calls (extensions' come from vkGet*ProcAddr).
#define STSV_VULKAN_FUNCTIONS(X)                                                                             \
    X(vkAllocateCommandBuffers)                                                                              \
    X(vkAllocateDescriptorSets)                                                                              \
    X(vkAllocateMemory)                                                                                      \
    X(vkBeginCommandBuffer)                                                                                  \
    X(vkBindBufferMemory)                                                                                    \
    X(vkBindImageMemory)                                                                                     \
    X(vkCmdBeginRendering)                                                                                   \
    X(vkCmdBindDescriptorSets)                                                                               \
    X(vkCmdBindPipeline)                                                                                     \
    X(vkCmdBindVertexBuffers)                                                                                \
    X(vkCmdClearColorImage)                                                                                  \
    X(vkCmdCopyBuffer)                                                                                       \
    X(vkCmdCopyBufferToImage)                                                                                \
    X(vkCmdCopyImageToBuffer)                                                                                \
    X(vkCmdCopyQueryPoolResults)                                                                             \
    X(vkCmdDispatch)                                                                                         \
    X(vkCmdDispatchIndirect)                                                                                 \
    X(vkCmdDraw)                                                                                             \
    X(vkCmdDrawIndirect)                                                                                     \
    X(vkCmdEndRendering)                                                                                     \
    X(vkCmdFillBuffer)                                                                                       \
    X(vkCmdPipelineBarrier2)                                                                                 \
    X(vkCmdPushConstants)                                                                                    \
    X(vkCmdResetQueryPool)                                                                                   \
    X(vkCmdSetScissor)                                                                                       \
    X(vkCmdSetViewport)                                                                                      \
    X(vkCmdWriteTimestamp2)                                                                                  \
    X(vkCreateBuffer)                                                                                        \
    X(vkCreateBufferView)                                                                                    \
    X(vkCreateCommandPool)                                                                                   \
    X(vkCreateComputePipelines)                                                                              \
    X(vkCreateDescriptorPool)                                                                                \
    X(vkCreateDescriptorSetLayout)                                                                           \
    X(vkCreateDevice)                                                                                        \
    X(vkCreateFence)                                                                                         \
    X(vkCreateGraphicsPipelines)                                                                             \
    X(vkCreateImage)                                                                                         \
    X(vkCreateImageView)                                                                                     \
    X(vkCreateInstance)                                                                                      \
    X(vkCreatePipelineLayout)                                                                                \
    X(vkCreateQueryPool)                                                                                     \
    X(vkCreateSampler)                                                                                       \
    X(vkCreateShaderModule)                                                                                  \
    X(vkDestroyBuffer)                                                                                       \
    X(vkDestroyBufferView)                                                                                   \
    X(vkDestroyCommandPool)                                                                                  \
    X(vkDestroyDescriptorPool)                                                                               \
    X(vkDestroyDescriptorSetLayout)                                                                          \
    X(vkDestroyDevice)                                                                                       \
    X(vkDestroyFence)                                                                                        \
    X(vkDestroyImage)                                                                                        \
    X(vkDestroyImageView)                                                                                    \
    X(vkDestroyInstance)                                                                                     \
    X(vkDestroyPipeline)                                                                                     \
    X(vkDestroyPipelineLayout)                                                                               \
    X(vkDestroyQueryPool)                                                                                    \
    X(vkDestroySampler)                                                                                      \
    X(vkDestroyShaderModule)                                                                                 \
    X(vkDeviceWaitIdle)                                                                                      \
    X(vkEndCommandBuffer)                                                                                    \
    X(vkEnumerateDeviceExtensionProperties)                                                                  \
    X(vkEnumerateInstanceLayerProperties)                                                                    \
    X(vkEnumeratePhysicalDevices)                                                                            \
    X(vkFreeMemory)                                                                                          \
    X(vkGetBufferDeviceAddress)                                                                              \
    X(vkGetBufferMemoryRequirements)                                                                         \
    X(vkGetDeviceProcAddr)                                                                                   \
    X(vkGetDeviceQueue)                                                                                      \
    X(vkGetImageMemoryRequirements)                                                                          \
    X(vkGetInstanceProcAddr)                                                                                 \
    X(vkGetPhysicalDeviceFeatures2)                                                                          \
    X(vkGetPhysicalDeviceFormatProperties)                                                                   \
    X(vkGetPhysicalDeviceMemoryProperties)                                                                   \
    X(vkGetPhysicalDeviceProperties)                                                                         \
    X(vkGetPhysicalDeviceProperties2)                                                                        \
    X(vkGetPhysicalDeviceQueueFamilyProperties)                                                              \
    X(vkGetQueryPoolResults)                                                                                 \
    X(vkMapMemory)                                                                                           \
    X(vkQueueSubmit2)                                                                                        \
    X(vkResetCommandBuffer)                                                                                  \
    X(vkResetFences)                                                                                         \
    X(vkUpdateDescriptorSets)                                                                                \
    X(vkWaitForFences)

#define STSV_DECLARE_VULKAN_FUNCTION(name) extern PFN_##name name;
STSV_VULKAN_FUNCTIONS(STSV_DECLARE_VULKAN_FUNCTION)
#undef STSV_DECLARE_VULKAN_FUNCTION

namespace stsv {

/// The environment variable that names the loader to open instead of libvulkan.so.1 (a path or
/// a library name).
inline constexpr const char* VULKAN_LOADER_ENV = "STSV_VULKAN_LOADER";

/// Opens the Vulkan loader and fills the function pointers, once per process (thread-safe).
/// Error naming the library when it cannot be opened (no loader installed: use --backend cpu
/// or install libvulkan1) or lacks an entry point (a loader older than Vulkan 1.3).
void loadVulkan();

} // namespace stsv

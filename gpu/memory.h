// Device memory: one plain allocation per resource (no sub-allocator; fine at this scale).
#pragma once

#include "gpu/vulkan.h"

namespace stsv {

class Device;

enum class MemoryUsage {
    DeviceLocal,  ///< GPU-only; filled and read back through staging copies
    HostToDevice, ///< host-visible and coherent, persistently mapped; uploads every frame
    DeviceToHost, ///< host-visible and coherent (cached where possible), mapped; readback
};

inline bool isHostVisible(MemoryUsage usage) {
    return usage != MemoryUsage::DeviceLocal;
}

/// Allocates memory for `requirements` with the property flags `usage` asks for; with
/// `deviceAddress`, memory a buffer's device address can point into (bufferDeviceAddress).
VkDeviceMemory allocateMemory(const Device& device, const VkMemoryRequirements& requirements,
                              MemoryUsage usage, bool deviceAddress = false);

} // namespace stsv

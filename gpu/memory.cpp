#include "gpu/memory.h"

#include "gpu/check.h"
#include "gpu/device.h"

namespace stsv {

VkDeviceMemory allocateMemory(const Device& device, const VkMemoryRequirements& requirements,
                              MemoryUsage usage, bool deviceAddress) {
    VkMemoryPropertyFlags required = 0;
    VkMemoryPropertyFlags preferred = 0;
    switch (usage) {
    case MemoryUsage::DeviceLocal:
        required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    case MemoryUsage::HostToDevice:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    case MemoryUsage::DeviceToHost:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    VkMemoryAllocateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = device.findMemoryType(requirements.memoryTypeBits, required, preferred);
    VkMemoryAllocateFlagsInfo flags{};
    flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    if (deviceAddress) info.pNext = &flags;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    STSV_VK_CHECK(vkAllocateMemory(device.handle(), &info, nullptr, &memory));
    return memory;
}

} // namespace stsv

#include "render/gpu_deferred.h"

#include "gpu/device.h"
#include "render/gpu_frame_dh.h"

#include <algorithm>

namespace stsv {

namespace {
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
}

DeferredFragments::DeferredFragments(const Device& device, const RenderOptions& options,
                                     std::uint64_t capacity, bool withMaskWords)
    : m_device(&device) {
    count = Buffer(device, 16, STORAGE, MemoryUsage::DeviceLocal);
    resize(capacity);
    const std::uint64_t words = withMaskWords && capacity > 0
                                    ? std::uint64_t(options.width) * std::uint64_t(options.height) *
                                          lsMaskWordCount(uint(options.samples))
                                    : 1;
    maskWords = Buffer(device, words * 4, STORAGE, MemoryUsage::DeviceLocal);
}

std::uint32_t deferredSampleGroups(const Device& device) {
    return device.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 256 : 8192;
}

void DeferredFragments::resize(std::uint64_t capacity) {
    m_capacity = capacity;
    fragments =
        Buffer(*m_device, std::max<std::uint64_t>(capacity, 1) * 8, STORAGE, MemoryUsage::DeviceLocal);
}

std::vector<DescriptorBinding> DeferredFragments::bindings() {
    return {{GPU_BINDING_DEFERRED_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_DEFERRED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_STSV_MASK_WORDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void DeferredFragments::writeDescriptors(DescriptorSet& set) const {
    set.writeBuffer(GPU_BINDING_DEFERRED_COUNT, count);
    set.writeBuffer(GPU_BINDING_DEFERRED, fragments);
    set.writeBuffer(GPU_BINDING_STSV_MASK_WORDS, maskWords);
}

} // namespace stsv

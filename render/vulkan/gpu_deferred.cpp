#include "render/vulkan/gpu_deferred.h"

#include "core/error.h"
#include "gpu/device.h"
#include "render/vulkan/gpu_volumes_dh.h"

#include <algorithm>
#include <string>

namespace stsv {

namespace {
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
/// A fragment's term record.
constexpr std::uint64_t TERM_BYTES = 16 * std::uint64_t(GPU_DEFERRED_TERM_TEXELS);
} // namespace

DeferredFragments::DeferredFragments(const Device& device, const RenderOptions& options,
                                     std::uint64_t initialCapacity, std::uint64_t maxCapacity)
    : m_device(&device),
      // No more than one storage buffer binding addresses (128 MiB, 16.8 M pairs, on lavapipe).
      m_maxCapacity(std::min<std::uint64_t>(maxCapacity > 0 ? maxCapacity : MAX_DEFERRED_FRAGMENTS,
                                            device.limits().maxStorageBufferRange / 8)),
      m_initialCapacity(std::min(initialCapacity, m_maxCapacity)),
      m_maskWordCount(std::uint64_t(options.width) * std::uint64_t(options.height) *
                      lsMaskWordCount(uint(options.samples))) {
    count = Buffer(device, 16, STORAGE, MemoryUsage::DeviceLocal);
    resize(0);
    maskWords = Buffer(device, 4, STORAGE, MemoryUsage::DeviceLocal);
}

void DeferredFragments::use(bool withMaskWords, bool withTerms) {
    if (withTerms && !m_terms) {
        m_terms = true;
        m_maxCapacity =
            std::min<std::uint64_t>(m_maxCapacity, m_device->limits().maxStorageBufferRange / TERM_BYTES);
        m_initialCapacity = std::min(m_initialCapacity, m_maxCapacity);
        if (m_capacity > 0) resize(std::min(m_capacity, m_maxCapacity));
    }
    if (m_capacity == 0) resize(m_initialCapacity);
    if (withMaskWords && !m_maskWords) {
        m_maskWords = true;
        maskWords = Buffer(*m_device, m_maskWordCount * 4, STORAGE, MemoryUsage::DeviceLocal);
    }
}

bool DeferredFragments::growFor(std::uint64_t listed) {
    if (listed <= m_capacity) return false;
    if (listed > m_maxCapacity)
        throw Error("a volume pass lists " + std::to_string(listed) +
                    " fragments for one light, more than the " + std::to_string(m_maxCapacity) +
                    " its list may hold; render a smaller --size");
    resize(std::min(listed + listed / 4, m_maxCapacity));
    return true;
}

std::uint32_t deferredSampleGroups(const Device& device, std::uint64_t capacity, int samples) {
    if (device.info().type != VK_PHYSICAL_DEVICE_TYPE_CPU) return 8192;
    const std::uint64_t perThread =
        std::max<std::uint64_t>(SAMPLE_LOOP_BUDGET / (2 * std::uint64_t(samples) + 16), 1);
    const std::uint64_t groups = (capacity + 64 * perThread - 1) / (64 * perThread);
    return static_cast<std::uint32_t>(std::clamp<std::uint64_t>(groups, 256, 65535));
}

void DeferredFragments::resize(std::uint64_t capacity) {
    m_capacity = capacity;
    fragments =
        Buffer(*m_device, std::max<std::uint64_t>(capacity, 1) * 8, STORAGE, MemoryUsage::DeviceLocal);
    terms = Buffer(*m_device, m_terms ? std::max<std::uint64_t>(capacity, 1) * TERM_BYTES : TERM_BYTES,
                   STORAGE, MemoryUsage::DeviceLocal);
}

std::vector<DescriptorBinding> DeferredFragments::bindings() {
    return {{GPU_BINDING_DEFERRED_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_DEFERRED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_DEFERRED_TERMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void DeferredFragments::writeDescriptors(DescriptorSet& set) const {
    set.writeBuffer(GPU_BINDING_DEFERRED_COUNT, count);
    set.writeBuffer(GPU_BINDING_DEFERRED, fragments);
    set.writeBuffer(GPU_BINDING_DEFERRED_TERMS, terms);
}

} // namespace stsv

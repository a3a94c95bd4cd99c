#include "gpu/descriptors.h"

#include "gpu/buffer.h"
#include "gpu/check.h"
#include "gpu/device.h"
#include "gpu/image.h"

#include <map>
#include <string>
#include <utility>

namespace stsv {

DescriptorSetLayout::DescriptorSetLayout(const Device& device, std::vector<DescriptorBinding> bindings)
    : m_device(&device), m_bindings(std::move(bindings)) {
    std::vector<VkDescriptorSetLayoutBinding> vkBindings;
    for (const DescriptorBinding& b : m_bindings)
        vkBindings.push_back({b.binding, b.type, b.count, b.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    info.bindingCount = uint32_t(vkBindings.size());
    info.pBindings = vkBindings.data();
    STSV_VK_CHECK(vkCreateDescriptorSetLayout(device.handle(), &info, nullptr, &m_layout));
}

DescriptorSetLayout::~DescriptorSetLayout() {
    destroy();
}

DescriptorSetLayout::DescriptorSetLayout(DescriptorSetLayout&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)),
      m_layout(std::exchange(other.m_layout, VK_NULL_HANDLE)), m_bindings(std::move(other.m_bindings)) {}

DescriptorSetLayout& DescriptorSetLayout::operator=(DescriptorSetLayout&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_layout = std::exchange(other.m_layout, VK_NULL_HANDLE);
        m_bindings = std::move(other.m_bindings);
    }
    return *this;
}

void DescriptorSetLayout::destroy() noexcept {
    if (m_device != nullptr && m_layout != VK_NULL_HANDLE)
        vkDestroyDescriptorSetLayout(m_device->handle(), m_layout, nullptr);
    m_layout = VK_NULL_HANDLE;
    m_device = nullptr;
}

const DescriptorBinding& DescriptorSetLayout::binding(uint32_t index) const {
    for (const DescriptorBinding& b : m_bindings)
        if (b.binding == index) return b;
    throw UsageError("descriptor set layout has no binding " + std::to_string(index));
}

DescriptorSet::DescriptorSet(const Device& device, const DescriptorSetLayout& layout)
    : m_device(&device), m_bindings(layout.bindings()) {
    std::map<VkDescriptorType, uint32_t> counts;
    for (const DescriptorBinding& b : layout.bindings()) counts[b.type] += b.count;
    std::vector<VkDescriptorPoolSize> sizes;
    sizes.reserve(counts.size());
    for (const auto& [type, count] : counts) sizes.push_back({type, count});
    VkDescriptorPoolCreateInfo poolInfo{};
    poolInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = uint32_t(sizes.size());
    poolInfo.pPoolSizes = sizes.data();
    STSV_VK_CHECK(vkCreateDescriptorPool(device.handle(), &poolInfo, nullptr, &m_pool));
    VkDescriptorSetAllocateInfo allocInfo{};
    allocInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    allocInfo.descriptorPool = m_pool;
    allocInfo.descriptorSetCount = 1;
    VkDescriptorSetLayout layoutHandle = layout.handle();
    allocInfo.pSetLayouts = &layoutHandle;
    try {
        STSV_VK_CHECK(vkAllocateDescriptorSets(device.handle(), &allocInfo, &m_set));
    } catch (...) {
        destroy();
        throw;
    }
}

DescriptorSet::~DescriptorSet() {
    destroy();
}

DescriptorSet::DescriptorSet(DescriptorSet&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)), m_bindings(std::move(other.m_bindings)),
      m_pool(std::exchange(other.m_pool, VK_NULL_HANDLE)), m_set(std::exchange(other.m_set, VK_NULL_HANDLE)) {
}

DescriptorSet& DescriptorSet::operator=(DescriptorSet&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_bindings = std::move(other.m_bindings);
        m_pool = std::exchange(other.m_pool, VK_NULL_HANDLE);
        m_set = std::exchange(other.m_set, VK_NULL_HANDLE);
    }
    return *this;
}

void DescriptorSet::destroy() noexcept {
    if (m_device != nullptr && m_pool != VK_NULL_HANDLE)
        vkDestroyDescriptorPool(m_device->handle(), m_pool, nullptr); // frees the set
    m_pool = VK_NULL_HANDLE;
    m_set = VK_NULL_HANDLE;
    m_device = nullptr;
}

VkDescriptorType DescriptorSet::typeOf(uint32_t binding) const {
    for (const DescriptorBinding& b : m_bindings)
        if (b.binding == binding) return b.type;
    throw UsageError("descriptor set has no binding " + std::to_string(binding));
}

void DescriptorSet::write(uint32_t binding, uint32_t arrayElement, const VkDescriptorBufferInfo* buffer,
                          const VkDescriptorImageInfo* image, const VkBufferView* texels) {
    VkWriteDescriptorSet write{};
    write.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    write.dstSet = m_set;
    write.dstBinding = binding;
    write.dstArrayElement = arrayElement;
    write.descriptorCount = 1;
    write.descriptorType = typeOf(binding);
    write.pBufferInfo = buffer;
    write.pImageInfo = image;
    write.pTexelBufferView = texels;
    vkUpdateDescriptorSets(m_device->handle(), 1, &write, 0, nullptr);
}

void DescriptorSet::writeBuffer(uint32_t binding, const Buffer& buffer, VkDeviceSize offset,
                                VkDeviceSize range, uint32_t arrayElement) {
    const VkDescriptorBufferInfo info{buffer.handle(), offset, range};
    write(binding, arrayElement, &info, nullptr);
}

void DescriptorSet::writeTexelBuffer(uint32_t binding, VkBufferView view, uint32_t arrayElement) {
    write(binding, arrayElement, nullptr, nullptr, &view);
}

void DescriptorSet::writeStorageImage(uint32_t binding, const Image& image, VkImageLayout layout,
                                      uint32_t arrayElement) {
    writeSampledImage(binding, image.view(), VK_NULL_HANDLE, layout, arrayElement);
}

void DescriptorSet::writeSampledImage(uint32_t binding, VkImageView view, VkSampler sampler,
                                      VkImageLayout layout, uint32_t arrayElement) {
    const VkDescriptorImageInfo info{sampler, view, layout};
    write(binding, arrayElement, nullptr, &info);
}

} // namespace stsv

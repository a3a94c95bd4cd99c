// Descriptor set layouts and sets. Binding indices come from the *_dh.h headers (DESIGN §3).
#pragma once

#include "gpu/vulkan.h"

#include <cstdint>
#include <vector>

namespace stsv {

class Buffer;
class Device;
class Image;

struct DescriptorBinding {
    uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkShaderStageFlags stages = VK_SHADER_STAGE_ALL;
    uint32_t count = 1;
};

/// Move-only VkDescriptorSetLayout that remembers its bindings.
class DescriptorSetLayout {
  public:
    DescriptorSetLayout() = default;
    DescriptorSetLayout(const Device& device, std::vector<DescriptorBinding> bindings);
    ~DescriptorSetLayout();
    DescriptorSetLayout(DescriptorSetLayout&& other) noexcept;
    DescriptorSetLayout& operator=(DescriptorSetLayout&& other) noexcept;

    VkDescriptorSetLayout handle() const { return m_layout; }
    const std::vector<DescriptorBinding>& bindings() const { return m_bindings; }
    /// The binding's declaration; UsageError when the layout has no such binding.
    const DescriptorBinding& binding(uint32_t index) const;

  private:
    const Device* m_device = nullptr;
    VkDescriptorSetLayout m_layout = VK_NULL_HANDLE;
    std::vector<DescriptorBinding> m_bindings;

    void destroy() noexcept;
};

/// One descriptor set in its own pool, sized for the layout. Move-only.
class DescriptorSet {
  public:
    DescriptorSet() = default;
    DescriptorSet(const Device& device, const DescriptorSetLayout& layout);
    ~DescriptorSet();
    DescriptorSet(DescriptorSet&& other) noexcept;
    DescriptorSet& operator=(DescriptorSet&& other) noexcept;

    VkDescriptorSet handle() const { return m_set; }

    /// Storage or uniform buffer (the type the layout declares), whole buffer by default.
    void writeBuffer(uint32_t binding, const Buffer& buffer, VkDeviceSize offset = 0,
                     VkDeviceSize range = VK_WHOLE_SIZE, uint32_t arrayElement = 0);
    /// Storage image (used in `layout`, GENERAL by default).
    void writeStorageImage(uint32_t binding, const Image& image,
                           VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL, uint32_t arrayElement = 0);
    /// Uniform or storage texel buffer (the type the layout declares).
    void writeTexelBuffer(uint32_t binding, VkBufferView view, uint32_t arrayElement = 0);
    /// Combined image sampler or sampled image (the type the layout declares).
    void writeSampledImage(uint32_t binding, VkImageView view, VkSampler sampler,
                           VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                           uint32_t arrayElement = 0);

  private:
    const Device* m_device = nullptr;
    std::vector<DescriptorBinding> m_bindings; ///< copied from the layout
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkDescriptorSet m_set = VK_NULL_HANDLE;

    VkDescriptorType typeOf(uint32_t binding) const;
    /// One descriptor at (binding, arrayElement) from exactly one of `buffer`, `image` and `texels`.
    void write(uint32_t binding, uint32_t arrayElement, const VkDescriptorBufferInfo* buffer,
               const VkDescriptorImageInfo* image, const VkBufferView* texels = nullptr);
    void destroy() noexcept;
};

} // namespace stsv

// 2D images: attachments (color, depth), storage images, readback and upload.
#pragma once

#include "gpu/vulkan.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace stsv {

class Device;

/// Bytes per texel of the formats stsv uses (R8G8B8A8_*, R32*, R16G16B16A16_SFLOAT, D32_SFLOAT,
/// ...); throws UsageError for others.
uint32_t texelSize(VkFormat format);
bool isDepthFormat(VkFormat format);

struct ImageDesc {
    uint32_t width = 0;  ///< pixels
    uint32_t height = 0; ///< pixels
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageUsageFlags usage = 0; ///< TRANSFER_SRC/DST are always added (readback, upload, clears)
};

/// A single-mip, single-layer 2D image with its own memory and a view of the whole image.
/// The image remembers the layout of its last recorded transition (layout()), so passes
/// recorded in order can call transition() without tracking layouts themselves.
/// Row 0 of upload/readback data is image row y = 0 (the top row under the Vulkan viewport).
/// Move-only; must not outlive its Device.
class Image {
  public:
    Image() = default;
    Image(const Device& device, const ImageDesc& desc);
    ~Image();
    Image(Image&& other) noexcept;
    Image& operator=(Image&& other) noexcept;

    VkImage handle() const { return m_image; }
    VkImageView view() const { return m_view; }
    VkFormat format() const { return m_desc.format; }
    VkExtent2D extent() const { return {m_desc.width, m_desc.height}; }
    uint32_t width() const { return m_desc.width; }
    uint32_t height() const { return m_desc.height; }
    VkImageAspectFlags aspect() const;
    VkImageLayout layout() const { return m_layout; }
    std::size_t byteSize() const {
        return std::size_t(m_desc.width) * m_desc.height * texelSize(m_desc.format);
    }

    /// Records a layout transition whose scopes are the typical uses of the old and the new
    /// layout (GENERAL: any use). No-op when the layout already matches, unless GENERAL (then
    /// it still records a full memory dependency). Passes that reuse an image in the same
    /// layout with a hazard (e.g. storage writes then reads) add their own barrier.
    void transition(VkCommandBuffer cmd, VkImageLayout newLayout);
    /// Notes that a barrier recorded elsewhere (gpu/pass_recorder.h) leaves the image in `layout`.
    void assumeLayout(VkImageLayout layout) { m_layout = layout; }

    /// Records a transition to TRANSFER_SRC_OPTIMAL and a copy of byteSize() tightly packed
    /// bytes (rows top to bottom) into `buffer` at `offset` (bytes). For readback inside a frame's
    /// command buffer: end it with hostReadBarrier before reading a mapped buffer.
    void recordCopyToBuffer(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset);

    /// Tightly packed texels, rows top to bottom; waits for the GPU. Leaves the image in
    /// TRANSFER_SRC_OPTIMAL.
    std::vector<std::byte> readback();
    template <class T> std::vector<T> readback() {
        std::vector<std::byte> bytes = readback();
        std::vector<T> values(bytes.size() / sizeof(T));
        std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
        return values;
    }
    /// Uploads byteSize() tightly packed bytes and leaves the image in `finalLayout`.
    void upload(const void* data, std::size_t bytes, VkImageLayout finalLayout);

  private:
    const Device* m_device = nullptr;
    ImageDesc m_desc;
    VkImage m_image = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkImageView m_view = VK_NULL_HANDLE;
    VkImageLayout m_layout = VK_IMAGE_LAYOUT_UNDEFINED;

    void destroy() noexcept;
};

/// Move-only VkSampler (no mipmaps, no anisotropy). Alpha textures are read with texelFetch
/// and the shared texel rule (scene/occlusion_rules_dh.h texelAt), so NEAREST is the usual choice.
class Sampler {
  public:
    Sampler() = default;
    Sampler(const Device& device, VkFilter filter, VkSamplerAddressMode addressMode);
    ~Sampler();
    Sampler(Sampler&& other) noexcept;
    Sampler& operator=(Sampler&& other) noexcept;

    VkSampler handle() const { return m_sampler; }

  private:
    const Device* m_device = nullptr;
    VkSampler m_sampler = VK_NULL_HANDLE;

    void destroy() noexcept;
};

} // namespace stsv

#include "gpu/image.h"

#include "gpu/buffer.h"
#include "gpu/check.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/memory.h"

#include <string>
#include <utility>

namespace stsv {
namespace {

struct LayoutUse {
    VkPipelineStageFlags2 stages;
    VkAccessFlags2 access;
};

/// The stages and accesses an image in `layout` is used with: the source scope of a
/// transition out of it, and the destination scope of a transition into it.
LayoutUse layoutUse(VkImageLayout layout) {
    switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED:
        return {VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT |
                    VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_SHADER_READ_BIT};
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_SHADER_READ_BIT};
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
        return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
    default: // GENERAL and anything else: any use
        return {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
    }
}

} // namespace

uint32_t texelSize(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R8_UNORM:
    case VK_FORMAT_R8_UINT:
        return 1;
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_R16_SFLOAT:
        return 2;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R8G8B8A8_UINT:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SINT:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
        return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_UINT:
    case VK_FORMAT_R32G32_UINT:
    case VK_FORMAT_R32G32_SFLOAT:
        return 8;
    case VK_FORMAT_R32G32B32A32_UINT:
    case VK_FORMAT_R32G32B32A32_SFLOAT:
        return 16;
    default:
        throw UsageError("unsupported image format " + std::to_string(int(format)));
    }
}

bool isDepthFormat(VkFormat format) {
    return format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D16_UNORM ||
           format == VK_FORMAT_D24_UNORM_S8_UINT || format == VK_FORMAT_D32_SFLOAT_S8_UINT ||
           format == VK_FORMAT_X8_D24_UNORM_PACK32;
}

Image::Image(const Device& device, const ImageDesc& desc) : m_device(&device), m_desc(desc) {
    if (desc.width == 0 || desc.height == 0 || desc.width > device.info().maxImageDimension2D ||
        desc.height > device.info().maxImageDimension2D)
        throw UsageError("image size " + std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                         " outside 1.." + std::to_string(device.info().maxImageDimension2D));
    (void)texelSize(desc.format); // rejects formats readback cannot handle
    m_desc.usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    try {
        VkImageCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = desc.format;
        info.extent = {desc.width, desc.height, 1};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = m_desc.usage;
        info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        STSV_VK_CHECK(vkCreateImage(device.handle(), &info, nullptr, &m_image));
        VkMemoryRequirements requirements;
        vkGetImageMemoryRequirements(device.handle(), m_image, &requirements);
        m_memory = allocateMemory(device, requirements, MemoryUsage::DeviceLocal);
        STSV_VK_CHECK(vkBindImageMemory(device.handle(), m_image, m_memory, 0));

        VkImageViewCreateInfo viewInfo{};

        viewInfo.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
        viewInfo.image = m_image;
        viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
        viewInfo.format = desc.format;
        viewInfo.subresourceRange = {aspect(), 0, 1, 0, 1};
        STSV_VK_CHECK(vkCreateImageView(device.handle(), &viewInfo, nullptr, &m_view));
    } catch (...) {
        destroy();
        throw;
    }
}

Image::~Image() {
    destroy();
}

Image::Image(Image&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)), m_desc(other.m_desc),
      m_image(std::exchange(other.m_image, VK_NULL_HANDLE)),
      m_memory(std::exchange(other.m_memory, VK_NULL_HANDLE)),
      m_view(std::exchange(other.m_view, VK_NULL_HANDLE)),
      m_layout(std::exchange(other.m_layout, VK_IMAGE_LAYOUT_UNDEFINED)) {}

Image& Image::operator=(Image&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_desc = other.m_desc;
        m_image = std::exchange(other.m_image, VK_NULL_HANDLE);
        m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
        m_view = std::exchange(other.m_view, VK_NULL_HANDLE);
        m_layout = std::exchange(other.m_layout, VK_IMAGE_LAYOUT_UNDEFINED);
    }
    return *this;
}

void Image::destroy() noexcept {
    if (m_device == nullptr) return;
    if (m_view != VK_NULL_HANDLE) vkDestroyImageView(m_device->handle(), m_view, nullptr);
    if (m_image != VK_NULL_HANDLE) vkDestroyImage(m_device->handle(), m_image, nullptr);
    if (m_memory != VK_NULL_HANDLE) vkFreeMemory(m_device->handle(), m_memory, nullptr);
    m_view = VK_NULL_HANDLE;
    m_image = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
    m_device = nullptr;
}

VkImageAspectFlags Image::aspect() const {
    return isDepthFormat(m_desc.format) ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                                        : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT);
}

void Image::transition(VkCommandBuffer cmd, VkImageLayout newLayout) {
    if (newLayout == m_layout && newLayout != VK_IMAGE_LAYOUT_GENERAL) return;
    const LayoutUse src = layoutUse(m_layout);
    const LayoutUse dst = layoutUse(newLayout);
    VkImageMemoryBarrier2 barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2;
    barrier.srcStageMask = src.stages;
    // Only writes need making available; reads only need the execution dependency.
    barrier.srcAccessMask = src.access & (VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                          VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    barrier.dstStageMask = dst.stages;
    barrier.dstAccessMask = dst.access;
    barrier.oldLayout = m_layout;
    barrier.newLayout = newLayout;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = m_image;
    barrier.subresourceRange = {aspect(), 0, 1, 0, 1};
    VkDependencyInfo dependency{};
    dependency.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO;
    dependency.imageMemoryBarrierCount = 1;
    dependency.pImageMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dependency);
    m_layout = newLayout;
}

void Image::recordCopyToBuffer(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset) {
    transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region{};
    region.bufferOffset = offset;
    region.imageSubresource = {aspect(), 0, 0, 1};
    region.imageExtent = {m_desc.width, m_desc.height, 1};
    vkCmdCopyImageToBuffer(cmd, m_image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &region);
}

std::vector<std::byte> Image::readback() {
    Buffer staging(*m_device, byteSize(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceToHost);
    submitOnce(*m_device, [&](VkCommandBuffer cmd) {
        recordCopyToBuffer(cmd, staging.handle(), 0);
        hostReadBarrier(cmd);
    });
    std::vector<std::byte> bytes(byteSize());
    staging.download(bytes.data(), bytes.size());
    return bytes;
}

void Image::upload(const void* data, std::size_t bytes, VkImageLayout finalLayout) {
    if (bytes != byteSize())
        throw UsageError("image upload of " + std::to_string(bytes) + " bytes, expected " +
                         std::to_string(byteSize()));
    Buffer staging(*m_device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::HostToDevice);
    staging.upload(data, bytes);
    submitOnce(*m_device, [&](VkCommandBuffer cmd) {
        transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy region{};
        region.imageSubresource = {aspect(), 0, 0, 1};
        region.imageExtent = {m_desc.width, m_desc.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.handle(), m_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                               &region);
        transition(cmd, finalLayout);
    });
}

Sampler::Sampler(const Device& device, VkFilter filter, VkSamplerAddressMode addressMode)
    : m_device(&device) {
    VkSamplerCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
    info.magFilter = filter;
    info.minFilter = filter;
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = addressMode;
    info.addressModeV = addressMode;
    info.addressModeW = addressMode;
    info.maxLod = 0.0f;
    info.borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    STSV_VK_CHECK(vkCreateSampler(device.handle(), &info, nullptr, &m_sampler));
}

Sampler::~Sampler() {
    destroy();
}

Sampler::Sampler(Sampler&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)),
      m_sampler(std::exchange(other.m_sampler, VK_NULL_HANDLE)) {}

Sampler& Sampler::operator=(Sampler&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_sampler = std::exchange(other.m_sampler, VK_NULL_HANDLE);
    }
    return *this;
}

void Sampler::destroy() noexcept {
    if (m_device != nullptr && m_sampler != VK_NULL_HANDLE)
        vkDestroySampler(m_device->handle(), m_sampler, nullptr);
    m_sampler = VK_NULL_HANDLE;
    m_device = nullptr;
}

} // namespace stsv

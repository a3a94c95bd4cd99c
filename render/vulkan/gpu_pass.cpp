#include "render/vulkan/gpu_pass.h"

#include "gpu/buffer.h"
#include "gpu/image.h"

namespace stsv {

PassAccesses ClearPass::accesses(std::size_t) const {
    PassAccesses accesses;
    for (Image* image : m_images) accesses.use(*image, ResourceUse::transferWrite());
    for (const Buffer* buffer : m_buffers) accesses.use(*buffer, ResourceUse::transferWrite());
    return accesses;
}

void ClearPass::record(VkCommandBuffer cmd, std::size_t) const {
    const VkClearColorValue zero{};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (const Image* image : m_images)
        vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    for (const Buffer* buffer : m_buffers) vkCmdFillBuffer(cmd, buffer->handle(), 0, VK_WHOLE_SIZE, 0);
}

} // namespace stsv

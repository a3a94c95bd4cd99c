#include "gpu/rendering.h"

#include "core/error.h"
#include "gpu/image.h"

#include <vector>

namespace stsv {

namespace {

void beginRenderingInfo(VkCommandBuffer cmd, VkExtent2D extent,
                        const std::vector<VkRenderingAttachmentInfo>& colorInfos,
                        const VkRenderingAttachmentInfo* depthInfo) {
    VkRenderingInfo info{};
    info.sType = VK_STRUCTURE_TYPE_RENDERING_INFO;
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = uint32_t(colorInfos.size());
    info.pColorAttachments = colorInfos.data();
    info.pDepthAttachment = depthInfo;
    vkCmdBeginRendering(cmd, &info);

    VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

} // namespace

void beginRendering(VkCommandBuffer cmd, std::span<const ColorTarget> colors,
                    std::optional<DepthTarget> depth) {
    VkExtent2D extent{0, 0};
    auto takeExtent = [&](const Image& image) {
        if (extent.width == 0)
            extent = image.extent();
        else if (extent.width != image.width() || extent.height != image.height())
            throw UsageError("render attachments differ in size");
    };
    std::vector<VkRenderingAttachmentInfo> colorInfos;
    for (const ColorTarget& target : colors) {
        if (target.image == nullptr) throw UsageError("null color attachment");
        takeExtent(*target.image);
        target.image->transition(cmd, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo info{};
        info.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
        info.imageView = target.image->view();
        info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        info.loadOp = target.clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
        info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        info.clearValue.color = target.clearValue;
        colorInfos.push_back(info);
    }
    VkRenderingAttachmentInfo depthInfo{};
    depthInfo.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    if (depth) {
        if (depth->image == nullptr) throw UsageError("null depth attachment");
        if (depth->readOnly && depth->clear)
            throw UsageError("a read-only depth attachment cannot be cleared");
        takeExtent(*depth->image);
        const VkImageLayout layout = depth->readOnly ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL
                                                     : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depth->image->transition(cmd, layout);
        depthInfo.imageView = depth->image->view();
        depthInfo.imageLayout = layout;
        depthInfo.loadOp = depth->clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
        depthInfo.storeOp = depth->readOnly ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
        depthInfo.clearValue.depthStencil = {depth->clearDepth, 0};
    }
    if (extent.width == 0) throw UsageError("rendering without attachments");
    beginRenderingInfo(cmd, extent, colorInfos, depth ? &depthInfo : nullptr);
}

void beginRendering(VkCommandBuffer cmd, VkExtent2D extent) {
    if (extent.width == 0 || extent.height == 0) throw UsageError("rendering over an empty area");
    beginRenderingInfo(cmd, extent, {}, nullptr);
}

} // namespace stsv

// Barriers from declared accesses, after Filament's FrameGraph and Falcor's RenderPass::reflect
// but without building a graph (each pass is recorded as it is added): every pass says which
// images and buffers it reads and writes and how; the recorder derives
// the pipeline barriers and image layout transitions between consecutive passes from that, so
// no pass places a barrier by hand. One queue, passes recorded in submission order.
#pragma once

#include "gpu/vulkan.h"

#include <functional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace stsv {

class Buffer;
class GpuTimer;
class Image;

/// How a pass uses one resource: its synchronisation scope and, for images, the layout it needs.
struct ResourceUse {
    VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 access = VK_ACCESS_2_NONE;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED; ///< ignored for buffers

    /// Color attachment, loaded or cleared, written (blending and logic ops read it too).
    static ResourceUse colorAttachment();
    /// Depth attachment with depth writes (the G-buffer).
    static ResourceUse depthAttachment();
    /// Depth test without writes (DEPTH_READ_ONLY_OPTIMAL): the volume passes.
    static ResourceUse depthTest();
    /// Storage image or buffer loads in `stages`.
    static ResourceUse storageRead(VkPipelineStageFlags2 stages);
    /// Sampled-image or texel-buffer reads (texelFetch) in `stages`.
    static ResourceUse sampledRead(VkPipelineStageFlags2 stages);
    /// Storage loads, stores and atomics in `stages`.
    static ResourceUse storageReadWrite(VkPipelineStageFlags2 stages);
    /// vkCmdClearColorImage / vkCmdFillBuffer.
    static ResourceUse transferWrite();
    /// Arguments of an indirect draw or dispatch.
    static ResourceUse indirectRead();
    /// Source of a copy (readback).
    static ResourceUse transferRead();
    /// Host reads of a mapped buffer after the frame's fence.
    static ResourceUse hostRead();

    bool writes() const;
};

/// One declared access: exactly one of `image` and `buffer`.
struct PassAccess {
    Image* image = nullptr;
    const Buffer* buffer = nullptr;
    ResourceUse use;
};

/// The accesses one pass declares. A resource declared twice gets the union of both uses (one
/// layout: UsageError when the two uses need different ones).
class PassAccesses {
  public:
    PassAccesses& use(Image& image, const ResourceUse& use);
    PassAccesses& use(const Buffer& buffer, const ResourceUse& use);
    std::span<const PassAccess> list() const { return m_accesses; }

  private:
    std::vector<PassAccess> m_accesses;
};

/// A dependency from the earlier accesses of one resource to a pass's access of it, with the
/// layout transition when the layouts differ (images only).
struct ResourceBarrier {
    Image* image = nullptr;
    const Buffer* buffer = nullptr;
    VkPipelineStageFlags2 srcStages = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 srcAccess = VK_ACCESS_2_NONE; ///< the writes to make available
    VkPipelineStageFlags2 dstStages = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 dstAccess = VK_ACCESS_2_NONE; ///< the accesses the writes become visible to
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
};

/// The hazard state of every resource seen so far, and the barriers a next pass needs:
///  * a write, or a layout change, waits for the last write and every read since (WAW, WAR)
///    and makes the last write available;
///  * a read waits for the last write and makes it visible, unless an earlier barrier already
///    made it visible to the same stages and accesses (consecutive readers share one barrier);
///  * reads after reads, and a first write to a fresh resource in its layout, need nothing.
/// An image's first layout is the one Image::layout() reports when it is first declared; host
/// reads end a resource's hazards (the next submission is ordered after them on the host).
/// Works on resource identities only (no Vulkan calls): tests drive it without a device.
class AccessTracker {
  public:
    /// The barriers the pass with `accesses` needs before it; records its accesses.
    std::vector<ResourceBarrier> enter(std::span<const PassAccess> accesses);

  private:
    struct VisibleScope {
        VkPipelineStageFlags2 stages;
        VkAccessFlags2 access;
    };
    struct State {
        VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
        VkPipelineStageFlags2 writeStages = VK_PIPELINE_STAGE_2_NONE; ///< last write, transitions since
        VkAccessFlags2 writeAccess = VK_ACCESS_2_NONE;
        VkPipelineStageFlags2 readStages = VK_PIPELINE_STAGE_2_NONE; ///< reads since then
        std::vector<VisibleScope> visible;                           ///< scopes the last write is visible to
    };
    std::unordered_map<const void*, State> m_states;
};

/// Records `barriers` as one vkCmdPipelineBarrier2 (nothing when empty) and notes each image's
/// new layout on the Image, so helpers that transition (beginRendering) find it in place.
void recordBarriers(VkCommandBuffer cmd, std::span<const ResourceBarrier> barriers);

/// Records passes in order: the derived barriers, then the pass inside a GPU timer scope.
class PassRecorder {
  public:
    /// `timer` must outlive the recorder.
    explicit PassRecorder(GpuTimer& timer) : m_timer(&timer) {}

    /// Records the barriers `accesses` need, then `record` in the timer scope `scope` ("" =
    /// untimed).
    void addPass(VkCommandBuffer cmd, const std::string& scope, const PassAccesses& accesses,
                 const std::function<void(VkCommandBuffer)>& record);
    /// Opens the timer scope `scope` around the passes that follow, until endScope (a pass
    /// recorded in several dispatches, each added untimed).
    void beginScope(VkCommandBuffer cmd, const std::string& scope);
    void endScope(VkCommandBuffer cmd);

  private:
    GpuTimer* m_timer;
    AccessTracker m_tracker;
};

} // namespace stsv

#include "gpu/pass_recorder.h"

#include "core/error.h"
#include "gpu/buffer.h"
#include "gpu/image.h"
#include "gpu/timer.h"

#include <algorithm>

namespace stsv {

namespace {

constexpr VkAccessFlags2 WRITE_ACCESS =
    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
    VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;

constexpr VkPipelineStageFlags2 FRAGMENT_TESTS =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;

const void* identityOf(const PassAccess& access) {
    return access.image != nullptr ? static_cast<const void*>(access.image)
                                   : static_cast<const void*>(access.buffer);
}

} // namespace

ResourceUse ResourceUse::colorAttachment() {
    return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
}

ResourceUse ResourceUse::depthAttachment() {
    return {FRAGMENT_TESTS,
            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL};
}

ResourceUse ResourceUse::depthTest() {
    return {FRAGMENT_TESTS, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
            VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
}

ResourceUse ResourceUse::storageRead(VkPipelineStageFlags2 stages) {
    return {stages, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_IMAGE_LAYOUT_GENERAL};
}

ResourceUse ResourceUse::sampledRead(VkPipelineStageFlags2 stages) {
    return {stages, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
}

ResourceUse ResourceUse::storageReadWrite(VkPipelineStageFlags2 stages) {
    return {stages, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
            VK_IMAGE_LAYOUT_GENERAL};
}

ResourceUse ResourceUse::transferWrite() {
    return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
}

ResourceUse ResourceUse::transferRead() {
    return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
}

ResourceUse ResourceUse::indirectRead() {
    return {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
            VK_IMAGE_LAYOUT_UNDEFINED};
}

ResourceUse ResourceUse::hostRead() {
    return {VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED};
}

bool ResourceUse::writes() const {
    return (access & WRITE_ACCESS) != 0;
}

PassAccesses& PassAccesses::use(Image& image, const ResourceUse& use) {
    for (PassAccess& a : m_accesses) {
        if (a.image != &image) continue;
        if (a.use.layout != use.layout) throw UsageError("a pass declares one image in two layouts");
        a.use.stages |= use.stages;
        a.use.access |= use.access;
        return *this;
    }
    m_accesses.push_back({&image, nullptr, use});
    return *this;
}

PassAccesses& PassAccesses::use(const Buffer& buffer, const ResourceUse& use) {
    for (PassAccess& a : m_accesses) {
        if (a.buffer != &buffer) continue;
        a.use.stages |= use.stages;
        a.use.access |= use.access;
        return *this;
    }
    m_accesses.push_back({nullptr, &buffer, {use.stages, use.access, VK_IMAGE_LAYOUT_UNDEFINED}});
    return *this;
}

std::vector<ResourceBarrier> AccessTracker::enter(std::span<const PassAccess> accesses) {
    std::vector<ResourceBarrier> barriers;
    for (const PassAccess& access : accesses) {
        auto [it, fresh] = m_states.try_emplace(identityOf(access));
        State& state = it->second;
        if (fresh && access.image != nullptr) state.layout = access.image->layout();
        const ResourceUse& use = access.use;
        const bool transition = access.image != nullptr && use.layout != state.layout;
        ResourceBarrier barrier{access.image,      access.buffer, VK_PIPELINE_STAGE_2_NONE,
                                state.writeAccess, use.stages,    use.access,
                                state.layout,      state.layout};
        if (use.writes() || transition) {
            // WAW and WAR: after the last write and every read since; the transition (a write
            // itself) happens inside this dependency.
            barrier.srcStages = state.writeStages | state.readStages;
            barrier.newLayout = access.image != nullptr ? use.layout : state.layout;
            if (barrier.srcStages != VK_PIPELINE_STAGE_2_NONE || transition) barriers.push_back(barrier);
            state.layout = barrier.newLayout;
            state.visible.clear();
            if (use.writes()) {
                state.writeStages = use.stages;
                state.writeAccess = use.access & WRITE_ACCESS;
                state.readStages = VK_PIPELINE_STAGE_2_NONE;
            } else {
                // A transition for a read: later readers wait for the transition (done by the
                // time `use.stages` run) and still see the last write, without relying on
                // barrier chaining.
                state.writeStages |= use.stages;
                state.readStages = use.stages;
                state.visible.push_back({use.stages, use.access});
            }
        } else {
            // RAW: the last write made visible to these stages, once.
            const bool visible =
                std::any_of(state.visible.begin(), state.visible.end(), [&](const VisibleScope& v) {
                    return (use.stages & ~v.stages) == 0 && (use.access & ~v.access) == 0;
                });
            if (state.writeStages != VK_PIPELINE_STAGE_2_NONE && !visible) {
                barrier.srcStages = state.writeStages;
                barriers.push_back(barrier);
                state.visible.push_back({use.stages, use.access});
            }
            state.readStages |= use.stages;
        }
        if (use.stages == VK_PIPELINE_STAGE_2_HOST_BIT) state = State{state.layout, {}, {}, {}, {}};
    }
    return barriers;
}

namespace {

/// The stages and accesses of `b` (no queue ownership transfer) into an image or buffer barrier.
template <class VkBarrier> void setDependency(VkBarrier& barrier, const ResourceBarrier& b) {
    barrier.srcStageMask = b.srcStages;
    barrier.srcAccessMask = b.srcAccess;
    barrier.dstStageMask = b.dstStages;
    barrier.dstAccessMask = b.dstAccess;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
}

} // namespace

void recordBarriers(VkCommandBuffer cmd, std::span<const ResourceBarrier> barriers) {
    if (barriers.empty()) return;
    std::vector<VkImageMemoryBarrier2> images;
    std::vector<VkBufferMemoryBarrier2> buffers;
    for (const ResourceBarrier& b : barriers) {
        if (b.image != nullptr) {
            VkImageMemoryBarrier2& barrier = images.emplace_back();
            barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2;
            setDependency(barrier, b);
            barrier.oldLayout = b.oldLayout;
            barrier.newLayout = b.newLayout;
            barrier.image = b.image->handle();
            barrier.subresourceRange = {b.image->aspect(), 0, 1, 0, 1};
            b.image->assumeLayout(b.newLayout);
        } else {
            VkBufferMemoryBarrier2& barrier = buffers.emplace_back();
            barrier.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2;
            setDependency(barrier, b);
            barrier.buffer = b.buffer->handle();
            barrier.offset = 0;
            barrier.size = VK_WHOLE_SIZE;
        }
    }
    VkDependencyInfo dependency{};
    dependency.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO;
    dependency.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
    dependency.pImageMemoryBarriers = images.data();
    dependency.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers.size());
    dependency.pBufferMemoryBarriers = buffers.data();
    vkCmdPipelineBarrier2(cmd, &dependency);
}

void PassRecorder::addPass(VkCommandBuffer cmd, const std::string& scope, const PassAccesses& accesses,
                           const std::function<void(VkCommandBuffer)>& record) {
    recordBarriers(cmd, m_tracker.enter(accesses.list()));
    if (!scope.empty()) m_timer->begin(cmd, scope);
    record(cmd);
    if (!scope.empty()) m_timer->end(cmd);
}

void PassRecorder::beginScope(VkCommandBuffer cmd, const std::string& scope) {
    m_timer->begin(cmd, scope);
}

void PassRecorder::endScope(VkCommandBuffer cmd) {
    m_timer->end(cmd);
}

} // namespace stsv

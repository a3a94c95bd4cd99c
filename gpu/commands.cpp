#include "gpu/commands.h"

#include "gpu/check.h"
#include "gpu/device.h"

#include <cstdint>
#include <utility>

namespace stsv {

CommandBuffer::CommandBuffer(const Device& device) : m_device(&device) {
    try {
        VkCommandPoolCreateInfo poolInfo{};
        poolInfo.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
        poolInfo.flags =
            VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        poolInfo.queueFamilyIndex = device.queueFamily();
        STSV_VK_CHECK(vkCreateCommandPool(device.handle(), &poolInfo, nullptr, &m_pool));
        VkCommandBufferAllocateInfo allocInfo{};
        allocInfo.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
        allocInfo.commandPool = m_pool;
        allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        allocInfo.commandBufferCount = 1;
        STSV_VK_CHECK(vkAllocateCommandBuffers(device.handle(), &allocInfo, &m_buffer));
        VkFenceCreateInfo fenceInfo{};
        fenceInfo.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        STSV_VK_CHECK(vkCreateFence(device.handle(), &fenceInfo, nullptr, &m_fence));
    } catch (...) {
        destroy();
        throw;
    }
}

CommandBuffer::~CommandBuffer() {
    destroy();
}

CommandBuffer::CommandBuffer(CommandBuffer&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)), m_pool(std::exchange(other.m_pool, VK_NULL_HANDLE)),
      m_buffer(std::exchange(other.m_buffer, VK_NULL_HANDLE)),
      m_fence(std::exchange(other.m_fence, VK_NULL_HANDLE)) {}

CommandBuffer& CommandBuffer::operator=(CommandBuffer&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_pool = std::exchange(other.m_pool, VK_NULL_HANDLE);
        m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
        m_fence = std::exchange(other.m_fence, VK_NULL_HANDLE);
    }
    return *this;
}

void CommandBuffer::destroy() noexcept {
    if (m_device == nullptr) return;
    if (m_fence != VK_NULL_HANDLE) vkDestroyFence(m_device->handle(), m_fence, nullptr);
    if (m_pool != VK_NULL_HANDLE) vkDestroyCommandPool(m_device->handle(), m_pool, nullptr);
    m_fence = VK_NULL_HANDLE;
    m_pool = VK_NULL_HANDLE;
    m_buffer = VK_NULL_HANDLE;
    m_device = nullptr;
}

VkCommandBuffer CommandBuffer::begin() {
    STSV_VK_CHECK(vkResetCommandBuffer(m_buffer, 0));
    VkCommandBufferBeginInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    STSV_VK_CHECK(vkBeginCommandBuffer(m_buffer, &info));
    return m_buffer;
}

void CommandBuffer::submitAndWait() {
    STSV_VK_CHECK(vkEndCommandBuffer(m_buffer));
    VkCommandBufferSubmitInfo cmdInfo{};
    cmdInfo.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO;
    cmdInfo.commandBuffer = m_buffer;
    VkSubmitInfo2 submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    STSV_VK_CHECK(vkResetFences(m_device->handle(), 1, &m_fence));
    STSV_VK_CHECK(vkQueueSubmit2(m_device->queue(), 1, &submit, m_fence));
    STSV_VK_CHECK(vkWaitForFences(m_device->handle(), 1, &m_fence, VK_TRUE, UINT64_MAX));
}

void submitOnce(const Device& device, const std::function<void(VkCommandBuffer)>& record) {
    CommandBuffer cmd(device);
    record(cmd.begin());
    cmd.submitAndWait();
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2;
    barrier.srcStageMask = srcStage;
    barrier.srcAccessMask = srcAccess;
    barrier.dstStageMask = dstStage;
    barrier.dstAccessMask = dstAccess;
    VkDependencyInfo dependency{};
    dependency.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO;
    dependency.memoryBarrierCount = 1;
    dependency.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dependency);
}

void hostReadBarrier(VkCommandBuffer cmd) {
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

} // namespace stsv

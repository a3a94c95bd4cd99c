#include "gpu/buffer.h"

#include "gpu/check.h"
#include "gpu/commands.h"
#include "gpu/device.h"

#include <cstring>
#include <string>
#include <utility>

namespace stsv {

Buffer::Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory)
    : m_device(&device), m_size(size) {
    if (size == 0) throw UsageError("cannot create an empty GPU buffer");
    m_usage = usage;
    if (!isHostVisible(memory))
        m_usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    try {
        VkBufferCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
        info.size = size;
        info.usage = m_usage;
        info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        STSV_VK_CHECK(vkCreateBuffer(device.handle(), &info, nullptr, &m_buffer));
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(device.handle(), m_buffer, &requirements);
        m_memory = allocateMemory(device, requirements, memory,
                                  (m_usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0);
        STSV_VK_CHECK(vkBindBufferMemory(device.handle(), m_buffer, m_memory, 0));
        if (isHostVisible(memory))
            STSV_VK_CHECK(vkMapMemory(device.handle(), m_memory, 0, VK_WHOLE_SIZE, 0, &m_mapped));
    } catch (...) {
        destroy();
        throw;
    }
}

VkDeviceAddress Buffer::deviceAddress() const {
    if ((m_usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) == 0)
        throw Error("internal error: the device address of a buffer created without one");
    VkBufferDeviceAddressInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO;
    info.buffer = m_buffer;
    return vkGetBufferDeviceAddress(m_device->handle(), &info);
}

Buffer::~Buffer() {
    destroy();
}

Buffer::Buffer(Buffer&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)),
      m_buffer(std::exchange(other.m_buffer, VK_NULL_HANDLE)),
      m_memory(std::exchange(other.m_memory, VK_NULL_HANDLE)), m_size(std::exchange(other.m_size, 0)),
      m_usage(std::exchange(other.m_usage, 0)), m_mapped(std::exchange(other.m_mapped, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_buffer = std::exchange(other.m_buffer, VK_NULL_HANDLE);
        m_memory = std::exchange(other.m_memory, VK_NULL_HANDLE);
        m_size = std::exchange(other.m_size, 0);
        m_usage = std::exchange(other.m_usage, 0);
        m_mapped = std::exchange(other.m_mapped, nullptr);
    }
    return *this;
}

void Buffer::destroy() noexcept {
    if (m_device == nullptr) return;
    if (m_buffer != VK_NULL_HANDLE) vkDestroyBuffer(m_device->handle(), m_buffer, nullptr);
    if (m_memory != VK_NULL_HANDLE) vkFreeMemory(m_device->handle(), m_memory, nullptr); // unmaps too
    m_buffer = VK_NULL_HANDLE;
    m_memory = VK_NULL_HANDLE;
    m_mapped = nullptr;
    m_device = nullptr;
}

void Buffer::checkRange(VkDeviceSize bytes, VkDeviceSize offset) const {
    if (m_buffer == VK_NULL_HANDLE) throw UsageError("use of an empty (moved-from) GPU buffer");
    if (offset > m_size || bytes > m_size - offset)
        throw UsageError("GPU buffer access of " + std::to_string(bytes) + " bytes at offset " +
                         std::to_string(offset) + " exceeds its size " + std::to_string(m_size));
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    checkRange(bytes, offset);
    if (bytes == 0) return;
    if (m_mapped != nullptr) {
        std::memcpy(static_cast<std::byte*>(m_mapped) + offset, data, bytes);
        return;
    }
    Buffer staging(*m_device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::HostToDevice);
    std::memcpy(staging.mapped(), data, bytes);
    submitOnce(*m_device, [&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, offset, bytes};
        vkCmdCopyBuffer(cmd, staging.handle(), m_buffer, 1, &region);
        // Visible to every later command on the queue (submission order spans batches).
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                      VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
    checkRange(bytes, offset);
    if (bytes == 0) return;
    if (m_mapped != nullptr) {
        std::memcpy(data, static_cast<const std::byte*>(m_mapped) + offset, bytes);
        return;
    }
    Buffer staging(*m_device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceToHost);
    submitOnce(*m_device, [&](VkCommandBuffer cmd) {
        // Earlier GPU writes (any stage) before the copy; the copy's writes to the host.
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(cmd, m_buffer, staging.handle(), 1, &region);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    std::memcpy(data, staging.mapped(), bytes);
}

BufferView::BufferView(const Device& device, const Buffer& buffer, VkFormat format, VkDeviceSize texelBytes)
    : m_device(&device) {
    const VkDeviceSize texels = buffer.size() / texelBytes;
    if (texels > device.limits().maxTexelBufferElements)
        throw UsageError("a texel buffer of " + std::to_string(texels) +
                         " texels exceeds the device's limit of " +
                         std::to_string(device.limits().maxTexelBufferElements));
    VkBufferViewCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO;
    info.buffer = buffer.handle();
    info.format = format;
    info.offset = 0;
    info.range = texels * texelBytes;
    STSV_VK_CHECK(vkCreateBufferView(device.handle(), &info, nullptr, &m_view));
}

BufferView::~BufferView() {
    destroy();
}

BufferView::BufferView(BufferView&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)), m_view(std::exchange(other.m_view, VK_NULL_HANDLE)) {}

BufferView& BufferView::operator=(BufferView&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_view = std::exchange(other.m_view, VK_NULL_HANDLE);
    }
    return *this;
}

void BufferView::destroy() noexcept {
    if (m_device != nullptr && m_view != VK_NULL_HANDLE)
        vkDestroyBufferView(m_device->handle(), m_view, nullptr);
    m_view = VK_NULL_HANDLE;
    m_device = nullptr;
}

} // namespace stsv

// Buffers: storage/uniform/vertex/index data, uploads and readback.
#pragma once

#include "gpu/memory.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <span>
#include <vector>

namespace stsv {

class Device;

/// A VkBuffer with its own memory. Device-local buffers also get TRANSFER_SRC/DST usage so
/// upload() and download() work through a staging buffer; host-visible ones are mapped for
/// their whole life. Move-only; must not outlive its Device.
class Buffer {
  public:
    Buffer() = default;
    /// `size` in bytes, > 0 (UsageError otherwise).
    Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUsage memory);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;

    VkBuffer handle() const { return m_buffer; }
    VkDeviceSize size() const { return m_size; } ///< bytes
    VkBufferUsageFlags usage() const { return m_usage; }
    /// Its address for shaders (a buffer created with VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT).
    VkDeviceAddress deviceAddress() const;
    bool hostVisible() const { return m_mapped != nullptr; }
    void* mapped() const { return m_mapped; } ///< nullptr for device-local buffers

    /// Copies `bytes` bytes into the buffer at `offset`. Device-local: staging copy, submitted
    /// and waited for (do not call while a recorded command buffer using it is pending).
    void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    /// Copies `bytes` bytes from `offset` into `data`; waits for a staging copy if device-local.
    /// The caller makes sure the GPU writes are finished (submitAndWait does).
    void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;

    template <class T> void upload(std::span<const T> values, VkDeviceSize offset = 0) {
        upload(values.data(), values.size_bytes(), offset);
    }
    /// The first `count` elements of type T (all that fit when count is omitted).
    template <class T> std::vector<T> download(std::size_t count = SIZE_MAX) const {
        if (count == SIZE_MAX) count = std::size_t(m_size / sizeof(T));
        std::vector<T> values(count);
        download(values.data(), count * sizeof(T));
        return values;
    }

  private:
    const Device* m_device = nullptr;
    VkBuffer m_buffer = VK_NULL_HANDLE;
    VkDeviceMemory m_memory = VK_NULL_HANDLE;
    VkDeviceSize m_size = 0;
    VkBufferUsageFlags m_usage = 0;
    void* m_mapped = nullptr;

    void checkRange(VkDeviceSize bytes, VkDeviceSize offset) const;
    void destroy() noexcept;
};

/// A typed view of a buffer for texel-buffer descriptors (`uniform usamplerBuffer` read with
/// texelFetch): on lavapipe a texel fetch at a per-lane index is a vector gather, where a
/// storage-buffer load is a loop over the lanes. Move-only; must not outlive the buffer or its
/// Device.
class BufferView {
  public:
    BufferView() = default;
    /// The whole buffer as texels of `format`; UsageError when it holds more texels than the
    /// device's maxTexelBufferElements.
    BufferView(const Device& device, const Buffer& buffer, VkFormat format, VkDeviceSize texelBytes);
    ~BufferView();
    BufferView(BufferView&& other) noexcept;
    BufferView& operator=(BufferView&& other) noexcept;

    VkBufferView handle() const { return m_view; }

  private:
    const Device* m_device = nullptr;
    VkBufferView m_view = VK_NULL_HANDLE;

    void destroy() noexcept;
};

/// A buffer holding `values` (device-local unless `memory` says otherwise).
template <class T>
Buffer createBuffer(const Device& device, std::span<const T> values, VkBufferUsageFlags usage,
                    MemoryUsage memory = MemoryUsage::DeviceLocal) {
    Buffer buffer(device, values.size_bytes(), usage, memory);
    buffer.upload(values);
    return buffer;
}

} // namespace stsv

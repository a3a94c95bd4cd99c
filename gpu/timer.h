// GPU timestamps: named scopes in a command buffer → milliseconds (per-pass timings).
#pragma once

#include "gpu/buffer.h"

#include "gpu/vulkan.h"

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

class Device;

struct GpuTiming {
    std::string name;
    double milliseconds = 0.0; ///< GPU time between the scope's begin and end timestamps
};

/// Usage per frame: reset(cmd) first, then begin(cmd, "pass") … end(cmd) around each pass
/// (scopes may nest), submit and wait, then results(). Move-only.
/// begin/end must be recorded outside dynamic rendering (between passes, not inside one).
/// On CPU devices (lavapipe) each timestamp is followed by a waiting query copy so that a
/// scope measures its own pass: without it lavapipe's timestamps run ahead of the worker
/// threads (a compute dispatch after a draw read ~0 ms). The waits serialise passes there,
/// which the per-pass numbers then reflect.
class GpuTimer {
  public:
    GpuTimer() = default;
    /// Throws UsageError when the device has no timestamps on its queue.
    explicit GpuTimer(const Device& device, uint32_t maxScopes = 64);
    ~GpuTimer();
    GpuTimer(GpuTimer&& other) noexcept;
    GpuTimer& operator=(GpuTimer&& other) noexcept;

    void reset(VkCommandBuffer cmd);
    void begin(VkCommandBuffer cmd, std::string name);
    void end(VkCommandBuffer cmd);
    /// Scopes in begin() order. Blocks until the timestamps are available.
    std::vector<GpuTiming> results() const;
    /// The scopes a frame may open.
    uint32_t maxScopes() const { return m_maxScopes; }

  private:
    const Device* m_device = nullptr;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint32_t m_maxScopes = 0;
    struct Scope {
        std::string name;
        uint32_t beginQuery = 0;
        bool ended = false;
    };
    std::vector<Scope> m_scopes;
    std::vector<std::size_t> m_open; ///< indices into m_scopes of scopes not yet ended
    uint32_t m_nextQuery = 0;
    Buffer m_fence; ///< CPU devices only: target of the waiting query copies (see writeTimestamp)

    void writeTimestamp(VkCommandBuffer cmd, uint32_t query);

    void destroy() noexcept;
};

} // namespace stsv

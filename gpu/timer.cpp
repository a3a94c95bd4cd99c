#include "gpu/timer.h"

#include "gpu/check.h"
#include "gpu/device.h"

#include <utility>

namespace stsv {

GpuTimer::GpuTimer(const Device& device, uint32_t maxScopes) : m_device(&device), m_maxScopes(maxScopes) {
    if (!device.info().timestamps) throw UsageError(device.info().name + " has no GPU timestamps");
    if (maxScopes == 0) throw UsageError("GpuTimer needs at least one scope");
    VkQueryPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2 * maxScopes;
    STSV_VK_CHECK(vkCreateQueryPool(device.handle(), &info, nullptr, &m_pool));
    if (device.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU)
        m_fence = Buffer(device, VkDeviceSize(2) * maxScopes * sizeof(uint64_t),
                         VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceLocal);
}

void GpuTimer::writeTimestamp(VkCommandBuffer cmd, uint32_t query) {
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, m_pool, query);
    if (m_fence.handle() == VK_NULL_HANDLE) return;
    // lavapipe (Mesa 22.3) runs rasterisation on worker threads behind the command stream and
    // takes a timestamp when the workers reach it, so without a wait a scope measures only
    // part of its pass (and compute, which runs on other threads, not at all). Copying the
    // result with WAIT_BIT makes the command stream wait until the timestamp exists, so each
    // scope covers exactly its own commands. Real GPUs do not need (or get) this.
    vkCmdCopyQueryPoolResults(cmd, m_pool, query, 1, m_fence.handle(), query * sizeof(uint64_t),
                              sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
}

GpuTimer::~GpuTimer() {
    destroy();
}

GpuTimer::GpuTimer(GpuTimer&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)), m_pool(std::exchange(other.m_pool, VK_NULL_HANDLE)),
      m_maxScopes(other.m_maxScopes), m_scopes(std::move(other.m_scopes)), m_open(std::move(other.m_open)),
      m_nextQuery(other.m_nextQuery), m_fence(std::move(other.m_fence)) {}

GpuTimer& GpuTimer::operator=(GpuTimer&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_pool = std::exchange(other.m_pool, VK_NULL_HANDLE);
        m_maxScopes = other.m_maxScopes;
        m_scopes = std::move(other.m_scopes);
        m_open = std::move(other.m_open);
        m_nextQuery = other.m_nextQuery;
        m_fence = std::move(other.m_fence);
    }
    return *this;
}

void GpuTimer::destroy() noexcept {
    if (m_device != nullptr && m_pool != VK_NULL_HANDLE)
        vkDestroyQueryPool(m_device->handle(), m_pool, nullptr);
    m_pool = VK_NULL_HANDLE;
    m_device = nullptr;
}

void GpuTimer::reset(VkCommandBuffer cmd) {
    vkCmdResetQueryPool(cmd, m_pool, 0, 2 * m_maxScopes);
    m_scopes.clear();
    m_open.clear();
    m_nextQuery = 0;
}

void GpuTimer::begin(VkCommandBuffer cmd, std::string name) {
    if (m_scopes.size() >= m_maxScopes)
        throw UsageError("GpuTimer: more than " + std::to_string(m_maxScopes) + " scopes in one frame");
    // The begin stamp waits for everything before it (ALL_COMMANDS), so the scope measures
    // the commands between begin and end, not overlap with earlier work.
    writeTimestamp(cmd, m_nextQuery);
    m_scopes.push_back({std::move(name), m_nextQuery, false});
    m_open.push_back(m_scopes.size() - 1);
    m_nextQuery += 2;
}

void GpuTimer::end(VkCommandBuffer cmd) {
    if (m_open.empty()) throw UsageError("GpuTimer::end without begin");
    Scope& scope = m_scopes[m_open.back()];
    m_open.pop_back();
    writeTimestamp(cmd, scope.beginQuery + 1);
    scope.ended = true;
}

std::vector<GpuTiming> GpuTimer::results() const {
    std::vector<GpuTiming> timings;
    if (m_nextQuery == 0) return timings;
    if (!m_open.empty()) throw UsageError("GpuTimer: scope '" + m_scopes[m_open.back()].name + "' not ended");
    std::vector<uint64_t> ticks(m_nextQuery);
    STSV_VK_CHECK(vkGetQueryPoolResults(m_device->handle(), m_pool, 0, m_nextQuery,
                                        ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const double msPerTick = double(m_device->info().timestampPeriod) * 1e-6;
    for (const Scope& scope : m_scopes) {
        const uint64_t t0 = ticks[scope.beginQuery];
        const uint64_t t1 = ticks[scope.beginQuery + 1];
        // Ticks are monotonic on one queue; a wrapped counter (valid bits < 64) reads as 0.
        timings.push_back({scope.name, t1 >= t0 ? double(t1 - t0) * msPerTick : 0.0});
    }
    return timings;
}

} // namespace stsv

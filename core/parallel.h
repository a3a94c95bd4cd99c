// CPU dispatch shaped like a GPU dispatch (pbrt-v4's ParallelFor): the CPU mirror calls the
// same per-item function a shader's main() calls, over all items, on every core.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace stsv {

/// Number of worker threads used by parallelFor (at least 1).
inline unsigned workerCount() {
    return std::max(1u, std::thread::hardware_concurrency());
}

/// Calls body(begin, end) over [0, count) in chunks of `grain` items, on all cores.
/// The first exception thrown by a chunk is rethrown after every worker stopped.
inline void parallelForChunks(std::size_t count, std::size_t grain,
                              const std::function<void(std::size_t, std::size_t)>& body) {
    grain = std::max<std::size_t>(1, grain);
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::mutex errorMutex;
    auto worker = [&] {
        for (;;) {
            const std::size_t begin = next.fetch_add(grain);
            if (begin >= count) return;
            try {
                body(begin, std::min(count, begin + grain));
            } catch (...) {
                std::lock_guard lock(errorMutex);
                if (!error) error = std::current_exception();
                next = count;
                return;
            }
        }
    };
    const auto threads =
        static_cast<unsigned>(std::min<std::size_t>(workerCount(), (count + grain - 1) / grain));
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

/// Calls body(i) for every i in [0, count).
inline void parallelFor(std::size_t count, const std::function<void(std::size_t)>& body,
                        std::size_t grain = 64) {
    parallelForChunks(count, grain, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) body(i);
    });
}

} // namespace stsv

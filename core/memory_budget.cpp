#include "core/memory_budget.h"

#include "core/error.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace stsv {

namespace {
std::atomic<std::uint64_t> g_limit{0};
constexpr double GIB = double(1ull << 30);
} // namespace

std::uint64_t physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long pageSize = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || pageSize <= 0) return 0;
    return std::uint64_t(pages) * std::uint64_t(pageSize);
}

std::uint64_t memoryLimitBytes() {
    const std::uint64_t set = g_limit.load();
    if (set > 0) return set;
    const std::uint64_t physical = physicalMemoryBytes();
    // Outputs, the driver and the program itself come on top of what is estimated: half.
    return physical > 0 ? physical / 2 : (std::uint64_t(8) << 30);
}

void setMemoryLimit(std::uint64_t bytes) {
    g_limit.store(bytes);
}

std::string formatBytes(double bytes) {
    char text[64];
    if (bytes >= GIB)
        std::snprintf(text, sizeof text, "%.1f GiB", bytes / GIB);
    else if (bytes >= double(1 << 20))
        std::snprintf(text, sizeof text, "%.1f MiB", bytes / double(1 << 20));
    else
        std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
    return text;
}

std::string describeMemoryLimit() {
    if (g_limit.load() > 0) return formatBytes(double(g_limit.load())) + " (--max-memory)";
    const std::uint64_t physical = physicalMemoryBytes();
    if (physical == 0)
        return formatBytes(double(memoryLimitBytes())) + " (the default; raise it with --max-memory)";
    return formatBytes(double(memoryLimitBytes())) + ", half of this machine's " +
           formatBytes(double(physical)) + " (raise it with --max-memory)";
}

std::uint64_t parseMemorySize(const std::string& text) {
    std::size_t used = 0;
    double value = 0.0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (char& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
    double scale = 0.0;
    if (unit.empty() || unit == "B")
        scale = 1.0;
    else if (unit == "K" || unit == "KB" || unit == "KIB")
        scale = 1024.0;
    else if (unit == "M" || unit == "MB" || unit == "MIB")
        scale = 1024.0 * 1024.0;
    else if (unit == "G" || unit == "GB" || unit == "GIB")
        scale = GIB;
    else if (unit == "T" || unit == "TB" || unit == "TIB")
        scale = GIB * 1024.0;
    if (used == 0 || scale == 0.0 || !std::isfinite(value) || value <= 0.0 || value * scale > 1e18)
        throw UsageError("--max-memory '" + text + "' is not a size such as 8G, 512M or 2.5GiB");
    return std::uint64_t(value * scale);
}

void checkMemory(const std::string& what, double bytes, const std::string& advice) {
    if (!(bytes <= double(memoryLimitBytes())))
        throw UsageError(what + " needs about " + formatBytes(bytes) + ", above the memory limit of " +
                         describeMemoryLimit() + (advice.empty() ? "" : "; " + advice));
}

} // namespace stsv

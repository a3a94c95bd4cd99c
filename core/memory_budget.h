// The memory stsv lets itself hold. Scenes, textures and frames are estimated before they are
// allocated and refused, with the part that is too large named, when the estimate is above the
// limit: half of the machine's physical memory unless --max-memory says otherwise.
#pragma once

#include <cstdint>
#include <string>

namespace stsv {

/// Bytes of physical memory of this machine (0 when the system does not say).
std::uint64_t physicalMemoryBytes();

/// The limit in force: the value of setMemoryLimit, else half of physicalMemoryBytes().
std::uint64_t memoryLimitBytes();
/// Sets the limit for the whole process (the CLI's --max-memory); 0 restores the default.
void setMemoryLimit(std::uint64_t bytes);
/// One line naming the limit and where it comes from ("12.0 GiB, half of this machine's 24.0 GiB").
std::string describeMemoryLimit();

/// Parses "8G", "512M", "2.5GiB", "1000000" (bytes); UsageError on anything else.
std::uint64_t parseMemorySize(const std::string& text);

/// "1.5 GiB", "20.3 MiB": a byte count to read at a glance.
std::string formatBytes(double bytes);

/// UsageError when `bytes` is above the limit: "<what> needs about X, above the memory limit of
/// Y (...); <advice>". `what` names the part ("texture chain.png of 20000x20000 texels").
void checkMemory(const std::string& what, double bytes, const std::string& advice = {});

} // namespace stsv

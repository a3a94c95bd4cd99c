// Files as inputs and outputs: what kind of thing a path names, and writes that are checked to
// the end (a full disk or a closed pipe is an error, not a silent success).
#pragma once

#include <cstddef>
#include <string>

namespace stsv {

/// Empty when `path` names a regular file; otherwise why it cannot be read as one: "does not
/// exist", "is a directory, not a file", "is a device, pipe or socket, not a regular file".
std::string notAFileReason(const std::string& path);

/// The extension of `path` in lower case, with the dot (".png"); empty when it has none.
std::string lowerExtension(const std::string& path);

/// Reads a whole regular file; InputError naming it when it is missing, not a regular file,
/// unreadable, or larger than `maxBytes`.
std::string readFileBytes(const std::string& path, const char* what, std::size_t maxBytes);

/// Writes `size` bytes to `path`, replacing it; Error naming the file and the system's reason
/// when opening, writing, flushing or closing fails (ENOSPC on /dev/full is caught at the flush).
void writeFileBytes(const std::string& path, const void* data, std::size_t size);

} // namespace stsv

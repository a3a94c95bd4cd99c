// Files as inputs and outputs: what kind of thing a path names, and writes that are checked to
// the end (a full disk or a closed pipe is an error, not a silent success).
#pragma once

#include <cstddef>
#include <string>

namespace stsv {

/// Empty when `path` names a regular file; otherwise why it cannot be read as one: "does not
/// exist", "is a directory, not a file", "is a device, pipe or socket, not a regular file".
std::string notAFileReason(const std::string& path);

/// Empty when `path` can be written as an output: it does not exist yet, or names a regular file
/// (through symbolic links). Otherwise why not: "is a directory, not a file", or "is a device,
/// pipe or socket, not a regular file" (a FIFO without a reader would block the write forever, a
/// device would take the bytes somewhere no file is).
std::string notAnOutputReason(const std::string& path);

/// The extension of `path` in lower case, with the dot (".png"); empty when it has none.
std::string lowerExtension(const std::string& path);

/// Reads a whole regular file; InputError naming it when it is missing, not a regular file,
/// unreadable, or larger than `maxBytes`.
std::string readFileBytes(const std::string& path, const char* what, std::size_t maxBytes);

/// Writes `size` bytes to `path`, replacing it; Error naming the file and the system's reason
/// when it is not a regular file (notAnOutputReason, checked again on the opened file, so a pipe
/// made after a command's checks cannot block it either), or when opening, writing, flushing or
/// closing fails (a full disk, a file size limit). A write that fails part way leaves no partial
/// file: the file is removed (emptied instead where `path` is a symbolic link to it).
void writeFileBytes(const std::string& path, const void* data, std::size_t size);

} // namespace stsv

#include "core/files.h"

#include "core/error.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace stsv {

namespace fs = std::filesystem;

std::string notAFileReason(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status)) return "does not exist";
    if (fs::is_directory(status)) return "is a directory, not a file";
    if (!fs::is_regular_file(status)) return "is a device, pipe or socket, not a regular file";
    return {};
}

std::string notAnOutputReason(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status) || fs::is_regular_file(status)) return {};
    if (fs::is_directory(status)) return "is a directory, not a file";
    return "is a device, pipe or socket, not a regular file";
}

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string readFileBytes(const std::string& path, const char* what, std::size_t maxBytes) {
    if (const std::string reason = notAFileReason(path); !reason.empty())
        throw InputError(path, std::string("cannot open ") + what + ": " + reason);
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (!ec && size > maxBytes)
        throw InputError(path, std::string(what) + " of " + std::to_string(size) +
                                   " bytes is larger than the " + std::to_string(maxBytes) +
                                   " bytes accepted");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, std::string("cannot open ") + what + " (unreadable)");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(path, std::string("cannot read ") + what);
    return text.str();
}

void writeFileBytes(const std::string& path, const void* data, std::size_t size) {
    if (const std::string reason = notAnOutputReason(path); !reason.empty())
        throw Error(path + ": cannot write: " + reason);
    // Opened without blocking (a FIFO made since the check, without a reader, fails at once with
    // ENXIO instead of waiting for one), not truncated before the opened file is known to be a
    // regular one. O_EXCL first, to know whether the file is this write's own.
    const int flags = O_WRONLY | O_NONBLOCK | O_CLOEXEC;
    int fd = ::open(path.c_str(), flags | O_CREAT | O_EXCL, 0666);
    const bool created = fd >= 0;
    if (!created && errno == EEXIST) fd = ::open(path.c_str(), flags | O_CREAT, 0666);
    if (fd < 0) {
        const int error = errno;
        if (error == ENXIO)
            throw Error(path + ": cannot write: is a pipe without a reader, not a regular file");
        throw Error(path + ": cannot open for writing (" + std::strerror(error) + ")");
    }
    struct stat opened {};
    if (::fstat(fd, &opened) != 0 || !S_ISREG(opened.st_mode)) {
        ::close(fd);
        throw Error(path + ": cannot write: is a device, pipe or socket, not a regular file");
    }
    // A write that fails part way leaves no partial file behind: once closed, the file is removed
    // where its name is the file itself (this write's own, or an old one already truncated), and
    // emptied where the name is a link to it (the link is the user's).
    std::FILE* file = nullptr;
    auto fail = [&](const std::string& what) {
        const int error = errno;
        if (file != nullptr)
            std::fclose(file);
        else if (fd >= 0)
            ::close(fd);
        struct stat named {};
        if (created || (::lstat(path.c_str(), &named) == 0 && named.st_dev == opened.st_dev &&
                        named.st_ino == opened.st_ino))
            ::unlink(path.c_str());
        else
            (void)::truncate(path.c_str(), 0);
        return Error(path + ": " + what + " (" + std::strerror(error) + ")");
    };
    if (::ftruncate(fd, 0) != 0 || ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0)
        throw fail("cannot open for writing");
    file = ::fdopen(fd, "wb");
    if (file == nullptr) throw fail("cannot open for writing");
    if (size > 0 && std::fwrite(data, 1, size, file) != size) throw fail("write failed");
    if (std::fflush(file) != 0) throw fail("write failed");
    const int closed = std::fclose(file);
    file = nullptr;
    if (closed != 0) {
        fd = -1; // closed, though it failed
        throw fail("write failed");
    }
}

} // namespace stsv

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
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "wb"), std::fclose);
    if (!file) throw Error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
    if (size > 0 && std::fwrite(data, 1, size, file.get()) != size)
        throw Error(path + ": write failed (" + std::strerror(errno) + ")");
    if (std::fflush(file.get()) != 0) throw Error(path + ": write failed (" + std::strerror(errno) + ")");
    if (std::fclose(file.release()) != 0) throw Error(path + ": write failed (" + std::strerror(errno) + ")");
}

} // namespace stsv

// Outputs are regular files: a FIFO, a device or a directory behind an output's name is refused
// by the check every command runs first and again by the write itself, which never blocks on a
// FIFO made in between.
#include "core/error.h"
#include "core/files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace stsv {
namespace {

namespace fs = std::filesystem;

/// A fresh directory under the system temp dir, removed at the end of the test.
class TempDir {
  public:
    TempDir() : m_path(fs::temp_directory_path() / ("stsv_files_" + std::to_string(::getpid()))) {
        fs::remove_all(m_path);
        fs::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (m_path / name).string(); }

  private:
    fs::path m_path;
};

TEST(Files, AnOutputIsANewOrARegularFile) {
    TempDir dir;
    EXPECT_EQ(notAnOutputReason(dir.file("new.png")), "");
    std::ofstream(dir.file("old.png")) << "x";
    EXPECT_EQ(notAnOutputReason(dir.file("old.png")), "");
    fs::create_symlink(dir.file("old.png"), dir.file("link.png"));
    EXPECT_EQ(notAnOutputReason(dir.file("link.png")), "") << "a link to a regular file is one";
    EXPECT_EQ(notAnOutputReason(dir.file("")), "is a directory, not a file");
    ASSERT_EQ(::mkfifo(dir.file("fifo").c_str(), 0600), 0);
    EXPECT_EQ(notAnOutputReason(dir.file("fifo")), "is a device, pipe or socket, not a regular file");
    EXPECT_EQ(notAnOutputReason("/dev/null"), "is a device, pipe or socket, not a regular file");
}

// A FIFO (here with a reader, so that the old fopen would not block but write into it) and a
// device are refused by the write itself, with nothing written.
TEST(Files, WriteFileBytesRefusesFifosAndDevices) {
    TempDir dir;
    ASSERT_EQ(::mkfifo(dir.file("out.png").c_str(), 0600), 0);
    const int reader = ::open(dir.file("out.png").c_str(), O_RDONLY | O_NONBLOCK);
    ASSERT_GE(reader, 0);
    try {
        writeFileBytes(dir.file("out.png"), "png", 3);
        ADD_FAILURE() << "wrote into a FIFO";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find("out.png: cannot write: is a device, pipe or socket"), std::string::npos)
            << e.message();
    }
    char buffer[8];
    EXPECT_LE(::read(reader, buffer, sizeof buffer), 0) << "bytes reached the FIFO";
    ::close(reader);
    EXPECT_THROW(writeFileBytes("/dev/null", "x", 1), Error);
    // A regular file is written, and a shorter write replaces a longer file whole.
    writeFileBytes(dir.file("a.txt"), "longer text", 11);
    writeFileBytes(dir.file("a.txt"), "short", 5);
    std::ifstream in(dir.file("a.txt"));
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), "short");
}

} // namespace
} // namespace stsv
